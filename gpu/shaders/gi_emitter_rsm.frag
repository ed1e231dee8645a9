// Reflective shadow map of an area emitter's point y (gpu/gi_raster.hpp, gi_emitter_rsm): one
// cube face of N x N texels in a tile of the atlas (its lower-left corner at `tile_origin`).
// Per texel: the surface point x its centre ray meets (gi_pixel_point.glsl, pasted before this
// file, with `origin` as the eye), the normal turned towards y and the flux it reflects of the
// light y sends into the texel: albedo L_e (A / K) c(n_e . w) Omega, c = max(0, .) for a
// one-sided emitter, |.| otherwise, Omega = (2/N)^2 / (1 + u^2 + v^2)^(3/2).
in vec3 v_position;
flat in vec3 v_normal;
flat in vec3 v_albedo;
flat in vec4 v_emission;
flat in vec3 v_anchor;
uniform vec3 origin;         // y, relative to the bounding-box centre
uniform vec3 emitter_normal;  // unit
uniform int one_sided;
uniform vec3 point_power;     // L_e A / K per channel
uniform vec3 tile_origin;     // the tile's lower-left corner in the atlas [texels] (z unused)
uniform float face_size;      // N
uniform vec3 face_f;          // the face's forward, right and up axes
uniform vec3 face_r;
uniform vec3 face_u;
layout(location = 0) out vec4 r_position;
layout(location = 1) out vec4 r_normal;
layout(location = 2) out vec4 r_flux;
void main() {
  float len = length(v_normal);
  vec3 n = len > 0.0 ? v_normal / len : vec3(0.0, 0.0, 1.0);
  vec3 x = gi_pixel_point(origin, v_position, n, v_anchor);
  if (dot(n, origin - x) < 0.0) n = -n;
  vec2 uv = 2.0 * (gl_FragCoord.xy - tile_origin.xy) / face_size - 1.0;
  vec3 w = normalize(face_f + uv.x * face_r + uv.y * face_u);
  float c = dot(emitter_normal, w);
  c = one_sided != 0 ? max(c, 0.0) : abs(c);
  float q = 1.0 + dot(uv, uv);
  float omega = (4.0 / (face_size * face_size)) / (q * sqrt(q));
  r_position = vec4(x, 1.0);
  r_normal = vec4(n, 0.0);
  r_flux = vec4(v_albedo * point_power * (c * omega), 0.0);
}
