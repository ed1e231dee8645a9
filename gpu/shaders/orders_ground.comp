// E of the current table at sun sample k: the upper hemisphere at the ground (the
// rule's zenith cosines x the sphere rule's azimuths) of the table's radiance times mu.
void main() {
  int k = orders_item();
  if (k >= params.n_items) return;
  double mu_s = orders_mus(k);
  float acc[ATMOSH_ORDERS_MAX_WAVELENGTHS];
  for (int w = 0; w < params.nw; ++w) acc[w] = 0.0;
  for (int z = 0; z < params.nz; ++z) {
    double mu = geom[params.off_up_mu + z], wz = geom[params.off_up_w + z] * (2.0LF * kOrdersPi / double(params.nphi)) * mu;
    OrdersRayCoord c = orders_ray_coord(params.R, mu, false, params.R, params.T, params.H, params.nr, params.nh);
    for (int b = 0; b < params.nphi; ++b) {
      double nu = orders_nu(mu, mu_s, geom[params.off_cphi + b]);
      OrdersLookup L = orders_corners(c, orders_sun_coord(mu, mu_s, nu, params.ns, params.na, params.sun_m));
      for (int w = 0; w < params.nw; ++w) acc[w] += float(wz) * orders_blend(L, w);
    }
  }
  for (int w = 0; w < params.nw; ++w) e_out[k * params.nw + w] = acc[w];
}
