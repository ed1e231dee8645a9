// S_k at a texel (i, j, k, a): the trapezoid rule along the texel's ray (its nodes from
// the CPU set-up) of the transmittance times J_k looked up at each node; stored as its
// logarithm in the next table and added (linear) to the sum of the orders.
void main() {
  int e = orders_item();
  if (e >= params.n_items) return;
  int a = e % params.na, k = (e / params.na) % params.ns, ray = e / (params.na * params.ns);
  double r = orders_radius(ray / params.nmu, params.nr, params.R, params.H), mu = geom[params.off_ray_mu + ray];
  double mu_s = orders_mus(k), nu = orders_nu(mu, mu_s, orders_azimuth_cos(a, params.na));
  float acc[ATMOSH_ORDERS_MAX_WAVELENGTHS];
  for (int w = 0; w < params.nw; ++w) acc[w] = 0.0;
  for (int n = 0; n < params.nn; ++n) {
    int nd = ray * params.nn + n;
    double wn = node[4 * nd + 3];
    if (!(wn > 0.0LF)) continue;
    double mus_y = orders_sun_cosine_at(r, mu_s, node[4 * nd], nu, node[4 * nd + 1]);
    OrdersLookup L = orders_corners(coord[nd], orders_sun_coord(node[4 * nd + 2], mus_y, nu, params.ns, params.na, params.sun_m));
    for (int w = 0; w < params.nw; ++w) acc[w] += float(wn) * ray_t[nd * params.nw + w] * orders_blend(L, w);
  }
  for (int w = 0; w < params.nw; ++w) {
    tab_out[e * params.nw + w] = orders_log(acc[w]);
    sum_lin[e * params.nw + w] += acc[w];
  }
}
