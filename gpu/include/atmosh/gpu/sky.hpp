// atmosh/gpu/sky.hpp — sky images on the GPU (OpenGL 4.3 compute, headless EGL).
//
// gpu::render_sky renders the same image as atmo::render_sky (same projections,
// same spectral channels, XYZ with Y in cd/m^2 and linear sRGB through the same
// SpectralToXyz weights, applied on the CPU after read-back) from the same
// SkyIntegrator: the shader gpu/shaders/sky.comp runs SkyIntegrator::radiance's
// algorithm (same cuts, pieces, Gauss-Legendre nodes) on the integrator's own
// optical-depth tables (uploaded as float), with the ray geometry, density
// profiles, phase functions and closed-form piecewise-linear columns
// (shared/geometry.glsl.hpp), the table lookup (shared/lut.glsl.hpp) and the
// view-ray cuts (shared/view_ray.glsl.hpp) taken from the shared headers at
// build time. Pixel directions come from
// atmo::sky_pixel_direction. With ScatteringMethod::Approximate it adds, at every node,
// the all-orders multiple-scattering term of atmo::MultipleScatteringLut's table (the
// integrator's, uploaded as float, or built by gpu/shaders/ms_build.comp), looked up
// through shared/ms_approx.glsl.hpp as on the CPU. With ScatteringMethod::Orders (orders
// >= 2) it adds per pixel the successive-orders term of the integrator's tables
// (atmo::ScatteringOrders: the sum of orders 2..N along the view ray and the sky's light
// reflected by the ground at its end, SkyIntegrator::shade's), uploaded as they are
// (float logs; built on the CPU or by the GPU's passes, gpu/orders.hpp) and looked up
// through shared/orders.glsl.hpp and gpu/shaders/orders_lookup.glsl (the table passes'
// lookup); with orders = 1 single scattering, as on the CPU.
//
// Precision: float, except positions along the view ray and its cuts, and the sun
// lookups' ray geometry and table interpolation (double; float radii would put ~0.5 m
// into altitudes, 4e-4 relative in a 1.2 km Mie density). The closed-form columns
// (ozone, subtracted kinks) are float.
// Agreement with the CPU (double) image: max 5.5e-5 relative in spectral
// radiance above 1e-6 of the image maximum (measured on Mesa llvmpipe,
// earth-physical, sun from 30 to -4 degrees; tests bound it by 1e-4; details
// in docs/gpu.md).
//
// Supported atmospheres: Rayleigh and Mie exponential (or absent), ozone absent
// or piecewise linear with at most 16 nodes (tent) and at most the table's
// analytic_max_nodes; analytic phase functions (not tabulated); <= 64
// wavelengths. gpu::sky_supported says why not; render_sky throws
// Unsupported otherwise, and Unavailable when no EGL context can be created.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/program.hpp"

namespace atmosh::gpu {

// The GPU pass cannot handle this input (the CPU path can).
class Unsupported : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The optical-depth tables of `lut` (built for `atm`) in the GPU layout: view
// toward the top, view toward the ground (from off_ground), sun (from off_sun),
// each [shell][direction][3] = log of the mean relative density along the ray
// for log-encoded constituents, 0 for the others. Read back exactly at the
// table nodes through the public lookup.
std::vector<float> lut_tables_from_cpu(const atmo::OpticalDepthLut& lut, const atmo::Atmosphere& atm, int& off_ground,
                                       int& off_sun);

// The same tables built on the GPU (gpu/shaders/lut_build.comp: the same pieces
// and Gauss-Legendre rule as OpticalDepthLut's build, positions and sums in
// double, densities in float). Agreement with the CPU tables: see docs/gpu.md.
// Unsupported for atmospheres sky_unsupported_reason rejects. `seconds`: wall
// time of the GPU pass (compile, upload, dispatch, read-back).
std::vector<float> build_lut_tables(const Context& ctx, const atmo::OpticalDepthLut& lut, const atmo::Atmosphere& atm,
                                    int& off_ground, int& off_sun, double* seconds = nullptr);

// The all-orders multiple-scattering table (atmo::MultipleScatteringLut, Hillaire 2020)
// of the integrator's atmosphere, sun table and options (sky.options().scattering: the
// ms_* sizes and rule, whatever the integrator's method), built on the GPU
// (gpu/shaders/ms_build.comp: the entries' math of shared/ms_approx.glsl.hpp, the sky
// pass's sun lookup; radii and cosines in double, sums in float), laid out as
// MultipleScatteringLut::log_table() ([altitude][sun][wavelength] log Psi), in float.
// gpu_tables: from GPU-built optical-depth tables (build_lut_tables). Agreement with the
// CPU table: docs/gpu.md. Unsupported for atmospheres sky_unsupported_reason rejects,
// InputError for options out of range. `seconds`: wall time (compile, upload, dispatch,
// read-back).
std::vector<float> build_ms_table(const Context& ctx, const atmo::SkyIntegrator& sky, bool gpu_tables = false,
                                  double* seconds = nullptr);
// The CPU table in the same layout, in float (what render_sky uploads by default).
std::vector<float> ms_table_from_cpu(const atmo::MultipleScatteringLut& lut);

// The shader parts of the sky and table passes, in order: the shared geometry
// (float), the shared table math (float and double builds), the shared view-ray
// cuts (double), sky_lib.glsl, then
// `main_shader` (a path under gpu/shaders/).
std::vector<ShaderPart> sky_parts(const std::string& main_shader);
// The sky pass's parts (gpu/shaders/sky.comp): sky_parts with shared/orders.glsl.hpp
// (double) after the view-ray block, and the orders tables' buffers
// (gpu/shaders/sky_orders.glsl) and lookup (gpu/shaders/orders_lookup.glsl) before
// sky.comp.
std::vector<ShaderPart> sky_pass_parts();

// Empty when the GPU sky supports the integrator's atmosphere, else the reason.
std::string sky_unsupported_reason(const atmo::SkyIntegrator& sky);

// Renders with ctx (made current on this thread): single scattering, or with
// ScatteringMethod::Approximate single scattering plus the all-orders term of the
// multiple-scattering table at every node of the view ray (the CPU's add_ms_node,
// through shared/ms_approx.glsl.hpp), or with ScatteringMethod::Orders plus the orders
// term of sky.orders_tables() per pixel (uploaded; gpu_tables does not rebuild them:
// a sky whose options name gpu::make_orders_passes built them on the GPU already).
// Agreement with the CPU image with orders: 3.1e-5 relative on llvmpipe (bound 1e-4,
// GpuOrders.SkyMatchesTheCpuImage).
// gpu_tables: rebuild the integrator's optical-depth tables (build_lut_tables) and its
// multiple-scattering table (build_ms_table) on the GPU instead of uploading its
// CPU-built ones.
atmo::SkyImage render_sky(const Context& ctx, const atmo::SkyIntegrator& sky, atmo::SkyProjection projection,
                          int width, int height, double altitude_m, const glm::dvec3& sun, bool keep_spectral,
                          bool gpu_tables = false);
// Sun-table lookups on the GPU: for each origin (altitude h [m] in [0, top], cosine mu
// of the sun's zenith angle there), the column [m] (x Rayleigh, y Mie, z ozone) to the
// top of the atmosphere through the integrator's tables, w = 1 where the ground
// blocks the ray (and no column). It runs sky_lib.glsl's sun_lookup, the code the sky
// pass evaluates at each of its integration nodes (gpu/shaders/sun_lookup.comp), on
// the same inputs, so it equals the sky pass's transmittance toward the sun;
// OpticalDepthLut::sun(R + h, mu) is its CPU counterpart (agreement: docs/gpu.md).
// The inputs are float, as in the sky pass. `seconds`: wall time of `repeats`
// dispatches over all origins (after one untimed warm-up dispatch), so seconds /
// lookups is the GPU's time per lookup. Unsupported for atmospheres
// sky_unsupported_reason rejects; InputError for an origin out of range, repeats
// outside [1, 1000] or more than 2^26 origins.
struct SunLookups {
  std::vector<glm::vec4> column;
  double seconds = 0.0;
  long lookups = 0;  // origins x repeats
};
SunLookups sun_lookups(const Context& ctx, const atmo::SkyIntegrator& sky, const std::vector<glm::vec2>& h_mu,
                       int repeats = 1);

// Creates a headless context first (throws Unavailable if none).
atmo::SkyImage render_sky(const atmo::SkyIntegrator& sky, atmo::SkyProjection projection, int width, int height,
                          double altitude_m, const glm::dvec3& sun, bool keep_spectral);

}  // namespace atmosh::gpu
