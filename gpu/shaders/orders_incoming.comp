// I_{k-1} on the scattering density's sphere rule (the J pass's first half in
// ScatteringOrders' build): per (radius i, sun k, direction z, b), the previous order's
// table looked up along the direction, plus, for directions to the ground, the ground's
// light: order 2 the direct sun, later orders the previous order's irradiance E.
void main() {
  int nq = params.nz * params.nphi, e = orders_item();
  if (e >= params.n_items) return;
  int i = e / (params.ns * nq), k = (e / nq) % params.ns, z = (e % nq) / params.nphi, b = e % params.nphi;
  double r = orders_radius(i, params.nr, params.R, params.H), mu_s = orders_mus(k);
  double muq = geom[i * params.nz + z], ss = sqrt(max(0.0LF, 1.0LF - mu_s * mu_s));
  double snq = sqrt(max(0.0LF, 1.0LF - muq * muq));
  double nu = orders_nu_of_sines(muq, mu_s, snq, ss, geom[params.off_cphi + b]);
  bool ground = z < params.ng;
  OrdersLookup L = orders_corners(orders_ray_coord(r, muq, ground, params.R, params.T, params.H, params.nr, params.nh),
                                  orders_sun_coord(muq, mu_s, nu, params.ns, params.na, params.sun_m));
  double mus_g = ground ? orders_ground_sun_cosine(r, mu_s, geom[params.off_d_ground + i * params.ng + z], nu, params.R) : 0.0LF;
  OrdersSunCoord g = orders_ground_coord(mus_g, params.ns, params.sun_m);
  int t0 = (i * params.ng + z) * params.nw, sg0 = params.off_sun_ground + (((i * params.ns + k) * params.ng + z) * params.nphi + b) * params.nw;
  for (int q = 0; q < params.nw; ++q) {
    float v = orders_blend(L, q);
    if (ground && params.albedo > 0.0LF) {
      double tg = double(ground_t[t0 + q]) * params.albedo / kOrdersPi;
      if (params.order == 2) {
        if (mus_g > 0.0LF) v += float(tg * mus_g * double(ground_t[sg0 + q]));
      } else {
        v += float(tg) * orders_ground_at(g, q);
      }
    }
    incoming[e * params.nw + q] = v;
  }
}
