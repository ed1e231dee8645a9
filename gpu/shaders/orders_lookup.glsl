// The successive-orders tables' lookup on the GPU, one copy for the table passes
// (orders_*.comp, through orders_lib.glsl) and the sky pass (sky.comp, through
// sky_orders.glsl): ScatteringOrders::Impl::interp (libatmo/src/scattering_orders.cpp)
// on the shared math of shared/orders.glsl.hpp (the corners' texels and weights, the
// blend of their logarithms with the spread correction, the visibility floor).
// Assembled after shared/orders.glsl.hpp and a part that defines
//   ATMOSH_ORDERS_TABLE(i)  the log table read (float, [texel][wavelength]);
//   ATMOSH_ORDERS_P         its GpuOrdersParams (nmu, ns, na, nw).

// The 8 (radius, view, sun) corners of a lookup: first value of each, at azimuth a0
// (weight w0) and a0 + 1 (p + nw, weight w1).
void orders_corners(OrdersRayCoord c, OrdersSunCoord s, out int p[8], out float w0[8], out float w1[8]) {
  for (int n = 0; n < 8; ++n) {
    int di = n >> 2, dj = (n >> 1) & 1, dk = n & 1;
    float w = orders_corner_weight(c.fr, c.fm, s.fs, di, dj, dk);
    p[n] = orders_texel(c.i0 + di, c.j0 + dj, s.k0 + dk, s.a0, ATMOSH_ORDERS_P.nmu, ATMOSH_ORDERS_P.ns,
                        ATMOSH_ORDERS_P.na) * ATMOSH_ORDERS_P.nw;
    w0[n] = w * (1.0 - s.fa);
    w1[n] = w * s.fa;
  }
}
// exp of the blend at wavelength q of the table (0 below the floor).
float orders_blend(int p[8], float w0[8], float w1[8], int q) {
  float ref = ATMOSH_ORDERS_TABLE(p[0] + q), a = 0.0, a2 = 0.0;
  for (int n = 0; n < 8; ++n) {
    float d0 = ATMOSH_ORDERS_TABLE(p[n] + q) - ref, d1 = ATMOSH_ORDERS_TABLE(p[n] + ATMOSH_ORDERS_P.nw + q) - ref;
    a += w0[n] * d0 + w1[n] * d1;
    a2 += w0[n] * d0 * d0 + w1[n] * d1 * d1;
  }
  return orders_log_visible(ref + a) ? exp(orders_blend_log(ref, a, a2)) : 0.0;
}
