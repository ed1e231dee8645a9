// Sky radiance, one invocation per pixel: SkyIntegrator::radiance (libatmo/src/sky.cpp)
// through the same shared code (shared/view_ray.glsl.hpp: the ray's set-up, its cuts,
// the walk along it, the node's terms; shared/scatter.glsl.hpp: the integrand;
// shared/ms_approx.glsl.hpp: the all-orders multiple-scattering table's lookup and
// term, where params.ms_altitudes > 0), on the inputs of sky_lib.glsl; with the
// successive-orders tables (op.nr > 0: sky_orders.glsl) their lookup per pixel through
// orders_lookup.glsl and shared/orders.glsl.hpp, as SkyIntegrator::shade's orders term.
// Assembled with ATMOSH_SKY_TRACE defined.
layout(local_size_x = ATMOSH_ITEM_GROUP_SIZE) in;

layout(std430, binding = ATMOSH_BIND_MS_TABLE) readonly buffer MsTable { float ms_tab[]; };

// The pixel's state that sky_visit adds to (GLSL has no closures).
SkyViewRay g_ray;
float g_p_ray, g_p_mie;
float g_acc[kMaxWavelengths];

dvec3 sky_density(double h) { return dvec3(density_at(float(h))); }

// The extinction optical depth of the column x at wavelength i.
float tau_at(int i, vec3 x) {
  int nw = params.nw;
  return column_optical_depth(spec[sky_spectral(0, nw, i)], spec[sky_spectral(1, nw, i)], spec[sky_spectral(2, nw, i)],
                              x[0], x[1], x[2]);
}

// SkyIntegrator::shade's node, in one loop over the wavelengths (one loop keeps llvmpipe's
// compilation short): the multiple-scattering term at every node, those in the Earth's
// shadow included (SkyIntegrator::add_ms_node: sigma_s Psi_ms T(observer, node) w, Psi_ms
// interpolated log-bilinearly at the node's radius and sun cosine), and where the sun is
// not in the Earth's shadow the single-scattering integrand.
void sky_visit(SkyViewNode nd) {
  double mus = sky_node_sun_cosine(g_ray, nd), top = params.top_radius_d - params.ground_radius_d;
  vec4 to_sun = sun_lookup(float(sky_altitude(nd.r, params.ground_radius_d)), float(mus));
#ifdef ATMOSH_SKY_MS
  bool lit = to_sun.w < 0.5, ms = params.ms_altitudes > 0;
#else
  const bool ms = false;  // no table: the term's code is left out of the program
  bool lit = to_sun.w < 0.5;
#endif
  if (!lit && !ms) return;
  SkyNodeTerms t = sky_node_terms(nd, dvec3(to_sun.xyz), double(g_p_ray), double(g_p_mie));
  int na = max(params.ms_altitudes, 2), ns = max(params.ms_suns, 2), nw = params.nw;  // nw <= kMaxWavelengths
  double ua = ms_altitude_index(nd.r, params.ground_radius_d, top, na), us = ms_sun_index(mus, ns);
  int a0 = ms_cell_start(ua, na), s0 = ms_cell_start(us, ns), p00 = (a0 * ns + s0) * nw, p10 = p00 + ns * nw;
  float fa = float(ua - double(a0)), fs = float(us - double(s0)), rr = float(nd.rho[0] * nd.w), rm = float(nd.rho[1] * nd.w);
  for (int i = 0; i < nw; ++i) {
    if (lit)
      g_acc[i] += scattering_term(exp(-tau_at(i, vec3(t.x[0], t.x[1], t.x[2]))), spec[sky_spectral(3, nw, i)],
                                  spec[sky_spectral(4, nw, i)], t.sr, t.sm);
    if (ms)
      g_acc[i] += ms_sky_term(exp(-tau_at(i, vec3(nd.column))),
                              ms_psi_of_log(ms_log_bilinear(fa, fs, ms_tab[p00 + i], ms_tab[p00 + nw + i], ms_tab[p10 + i],
                                                            ms_tab[p10 + nw + i])),
                              spec[sky_spectral(3, nw, i)], spec[sky_spectral(4, nw, i)], rr, rm);
  }
}

// SkyIntegrator::shade's orders term (method orders): orders 2..N for the whole view ray,
// one lookup in the sum of their tables (ScatteringOrders::radiance: the observer's
// radius clamped to the tables', the ray's own cosines), and where the ray ends on the
// ground the sky's light reflected there, albedo / pi E_1..E_{N-1}(mu_s at the ground)
// (ScatteringOrders::ground_irradiance) times the view ray's transmittance. Into g_acc,
// already in radiance units (scale: the solar irradiance's per wavelength).
void sky_add_orders(dvec3 column) {
  int nw = params.nw, nwc = min(nw, kMaxWavelengths);
  double r = clamp(g_ray.r, op.R, op.T);
  OrdersRayCoord c = orders_ray_coord(r, g_ray.mu, g_ray.ground, op.R, op.T, op.H, op.nr, op.nh);
  OrdersSunCoord s = orders_sun_coord(g_ray.mu, g_ray.mu_s, g_ray.nu, op.ns, op.na, op.sun_m);
  OrdersLookup L = orders_corners(c, s);
  for (int i = 0; i < nwc; ++i)
    g_acc[i] += spec[sky_spectral(6, nw, i)] * params.irradiance_scale * orders_blend(L, i);
  if (g_ray.ground && op.albedo > 0.0LF) {
    OrdersSunCoord g = orders_ground_coord(sky_ground_sun_cosine(g_ray), op.ns, op.sun_m);
    float a = float(op.albedo / 3.14159265358979323846LF);
    for (int i = 0; i < nwc; ++i)
      g_acc[i] += spec[sky_spectral(6, nw, i)] * params.irradiance_scale * a *
                  orders_ground_at(g, i) *
                  exp(-tau_at(i, vec3(column)));
  }
}

void main() {
  int pix = item_index(int(gl_GlobalInvocationID.x), int(gl_GlobalInvocationID.y), int(gl_NumWorkGroups.x));
  if (pix >= params.n_items) return;
  int nw = params.nw, nwc = min(nw, kMaxWavelengths);
  double R = params.ground_radius_d;
  for (int i = 0; i < nwc; ++i) g_acc[i] = 0.0;
  g_ray = sky_view_ray_toward(params.observer_radius_d, dvec3(dirs[pix].xyz),
                              dvec3(params.sun_dir[0], params.sun_dir[1], params.sun_dir[2]), R, params.top_radius_d);
  if (dirs[pix].w > 0.0 && !g_ray.empty && g_ray.s_end > 0.0LF) {
    g_p_ray = params.has_ext[0] != 0 ? phase_value(0, float(g_ray.nu)) : 0.0;
    g_p_mie = params.has_ext[1] != 0 ? phase_value(1, float(g_ray.nu)) : 0.0;
    dvec3 column = sky_walk(g_ray, params.cut_radii, params.n_cuts, R, dvec3(params.ext_max[0], params.ext_max[1],
                            params.ext_max[2]), double(params.max_piece_optical_depth), params.gauss_x, params.gauss_w,
                            params.n_gauss, params.part_w);
    for (int i = 0; i < nwc; ++i) g_acc[i] *= spec[sky_spectral(6, nw, i)] * params.irradiance_scale;
#ifdef ATMOSH_SKY_ORDERS
    if (op.nr > 0) sky_add_orders(column);
#endif
    float mus_g = float(sky_ground_sun_cosine(g_ray));
    vec4 to_sun = sun_lookup(0.0, mus_g);
    if (sky_ground_lit(g_ray, double(params.albedo), double(mus_g)) && to_sun.w < 0.5)  // ground reflection
      for (int i = 0; i < nwc; ++i)
        g_acc[i] += spec[sky_spectral(6, nw, i)] * params.irradiance_scale *
                    ground_term(params.albedo, mus_g, exp(-tau_at(i, vec3(column) + to_sun.xyz)));
  }
  for (int i = 0; i < nw; ++i) radiance[pix * nw + i] = i < nwc ? g_acc[i] : 0.0;
}
