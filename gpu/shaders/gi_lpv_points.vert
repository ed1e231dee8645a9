// Injection into a light propagation volume by points (the GPU-resident frame of
// gpu/gi_raster.hpp, GiLpvFrame; Kaplanyan & Dachsbacher 2010): one point per item, drawn into
// an atlas of cells (column i, row k ny + j) with additive blending; pasted after
// gi_lpv_decl.glsl and the shared blocks of radiosity.glsl.hpp and lpv.glsl.hpp.
//   mode 0: the reflective shadow map's texel gl_VertexID (position w = 1 where a surface is;
//           normal towards the sun; flux): a VPL at p + vpl_shift n (h/2; in a cascade half the
//           fine cell edge), in cell gi_lpv_cell_of of it, Phi gi_lpv_lobe(n);
//   mode 1: a given VPL (9 floats: position already moved vpl_shift along n, n, flux), the same;
//   in modes 0 and 1 of a cascade's level (box_mode 1: only VPLs inside the fine box
//           [box_lo, box_hi], by the shared gi_lpv_in_box; 2: only those outside it) the VPL is
//           moved a further level_shift along n (the coarse level's half-cell shift) before its
//           cell is found;
//   mode 2: a geometry-volume surfel (4 floats: n, A_s / h^2; its corner index in `corner_index`) into the
//           corner atlas (column i, row k (ny + 1) + j; lpv_nx.. are then the corners' counts),
//           coefficients gi_lpv_surfel 0..8 in targets 0, 1, 2.x.
// Points whose texel sees nothing are moved outside the clip volume.
uniform int mode;
uniform sampler2D rsm_position;
uniform sampler2D rsm_normal;
uniform sampler2D rsm_flux;
uniform int rsm_width;
layout(std430, binding = 0) readonly buffer Items { float item[]; };
layout(std430, binding = 1) readonly buffer CornerIndex { uint corner_index[]; };
uniform vec3 lpv_lo;  // relative to the mesh's bounding-box centre
uniform float lpv_h;
uniform int lpv_nx;
uniform int lpv_ny;
uniform int lpv_nz;
uniform float vpl_shift;
uniform int box_mode;
uniform vec3 box_lo;
uniform vec3 box_hi;
uniform float level_shift;
flat out vec4 v_c0;
flat out vec4 v_c1;
flat out vec4 v_c2;

vec4 gi_lpv_fetch(ivec3 s, int ch) { return vec4(0.0); }
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f) { return 1.0; }
float gi_lpv_fetch_corner(int c, int q) { return 0.0; }

void main() {
  gl_PointSize = 1.0;
  ivec3 dims = ivec3(lpv_nx, lpv_ny, lpv_nz);
  ivec3 c = ivec3(0);
  v_c0 = vec4(0.0);
  v_c1 = vec4(0.0);
  v_c2 = vec4(0.0);
  if (mode == 2) {
    int o = gl_VertexID * 4;
    int corner = int(corner_index[gl_VertexID]);
    vec3 n = vec3(item[o], item[o + 1], item[o + 2]);
    float w = item[o + 3];
    c = ivec3(corner % lpv_nx, (corner / lpv_nx) % lpv_ny, corner / (lpv_nx * lpv_ny));
    v_c0 = vec4(gi_lpv_surfel(n, w, 0), gi_lpv_surfel(n, w, 1), gi_lpv_surfel(n, w, 2), gi_lpv_surfel(n, w, 3));
    v_c1 = vec4(gi_lpv_surfel(n, w, 4), gi_lpv_surfel(n, w, 5), gi_lpv_surfel(n, w, 6), gi_lpv_surfel(n, w, 7));
    v_c2 = vec4(gi_lpv_surfel(n, w, 8), 0.0, 0.0, 0.0);
  } else {
    vec3 p;
    vec3 n;
    vec3 phi;
    if (mode == 0) {
      ivec2 tc = ivec2(gl_VertexID % rsm_width, gl_VertexID / rsm_width);
      vec4 pw = texelFetch(rsm_position, tc, 0);
      if (pw.w == 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
      }
      n = texelFetch(rsm_normal, tc, 0).xyz;
      phi = texelFetch(rsm_flux, tc, 0).rgb;
      p = pw.xyz + vpl_shift * n;
    } else {
      int o = gl_VertexID * 9;
      p = vec3(item[o], item[o + 1], item[o + 2]);
      n = vec3(item[o + 3], item[o + 4], item[o + 5]);
      phi = vec3(item[o + 6], item[o + 7], item[o + 8]);
    }
    if (box_mode != 0) {
      bool in_box = gi_lpv_in_box(p, box_lo, box_hi);
      if (in_box != (box_mode == 1)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
      }
      p = p + level_shift * n;
    }
    c = gi_lpv_cell_of(p, lpv_lo, lpv_h, dims);
    vec4 y = gi_lpv_lobe(n);
    v_c0 = phi.x * y;
    v_c1 = phi.y * y;
    v_c2 = phi.z * y;
  }
  vec2 atlas = vec2(float(lpv_nx), float(lpv_ny * lpv_nz));
  vec2 px = vec2(float(c.x) + 0.5, float(c.z * lpv_ny + c.y) + 0.5);
  gl_Position = vec4(px / atlas * 2.0 - 1.0, 0.0, 1.0);
}
