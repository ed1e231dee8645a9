// Evaluates the shared geometry / density / phase functions for a list of
// inputs (used by the tests to compare the GLSL build of the shared headers with
// the C++ double build). Assembled after shared/geometry.glsl.hpp and
// shared/lut.glsl.hpp.
layout(local_size_x = 64) in;

struct CheckInput {
  float r, mu, s, h, cos_theta, g, pad0, pad1;
};
layout(std430, binding = 0) readonly buffer Inputs { CheckInput check_in[]; };
layout(std430, binding = 1) writeonly buffer Outputs { float check_out[]; };
uniform int n_cases;
uniform float ground_radius;
uniform float top_radius;

const int kOutputs = 16;

void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= n_cases) return;
  CheckInput c = check_in[i];
  float R = ground_radius, T = top_radius;
  int o = i * kOutputs;
  check_out[o + 0] = radius_along(c.r, c.mu, c.s);
  check_out[o + 1] = distance_to_top(c.r, c.mu, T);
  check_out[o + 2] = ray_hits_ground(c.r, c.mu, R) ? distance_to_ground(c.r, c.mu, R) : -1.0;
  check_out[o + 3] = mu_horizon(c.r, R);
  check_out[o + 4] = density_exponential(c.h, 8000.0);
  check_out[o + 5] = density_tent(c.h, 10000.0, 25000.0, 40000.0);
  check_out[o + 6] = phase_rayleigh(c.cos_theta, 0.0279);
  check_out[o + 7] = phase_hg(c.cos_theta, c.g);
  check_out[o + 8] = phase_cornette_shanks(c.cos_theta, c.g);
  check_out[o + 9] = phase_double_hg(c.cos_theta, c.g, -0.3, 0.8);
  check_out[o + 10] = mu_along(c.r, c.mu, c.s, radius_along(c.r, c.mu, c.s));
  check_out[o + 11] = tangent_radius_sq(c.r, c.mu) * 1e-12;
  // shared/lut.glsl.hpp
  check_out[o + 12] = lut_x(c.s, 1000.0, 41000.0);
  float p = 3.0 * (c.cos_theta + 1.0) / 2.0;  // [0, 3]
  check_out[o + 13] = lagrange_cubic_weight(p, i % 4);
  float rs = radius_along(c.r, c.mu, c.s);
  check_out[o + 14] = cos_zenith_along(c.r, c.g, c.cos_theta, c.s, rs);
  // quadratic_ramps_column: two ramps (11 and 47 km above the ground) over [0, s]
  float ramp_r[kMaxLinearNodes], ramp_c[kMaxLinearNodes];
  ramp_r[0] = R + 11000.0;
  ramp_r[1] = R + 47000.0;
  ramp_c[0] = 1.8e-9;
  ramp_c[1] = -2.3e-12;
  check_out[o + 15] = quadratic_ramps_column(c.r, c.mu, c.s, ramp_r, ramp_c, 2);
}
