// Radiance probes (gpu/cube_raster.hpp, ProbePipeline): the SH projection of a batch of
// rasterised cube maps, on the GPU, as libsh's sh::project_cube does it on the CPU — the
// texel-centre basis value times the texel's exact solid angle, both from the shared block
// of libsh/include/atmosh/sh/shared/cube.glsl.hpp (pasted before this file) — with the
// supersampled texel means of gi::build_probe_grid_surface: the cube maps are rendered at
// NS = N S texels a side; coarse texel (r, c) of size N takes the basis at its own centre and
// the sum of its S x S sub-texels' radiance times their exact solid angles:
//   c_lm = sum_{f, coarse texels t} Y_lm(dir_t) sum_{sub-texels s of t} Omega_s L_s.
// L_s is the atlas texel where a surface was drawn (alpha != 0), else the environment along
// the sub-texel's centre (`env`, the same for every probe). Then band l is multiplied by
// window[l] after adding, with include_sun, the point sun's exact projection E Y_lm(s)
// (as gi::build_probe_grid_surface's projection step).
// One invocation per (probe of the batch, coefficient); float sums per face row.
layout(local_size_x = 64) in;
uniform sampler2D atlas;  // RGBA32F: face f of batch probe k, texel (row, col) at (f NS + col, k NS + row)
layout(std430, binding = 0) readonly buffer Env { float env[]; };  // [((f NS + row) NS + col) 3 + channel]
layout(std430, binding = 1) buffer Sh { float sh_out[]; };         // [((first + k) 3 + channel) stride + i]
uniform int ns;           // texels a side as rendered (N S)
uniform int ss;           // supersample S (N = ns / ss)
uniform int bands;        // 1..16
uniform int count;        // probes in this batch
uniform int first;        // index of the batch's first probe in the output
uniform int stride;       // floats per channel in the output (>= bands^2)
uniform float window[16];  // per band
uniform int include_sun;
uniform vec3 sun_dir;     // unit, towards the sun
uniform vec3 sun_e;       // irradiance at normal incidence, per channel

void main() {
  int nc = bands * bands;
  int id = int(gl_GlobalInvocationID.x);
  if (id >= count * nc) return;
  int k = id / nc;
  int i = id - k * nc;
  int l = sh_index_band(i);
  int m = i - l * (l + 1);
  int n = ns / ss;
  vec3 acc = vec3(0.0);
  for (int f = 0; f < 6; ++f) {
    for (int r = 0; r < n; ++r) {
      vec3 row_acc = vec3(0.0);
      for (int c = 0; c < n; ++c) {
        float y = sh_basis_lm(l, m, sh_cube_texel_direction(f, c, r, n));
        vec3 t_acc = vec3(0.0);
        for (int sr = 0; sr < ss; ++sr)
          for (int sc = 0; sc < ss; ++sc) {
            int fr = r * ss + sr;
            int fc = c * ss + sc;
            vec4 t = texelFetch(atlas, ivec2(f * ns + fc, k * ns + fr), 0);
            vec3 L = t.a != 0.0 ? t.rgb : vec3(env[((f * ns + fr) * ns + fc) * 3], env[((f * ns + fr) * ns + fc) * 3 + 1],
                                               env[((f * ns + fr) * ns + fc) * 3 + 2]);
            t_acc += sh_cube_texel_solid_angle(fc, fr, ns) * L;
          }
        row_acc += y * t_acc;
      }
      acc += row_acc;
    }
  }
  if (include_sun != 0) acc += sun_e * sh_basis_lm(l, m, sun_dir);
  acc *= window[l];
  for (int ch = 0; ch < 3; ++ch) sh_out[((first + k) * 3 + ch) * stride + i] = acc[ch];
}
