// The LPV applied to the G-buffer of the GPU-resident frame (gpu/gi_raster.hpp, GiLpvFrame),
// pasted after gi_lpv_decl.glsl and the shared blocks of radiosity.glsl.hpp and lpv.glsl.hpp:
// per G-buffer texel that sees a surface (position w = 1; positions relative to the mesh's
// bounding-box centre) the direct irradiance E_sun f + E_emitters + E_sky (f: the normal
// target's w) and the shared gi_lpv_receiver_irradiance:
//   L = L_e + a / pi max(0, E_direct + E_lpv),
// written as RGBA (alpha 1) at row height - 1 - y (row 0 at the top); elsewhere 0.
layout(local_size_x = 8, local_size_y = 8) in;
uniform sampler2D g_position;
uniform sampler2D g_normal;
uniform sampler2D g_albedo;
uniform sampler2D g_emission;
uniform sampler2D g_emitter;
uniform sampler2D g_sky;
uniform int width;
uniform int height;
uniform vec3 sun_irradiance;
uniform vec3 lpv_lo;
uniform float lpv_h;
uniform int lpv_nx;
uniform int lpv_ny;
uniform int lpv_nz;
layout(std430, binding = 5) writeonly buffer Radiance { float radiance[]; };
layout(std430, binding = 6) readonly buffer Lpv { float lpv[]; };

vec4 gi_lpv_fetch(ivec3 s, int ch) {
  int o = ((s.z * lpv_ny + s.y) * lpv_nx + s.x) * 12 + ch * 4;
  return vec4(lpv[o], lpv[o + 1], lpv[o + 2], lpv[o + 3]);
}
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f) { return 1.0; }
float gi_lpv_fetch_corner(int c, int q) { return 0.0; }

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (px.x >= width || px.y >= height) return;
  int o = ((height - 1 - px.y) * width + px.x) * 4;
  vec4 pos = texelFetch(g_position, px, 0);
  if (pos.w == 0.0) {
    radiance[o] = 0.0;
    radiance[o + 1] = 0.0;
    radiance[o + 2] = 0.0;
    radiance[o + 3] = 0.0;
    return;
  }
  vec4 nf = texelFetch(g_normal, px, 0);
  vec3 a = texelFetch(g_albedo, px, 0).rgb;
  vec3 le = texelFetch(g_emission, px, 0).rgb;
  vec3 ed = sun_irradiance * nf.w + texelFetch(g_emitter, px, 0).rgb + texelFetch(g_sky, px, 0).rgb;
  vec3 E = gi_lpv_receiver_irradiance(pos.xyz, nf.xyz, lpv_lo, lpv_h, ivec3(lpv_nx, lpv_ny, lpv_nz));
  vec3 L = le + a * 0.31830988618379067 * max(ed + E, vec3(0.0));
  radiance[o] = L.x;
  radiance[o + 1] = L.y;
  radiance[o + 2] = L.z;
  radiance[o + 3] = 1.0;
}
