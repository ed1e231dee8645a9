// Buffers and the table lookup of the successive-orders passes (orders_*.comp), after
// shared/geometry.glsl.hpp (float, then double) and shared/orders.glsl.hpp (double).
// The lookup is ScatteringOrders::Impl::interp (libatmo/src/scattering_orders.cpp):
// the 16 corners' logarithms blended per wavelength by the shared orders_blend_log.
layout(local_size_x = 64) in;
layout(std430, binding = ATMOSH_ORDERS_BIND_TAB_IN) readonly buffer TabIn { float tab_in[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_TAB_OUT) writeonly buffer TabOut { float tab_out[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_SUM) buffer Sum { float sum_lin[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_INCOMING) buffer Incoming { float incoming[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_NODES) readonly buffer Nodes { double node[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_COORDS) readonly buffer Coords { OrdersRayCoord coord[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_RAY_T) readonly buffer RayT { float ray_t[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_GEOM) readonly buffer Geom { double geom[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_PR) readonly buffer PhaseR { float phase_r[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_PM) readonly buffer PhaseM { float phase_m[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_GROUND_T) readonly buffer GroundT { float ground_t[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_GROUND) readonly buffer Ground { float ground_log[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_E_OUT) writeonly buffer EOut { float e_out[]; };
layout(std430, binding = ATMOSH_ORDERS_BIND_PARAMS) readonly buffer Params { GpuOrdersParams params; };

const double kOrdersPi = 3.14159265358979323846LF;

int orders_item() { return int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u); }

// The 8 (radius, view, sun) corners of a lookup: first value of each, at azimuth a0
// (weight w0) and a0 + 1 (p + nw, weight w1).
void orders_corners(OrdersRayCoord c, OrdersSunCoord s, out int p[8], out float w0[8], out float w1[8]) {
  for (int n = 0; n < 8; ++n) {
    int di = n >> 2, dj = (n >> 1) & 1, dk = n & 1;
    float w = orders_corner_weight(c.fr, c.fm, s.fs, di, dj, dk);
    p[n] = orders_texel(c.i0 + di, c.j0 + dj, s.k0 + dk, s.a0, params.nmu, params.ns, params.na) * params.nw;
    w0[n] = w * (1.0 - s.fa);
    w1[n] = w * s.fa;
  }
}
// exp of the blend at wavelength q of tab_in (0 below the floor).
float orders_blend(int p[8], float w0[8], float w1[8], int q) {
  float ref = tab_in[p[0] + q], a = 0.0, a2 = 0.0;
  for (int n = 0; n < 8; ++n) {
    float d0 = tab_in[p[n] + q] - ref, d1 = tab_in[p[n] + params.nw + q] - ref;
    a += w0[n] * d0 + w1[n] * d1;
    a2 += w0[n] * d0 * d0 + w1[n] * d1 * d1;
  }
  return orders_log_visible(ref + a) ? exp(orders_blend_log(ref, a, a2)) : 0.0;
}
float orders_log(float v) { return log(max(v, kOrdersFloor)); }
double orders_mus(int k) { return orders_mus_of_u(double(k) / double(params.ns - 1), params.sun_m); }
