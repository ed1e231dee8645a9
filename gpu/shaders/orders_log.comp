// The logarithm of the sum of the orders (sum_lin, linear) into tab_out, the table the
// sky pass looks up, when the table stays on the GPU (gpu::OrdersTables): the
// CPU's to_log (scattering_orders.cpp: log of max(v, kOrdersFloor), in float) on the
// GPU. GLSL's float log is exact to 3 ulp only (and llvmpipe's exp too coarse for a
// Newton step), and GLSL has no double log: the log here is computed in double,
// v = m 2^e with m in [sqrt(1/2), sqrt(2)), log v = e ln 2 + 2 atanh(t), t = (m - 1)/(m + 1)
// (|t| <= 0.172: the odd series to t^23, remainder < 1e-19), then rounded to float, so
// the table kept on the GPU equals the one read back and logged on the CPU to the last
// bit wherever the CPU's logf is correctly rounded (test
// GpuOrders.SkyWithGpuBuiltTablesMatchesAndStiffCasesAreFinite).
void main() {
  int e = orders_item();
  if (e >= params.n_items) return;
  int ex;
  double m = frexp(double(max(sum_lin[e], kOrdersFloor)), ex);
  if (m < 0.70710678118654752440LF) {
    m *= 2.0LF;
    ex -= 1;
  }
  double t = (m - 1.0LF) / (m + 1.0LF), t2 = t * t, s = 1.0LF / 23.0LF;
  for (int k = 21; k >= 1; k -= 2) s = 1.0LF / double(k) + t2 * s;
  tab_out[e] = float(double(ex) * 0.69314718055994530942LF + 2.0LF * t * s);
}
