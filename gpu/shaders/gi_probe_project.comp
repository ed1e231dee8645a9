// Radiance probes (gpu/cube_raster.hpp, ProbeProjector): the SH projection of a batch of
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
// Two dispatches of this program per batch (uniform `stage`):
//   stage 0, one invocation per (probe of the batch, texel of the N x N map): the texel's
//            integral I_t = sum over its sub-texels of Omega_s L_s into `texel_int`;
//   stage 1, one invocation per (probe of the batch, coefficient): c_lm = sum_t Y_lm(dir_t) I_t
//            over the 6 N^2 texels (float sums per face row), the sun, the window.
layout(local_size_x = 64) in;
uniform sampler2D atlas;  // RGBA32F: face f of batch probe k, texel (row, col) at (f NS + col, k NS + row)
layout(std430, binding = 0) readonly buffer Env { float env[]; };  // [((f NS + row) NS + col) 3 + channel]
layout(std430, binding = 1) buffer Sh { float sh_out[]; };         // [((first + k) 3 + channel) stride + i]
layout(std430, binding = 2) buffer TexelIntegrals { float texel_int[]; };  // [((k 6 + f) N + r) N + c] 3 + channel
uniform int stage;
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

void texel_integral(int id) {
  int n = ns / ss;
  int per_probe = 6 * n * n;
  if (id >= count * per_probe) return;
  int k = id / per_probe;
  int t = id - k * per_probe;
  int f = t / (n * n);
  int r = (t / n) % n;
  int c = t % n;
  vec3 acc = vec3(0.0);
  for (int sr = 0; sr < ss; ++sr)
    for (int sc = 0; sc < ss; ++sc) {
      int fr = r * ss + sr;
      int fc = c * ss + sc;
      vec4 v = texelFetch(atlas, ivec2(f * ns + fc, k * ns + fr), 0);
      int e = ((f * ns + fr) * ns + fc) * 3;
      vec3 L = v.a != 0.0 ? v.rgb : vec3(env[e], env[e + 1], env[e + 2]);
      acc += sh_cube_texel_solid_angle(fc, fr, ns) * L;
    }
  for (int ch = 0; ch < 3; ++ch) texel_int[id * 3 + ch] = acc[ch];
}

void coefficient(int id) {
  int nc = bands * bands;
  if (id >= count * nc) return;
  int k = id / nc;
  int i = id - k * nc;
  int l = sh_index_band(i);
  int m = i - l * (l + 1);
  int n = ns / ss;
  vec3 acc = vec3(0.0);
  for (int f = 0; f < 6; ++f)
    for (int r = 0; r < n; ++r) {
      vec3 row_acc = vec3(0.0);
      for (int c = 0; c < n; ++c) {
        int t = ((k * 6 + f) * n + r) * n + c;
        row_acc += sh_basis_lm(l, m, sh_cube_texel_direction(f, c, r, n)) *
                   vec3(texel_int[t * 3], texel_int[t * 3 + 1], texel_int[t * 3 + 2]);
      }
      acc += row_acc;
    }
  if (include_sun != 0) acc += sun_e * sh_basis_lm(l, m, sun_dir);
  acc *= window[l];
  for (int ch = 0; ch < 3; ++ch) sh_out[((first + k) * 3 + ch) * stride + i] = acc[ch];
}

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (stage == 0)
    texel_integral(id);
  else
    coefficient(id);
}
