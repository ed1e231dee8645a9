// Buffers and the table lookup of the successive-orders passes (orders_*.comp), after
// shared/geometry.glsl.hpp (float, then double) and shared/orders.glsl.hpp (double).
// The lookup (orders_corners, orders_blend, orders_ground_at) is orders_lookup.glsl's, assembled after
// this part on the table a pass reads (tab_in).
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

#define ATMOSH_ORDERS_TABLE(i) tab_in[i]
#define ATMOSH_ORDERS_GROUND(i) ground_log[i]
#define ATMOSH_ORDERS_P params

const double kOrdersPi = 3.14159265358979323846LF;

int orders_item() { return int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u); }

float orders_log(float v) { return log(max(v, kOrdersFloor)); }
double orders_mus(int k) { return orders_mus_of_u(double(k) / double(params.ns - 1), params.sun_m); }
