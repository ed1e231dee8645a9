// The all-orders multiple-scattering table Psi_ms(altitude, mu_s) (MultipleScatteringLut,
// libatmo/src/multiple_scattering.cpp), one invocation per entry (altitude row a, sun
// column s), every wavelength: the same sphere rule, walk along its rays, phase
// normalisation, ground and terms through shared/ms_approx.glsl.hpp, the sun's
// transmittance through sky_lib.glsl's sun_lookup (the sky pass's). Radii, distances and
// cosines in double; densities, transmittances, phase functions and sums in float.
// Output: log Psi per wavelength (ms_table_value), [entry][wavelength].
layout(local_size_x = ATMOSH_ITEM_GROUP_SIZE) in;

// The zenith rule's Gauss-Legendre nodes on [-1, 1]: below the horizon x[n_lo], w[n_lo],
// then above it x[n_hi], w[n_hi] (sh::gauss_legendre, as the CPU build).
layout(std430, binding = ATMOSH_BIND_RULE) readonly buffer Rule { double rule[]; };
layout(std430, binding = ATMOSH_BIND_TABLE_OUT) writeonly buffer Out { float ms_out[]; };

// The hooks of the shared macros: the rule, densities, azimuths, phase functions, the
// extinction optical depth of a column at wavelength i, the sun seen from the ground
// and the ground's light.
#define RULE(i) rule[i]
#define DENSITY(h) dvec3(density_at(float(h)))
#define COS_PHI(a) double(cos(ms_azimuth(a, naz)))
#define PHASE(c, nu) phase_value(c, float(nu))
#define NO_VISIT(j, a)
#define SCA(row, i) spec[sky_spectral(row, params.nw, i)]
#define TAU(i, x) column_optical_depth(SCA(0, i), SCA(1, i), SCA(2, i), (x)[0], (x)[1], (x)[2])
#define SUN_GROUND(mu) vec4 ms_c_ = sun_lookup(0.0, float(mu)); bool ms_lit_ = ms_c_.w < 0.5; vec3 ms_sun_ = ms_c_.xyz;
#define ADD_GROUND(g, col) for (int i = 0; i < nw; ++i) l2[i] += float(g) * tview[i] * exp(-TAU(i, col));
// The entry's state (GLSL has no closures): f_ms, L_2nd and the view transmittance of the
// current ray per wavelength, the current ray's weights, zenith cosine, length and end.
float f[kMaxWavelengths], l2[kMaxWavelengths], tview[kMaxWavelengths], wdir_f, wdir;
double norm_r, norm_m, r, mus, mu_z, d_ray;
int nw, naz;
bool ground;

// One step of a ray of the rule (ATMOSH_MS_RAY_STEPS): f_ms (no sun), and L_2nd: the
// sun's light scattered at the step toward the entry's point, at every azimuth.
#define VISIT(k) ground = ms_ground_; d_ray = ms_d_; visit_step(k, ms_t_, ms_ry_, vec3(ms_rho_), vec3(ms_col_), float(ms_wt_), steps)
void visit_step(int k, double t, double ry, vec3 rho, vec3 x, float wt, int steps) {
  for (int i = 0; i < nw; ++i) {
    float tr = exp(-TAU(i, x));
    f[i] += wdir_f * wt * scattering_term(tr, SCA(3, i), SCA(4, i), rho.x, rho.y);
    if (k == steps) tview[i] = tr;
  }
  for (int q = 0; q < naz; ++q) {
    double nu = ms_scattering_cosine(mu_z, COS_PHI(q), mus);
    vec4 c = sun_lookup(float(max(ry - params.ground_radius_d, 0.0LF)), float(ms_point_sun_cosine(r, mus, t, nu, ry)));
    if (c.w > 0.5) continue;  // the Earth's shadow
    float w = wdir * wt, rr = rho.x * (PHASE(0, nu) / float(norm_r)) * w, rm = rho.y * (PHASE(1, nu) / float(norm_m)) * w;
    for (int i = 0; i < nw; ++i) l2[i] += scattering_term(exp(-TAU(i, x + c.xyz)), SCA(3, i), SCA(4, i), rr, rm);
  }
}

void main() {
  int item = item_index(int(gl_GlobalInvocationID.x), int(gl_GlobalInvocationID.y), int(gl_NumWorkGroups.x));
  if (item >= params.n_items) return;
  int ns = params.ms_suns, a = item / ns, s = item - a * ns, steps = params.ms_steps;
  int nz = params.ms_zenith, n_lo = ms_zenith_below(nz), n_hi = nz - n_lo;
  nw = params.nw;  // <= kMaxWavelengths (host); a bound of 64 would unroll every loop over it
  naz = params.ms_azimuths;
  double R = params.ground_radius_d, T = params.top_radius_d, w_z;
  r = R + ms_row_altitude(a, params.ms_altitudes, T - R);
  mus = ms_sun_cosine(double(s) / double(ns - 1));
  double mu_h = ms_horizon_cosine(r, R);
  float w_phi = ms_azimuth_weight(naz);
  norm_r = norm_m = 0.0LF;  // the phase functions normalised to 1 over the rule
  ATMOSH_MS_PHASE_NORMS(norm_r, norm_m, double, nz, naz, n_lo, n_hi, mu_h, RULE, COS_PHI, mus, w_phi, PHASE, NO_VISIT);
  for (int i = 0; i < nw; ++i) f[i] = l2[i] = 0.0;
  for (int j = 0; j < nz; ++j) {
    ATMOSH_MS_ZENITH_NODE(mu_z, w_z, j, n_lo, n_hi, mu_h, RULE);
    wdir_f = float(ms_direction_weight(w_z, 2.0LF * double(3.14159265358979323846LF), double(inv_four_pi())));
    wdir = float(ms_direction_weight(w_z, double(w_phi), double(inv_four_pi())));
    ATMOSH_MS_RAY_STEPS(double, dvec3, r, mu_z, R, T, steps, DENSITY, VISIT);
    if (ground && params.albedo > 0.0)  // the ground at the ray's end, lit by the sun (Lambertian)
      for (int q = 0; q < naz; ++q)
        ATMOSH_MS_GROUND(double, r, mus, d_ray, ms_scattering_cosine(mu_z, COS_PHI(q), mus), R, double(wdir),
                         double(params.albedo), SUN_GROUND, ADD_GROUND);
  }
  for (int i = 0; i < params.nw; ++i) ms_out[item * params.nw + i] = ms_table_value(ms_psi_entry(l2[i], f[i]));
}
