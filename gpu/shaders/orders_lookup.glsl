// The successive-orders tables' lookup on the GPU, one copy for the table passes
// (orders_*.comp, through orders_lib.glsl) and the sky pass (sky.comp, through
// sky_orders.glsl): ScatteringOrders::Impl::lookup, blend_log_corners and interp_ground
// (libatmo/src/scattering_orders.cpp) on the shared math of shared/orders.glsl.hpp (the
// corners' texels and weights, the curvature correction, the visibility floor).
// Assembled after shared/orders.glsl.hpp and a part that defines
//   ATMOSH_ORDERS_TABLE(i)   the log table read (float, [texel][wavelength]);
//   ATMOSH_ORDERS_GROUND(i)  the log ground table read (float, [sun sample][wavelength]);
//   ATMOSH_ORDERS_P          their GpuOrdersParams (nr, nmu, nh, ns, na, nw).

// One lookup: the 8 (radius, view, sun) corners' first values p (at azimuth a0, weight
// w0; a0 + 1 at p + nw, weight w1); per axis x (radius, view, sun, azimuth) the first
// values b0[x], b1[x] of the two samples whose second differences (neighbours at -+ st[x])
// are blended with the weights g0[x], g1[x] (orders_curvature).
struct OrdersLookup {
  int p[8];
  float w0[8];
  float w1[8];
  int b0[4];
  int b1[4];
  int st[4];
  float g0[4];
  float g1[4];
};
OrdersLookup orders_corners(OrdersRayCoord c, OrdersSunCoord s) {
  OrdersLookup L;
  int nmu = ATMOSH_ORDERS_P.nmu, ns = ATMOSH_ORDERS_P.ns, na = ATMOSH_ORDERS_P.na, nw = ATMOSH_ORDERS_P.nw;
  for (int n = 0; n < 8; ++n) {
    int di = n >> 2, dj = (n >> 1) & 1, dk = n & 1;
    float w = orders_corner_weight(c.fr, c.fm, s.fs, di, dj, dk);
    L.p[n] = orders_texel(c.i0 + di, c.j0 + dj, s.k0 + dk, s.a0, nmu, ns, na) * nw;
    L.w0[n] = w * (1.0 - s.fa);
    L.w1[n] = w * s.fa;
  }
  OrdersCurvature k = orders_curvature(c, s, ATMOSH_ORDERS_P.nr, ATMOSH_ORDERS_P.nh, ns, na);
  int centre = orders_texel(k.centre.x, k.centre.y, k.centre.z, k.centre.w, nmu, ns, na) * nw;
  L.st[0] = nmu * ns * na * nw;
  L.st[1] = ns * na * nw;
  L.st[2] = na * nw;
  L.st[3] = nw;
  for (int x = 0; x < 4; ++x) {  // the line along axis x through the centre
    L.b0[x] = centre + (k.at0[x] - k.centre[x]) * L.st[x];
    L.b1[x] = centre + (k.at1[x] - k.centre[x]) * L.st[x];
    L.g0[x] = k.g0[x];
    L.g1[x] = k.g1[x];
  }
  return L;
}
// g D at the sample whose first value is b, wavelength q (orders_curvature_term).
float orders_curvature_at_q(float g, int b, int st, int q) {
  return orders_curvature_term(g, ATMOSH_ORDERS_TABLE(b - st + q), ATMOSH_ORDERS_TABLE(b + q),
                               ATMOSH_ORDERS_TABLE(b + st + q));
}
// exp of the blend at wavelength q of the table (0 below the floor).
float orders_blend(OrdersLookup L, int q) {
  float ref = ATMOSH_ORDERS_TABLE(L.p[0] + q), a = 0.0, corr = 0.0;
  for (int n = 0; n < 8; ++n)
    a += L.w0[n] * (ATMOSH_ORDERS_TABLE(L.p[n] + q) - ref) +
         L.w1[n] * (ATMOSH_ORDERS_TABLE(L.p[n] + ATMOSH_ORDERS_P.nw + q) - ref);
  for (int x = 0; x < 4; ++x) {
    if (L.g0[x] > 0.0) corr += orders_curvature_at_q(L.g0[x], L.b0[x], L.st[x], q);
    if (L.g1[x] > 0.0) corr += orders_curvature_at_q(L.g1[x], L.b1[x], L.st[x], q);
  }
  return orders_log_visible(ref + a) ? exp(ref + a - corr) : 0.0;
}
// The ground table's value at coordinate g, wavelength q (orders_ground_value).
float orders_ground_at(OrdersSunCoord g, int q) {
  int nw = ATMOSH_ORDERS_P.nw, ns = ATMOSH_ORDERS_P.ns;
  float w = orders_curvature_weight(g.fs, ns), t = 0.0;
  if (w > 0.0) {
    int p0 = orders_curvature_at(g.k0, 0, ns) * nw + q, p1 = orders_curvature_at(g.k0 + 1, 0, ns) * nw + q;
    t = orders_curvature_term(w * (1.0 - g.fs), ATMOSH_ORDERS_GROUND(p0 - nw), ATMOSH_ORDERS_GROUND(p0),
                              ATMOSH_ORDERS_GROUND(p0 + nw)) +
        orders_curvature_term(w * g.fs, ATMOSH_ORDERS_GROUND(p1 - nw), ATMOSH_ORDERS_GROUND(p1),
                              ATMOSH_ORDERS_GROUND(p1 + nw));
  }
  return orders_ground_value(ATMOSH_ORDERS_GROUND(g.k0 * nw + q), ATMOSH_ORDERS_GROUND((g.k0 + 1) * nw + q), g.fs, t);
}
