// The LPV applied to the G-buffer of the GPU-resident frame (gpu/gi_raster.hpp, GiLpvFrame),
// pasted after gi_lpv_decl.glsl and the shared blocks of radiosity.glsl.hpp and lpv.glsl.hpp:
// per G-buffer texel that sees a surface (position w = 1; positions relative to the mesh's
// bounding-box centre) the direct irradiance E_sun f + E_emitters + E_sky (f: the normal
// target's w) and the shared gi_lpv_receiver_irradiance:
//   L = L_e + a / pi max(0, E_direct + E_lpv),
// written as RGBA (alpha 1) at row height - 1 - y (row 0 at the top); elsewhere 0.
// cascade != 0: a 2-level cascade (GiLpvCascade): `lpv` is the coarse outer grid, `lpv_inner`
// the coarse inner grid (the same lattice), `lpv_fine` the fine grid (fine_grid_lo, fine_h,
// fine_n*); E_lpv = gi_lpv_cascade_blend(E_outer, E_fine, E_inner, w), w the shared
// gi_lpv_cascade_weight of the fine box [fine_lo, fine_hi] in the coarse grid [lpv_lo, lpv_hi].
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
uniform int cascade;
uniform vec3 lpv_hi;
uniform vec3 fine_lo;
uniform vec3 fine_hi;
uniform vec3 fine_grid_lo;
uniform float fine_h;
uniform int fine_nx;
uniform int fine_ny;
uniform int fine_nz;
layout(std430, binding = 5) writeonly buffer Radiance { float radiance[]; };
layout(std430, binding = 6) readonly buffer Lpv { float lpv[]; };
layout(std430, binding = 7) readonly buffer LpvInner { float lpv_inner[]; };
layout(std430, binding = 8) readonly buffer LpvFine { float lpv_fine[]; };

// The grid gi_lpv_fetch reads: 0 lpv, 1 lpv_inner, 2 lpv_fine (level_nx, level_ny its cells).
int level = 0;
int level_nx = 1;
int level_ny = 1;

vec4 gi_lpv_fetch(ivec3 s, int ch) {
  int o = ((s.z * level_ny + s.y) * level_nx + s.x) * 12 + ch * 4;
  if (level == 1) return vec4(lpv_inner[o], lpv_inner[o + 1], lpv_inner[o + 2], lpv_inner[o + 3]);
  if (level == 2) return vec4(lpv_fine[o], lpv_fine[o + 1], lpv_fine[o + 2], lpv_fine[o + 3]);
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
  level = 0;
  level_nx = lpv_nx;
  level_ny = lpv_ny;
  vec3 E = gi_lpv_receiver_irradiance(pos.xyz, nf.xyz, lpv_lo, lpv_h, ivec3(lpv_nx, lpv_ny, lpv_nz));
  if (cascade != 0) {
    float w = gi_lpv_cascade_weight(pos.xyz, fine_lo, fine_hi, lpv_lo, lpv_hi, lpv_h);
    vec3 e_fine = vec3(0.0);
    vec3 e_inner = vec3(0.0);
    if (w > 0.0) {
      level = 2;
      level_nx = fine_nx;
      level_ny = fine_ny;
      e_fine = gi_lpv_receiver_irradiance(pos.xyz, nf.xyz, fine_grid_lo, fine_h, ivec3(fine_nx, fine_ny, fine_nz));
    }
    if (w < 1.0) {
      level = 1;
      level_nx = lpv_nx;
      level_ny = lpv_ny;
      e_inner = gi_lpv_receiver_irradiance(pos.xyz, nf.xyz, lpv_lo, lpv_h, ivec3(lpv_nx, lpv_ny, lpv_nz));
    }
    E = gi_lpv_cascade_blend(E, e_fine, e_inner, w);
  }
  vec3 L = le + a * 0.31830988618379067 * max(ed + E, vec3(0.0));
  radiance[o] = L.x;
  radiance[o + 1] = L.y;
  radiance[o + 2] = L.z;
  radiance[o + 3] = 1.0;
}
