// Test driver: the shared view-ray cuts (shared/view_ray.glsl.hpp, double
// build) for a list of rays (r, mu, mu_s, nu, s_end; ground radius R) and cut
// radii -> n, then the cuts, per ray (kMaxViewCuts + 1 doubles).
layout(local_size_x = 64) in;
layout(std430, binding = 7) readonly buffer CutRays { double cut_in[]; };      // [ray][5]
layout(std430, binding = 8) readonly buffer CutRadii { double cut_radii[]; };  // ascending
layout(std430, binding = 9) writeonly buffer CutOut { double cut_out[]; };
uniform int n_rays;
uniform int n_radii;
uniform double radius_R;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= n_rays) return;
  double r = cut_in[5 * i], mu = cut_in[5 * i + 1];
  uvec2 radii[kMaxCutSpheres];  // the double build's packed real_array (shared/view_ray.glsl.hpp)
  for (int k = 0; k < n_radii; ++k) radii[k] = unpackDouble2x32(cut_radii[k]);
  double rt2 = tangent_radius_sq(r, mu);
  ViewRayCuts c = view_ray_cuts(r, mu, cut_in[5 * i + 2], cut_in[5 * i + 3], radius_R, cut_in[5 * i + 4], rt2, radii,
                                n_radii);
  int o = i * (kMaxViewCuts + 1);
  cut_out[o] = double(c.n);
  for (int k = 0; k < c.n; ++k) cut_out[o + 1 + k] = packDouble2x32(c.s[k]);
}
