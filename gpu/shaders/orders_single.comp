// S_1 at a texel (i, j, k, a) of the successive-orders tables (ScatteringOrders' single-
// scattering pass): the trapezoid rule along the texel's ray (nodes from the CPU set-up)
// of sum_c beta_c rho_c P_c(nu) exp(-tau(start -> node -> sun)), the sun's column by
// sky_lib.glsl's sun_lookup on the orders' own optical-depth tables (0 where the ground
// blocks the sun); stored as its logarithm. Assembled after the sky parts (gpu::sky_parts)
// and shared/orders.glsl.hpp (double).
layout(local_size_x = 64) in;
layout(std430, binding = 7) readonly buffer ONodes { double onode[]; };      // [ray][n] (t, r, mu, w)
layout(std430, binding = 8) readonly buffer ODens { double odens[]; };       // [ray][n] (rho_r, rho_m, column)
layout(std430, binding = 9) readonly buffer OGeom { double ogeom[]; };       // ATMOSH_ORDERS_BIND_GEOM's
layout(std430, binding = 10) writeonly buffer OOut { float s1_out[]; };      // log S_1 [texel][wavelength]
layout(std430, binding = 11) readonly buffer OParams { GpuOrdersParams op; };

void main() {
  int e = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u);
  if (e >= op.n_items) return;
  int a = e % op.na, k = (e / op.na) % op.ns, ray = e / (op.na * op.ns);
  double r = orders_radius(ray / op.nmu, op.nr, op.R, op.H), mu = ogeom[op.off_ray_mu + ray];
  double mu_s = orders_mus_of_u(double(k) / double(op.ns - 1), op.sun_m), nu = orders_nu(mu, mu_s, orders_azimuth_cos(a, op.na));
  float pr = phase_value(0, float(nu)), pm = phase_value(1, float(nu));
  float acc[ATMOSH_ORDERS_MAX_WAVELENGTHS];
  for (int w = 0; w < op.nw; ++w) acc[w] = 0.0;
  for (int n = 0; n < op.nn; ++n) {
    int nd = ray * op.nn + n;
    double wn = onode[4 * nd + 3], rn = onode[4 * nd + 1];
    if (!(wn > 0.0LF)) continue;
    double mus_y = orders_sun_cosine_at(r, mu_s, onode[4 * nd], nu, rn);
    vec4 c = sun_lookup(float(rn - op.R), float(mus_y));
    if (c.w != 0.0) continue;
    vec3 x = vec3(dvec3(odens[5 * nd + 2], odens[5 * nd + 3], odens[5 * nd + 4]) + dvec3(c.xyz));
    float wr = float(wn * odens[5 * nd] * double(pr)), wm = float(wn * odens[5 * nd + 1] * double(pm));
    for (int w = 0; w < op.nw; ++w)
      acc[w] += (spec[sky_spectral(3, op.nw, w)] * wr + spec[sky_spectral(4, op.nw, w)] * wm) *
                exp(-(spec[sky_spectral(0, op.nw, w)] * x.x + spec[sky_spectral(1, op.nw, w)] * x.y + spec[sky_spectral(2, op.nw, w)] * x.z));
  }
  for (int w = 0; w < op.nw; ++w) s1_out[e * op.nw + w] = log(max(acc[w], kOrdersFloor));
}
