// The successive-orders tables in the sky pass (sky.comp with ScatteringMethod::Orders),
// after shared/orders.glsl.hpp (double): the sum of orders 2..N and of the ground's
// irradiance E_1..E_{N-1} (atmo::ScatteringOrders::radiance_table, ground_table: logs,
// uploaded from the CPU tables or from the GPU build) and their sizes. op.nr = 0: no
// orders term. orders_lookup.glsl (assembled next) reads them through these macros.
layout(std430, binding = ATMOSH_SKY_BIND_ORDERS) readonly buffer OrdersSum { float orders_sum[]; };
layout(std430, binding = ATMOSH_SKY_BIND_ORDERS_GROUND) readonly buffer OrdersGround { float orders_ground[]; };
layout(std430, binding = ATMOSH_SKY_BIND_ORDERS_PARAMS) readonly buffer OrdersParams { GpuOrdersParams op; };
#define ATMOSH_ORDERS_TABLE(i) orders_sum[i]
#define ATMOSH_ORDERS_GROUND(i) orders_ground[i]
#define ATMOSH_ORDERS_P op
