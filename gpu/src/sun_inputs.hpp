// The inputs of sky_lib.glsl's sun_lookup and phase_value for an optical-depth table and
// its atmosphere (private to atmosh::gpu): what the sky pass uploads for its integrator's
// table, for another table (the successive-orders build's own, gpu/src/orders.cpp).
// Defined in sky.cpp, next to the sky pass's inputs.
#pragma once

#include <vector>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/shared/sky_params.glsl.hpp"

namespace atmosh::gpu {

struct SunLookupInputs {
  atmo::shared::GpuSkyParams params{};  // constituents, sun table, closed-form nodes, phase functions
  std::vector<float> tables;            // ATMOSH_BIND_TABLES
  std::vector<double> shells;           // ATMOSH_BIND_SHELLS (rho, inverse denominators)
  std::vector<float> spectral;          // ATMOSH_BIND_SPECTRAL (solar row 0)
};
SunLookupInputs sun_lookup_inputs(const atmo::OpticalDepthLut& lut, const atmo::Atmosphere& atm);

}  // namespace atmosh::gpu
