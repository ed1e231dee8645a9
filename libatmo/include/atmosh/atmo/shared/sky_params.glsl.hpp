// atmosh/atmo/shared/sky_params.glsl.hpp — the parameter block of the GPU's
// atmosphere passes (gpu/shaders/sky_lib.glsl and the shaders assembled after it:
// sky.comp, sun_lookup.comp, lut_build.comp, ms_build.comp, ozone_check.comp), declared once for
// the C++ side that fills it (gpu/src/sky.cpp) and the GLSL side that reads it
// (`layout(std430) readonly buffer ... { GpuSkyParams params; }` in sky_lib.glsl).
//
// Layout: std430 (GLSL 4.30, sec. 7.6.2.2): a scalar member is aligned to its size
// and an array of scalars has the scalar's size as stride, i.e. the C++ layout of
// the same members on every platform atmosh builds for. The doubles come first, then
// only 4-byte members, so there is no padding; gpu/src/sky.cpp static_asserts the
// size and the offsets, and GpuSky.ParameterBlockLayoutMatches compares them with the
// driver's (program interface query).
//
// The offsets ("off_*") index the storage buffers of sky_lib.glsl; counts of 0 mean
// "none". Units: metres, 1/m.
#pragma once

#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/view_ray.glsl.hpp"

namespace atmosh::atmo::shared {

#define ATMOSH_FN inline

// ATMOSH_GLSL_BEGIN

const int kMaxWavelengths = 64;  // wavelengths of the GPU sky (accumulated per invocation)

// Binding points of the storage buffers (gpu/src/sky.cpp binds, the shaders declare).
#define ATMOSH_BIND_ITEMS 0       // per item: pixel direction (xyz, w > 0 valid) or lookup origin
#define ATMOSH_BIND_TABLES 1      // optical-depth tables, float [shell][direction][3] (lut_table_entry)
#define ATMOSH_BIND_NODES 2       // float: piecewise-linear density nodes (altitudes[n], values[n])
#define ATMOSH_BIND_SPECTRAL 3    // float: extinction[3][nw], scattering[3][nw], solar[nw] (sky_spectral)
#define ATMOSH_BIND_RESULT 4      // float: per item, nw radiances or 4 sun-lookup values
#define ATMOSH_BIND_SHELLS 6      // double: the table's shell rho[S], inverse Lagrange denominators[(S - 3) 4]
#define ATMOSH_BIND_CHECK_IN 7    // test drivers' inputs
#define ATMOSH_BIND_CHECK_OUT 8   // test drivers' outputs
#define ATMOSH_BIND_CROSSINGS 9   // double: table build, sorted radii that cut a table ray
#define ATMOSH_BIND_TABLE_OUT 10  // float: table build output [entry][3]
#define ATMOSH_BIND_RULE 11       // double: table build, Gauss-Legendre rule on (0, 1): x[n], w[n]
#define ATMOSH_BIND_SHELL_RADII 12  // double: table build, shell radii
#define ATMOSH_BIND_PARAMS 13     // GpuSkyParams
#define ATMOSH_BIND_MS_TABLE 14   // float: multiple-scattering table, log Psi [altitude][sun][wavelength] (ms_approx)

// The passes run one invocation per item in work groups of ATMOSH_ITEM_GROUP_SIZE, as a grid
// of groups_x x groups_y groups (groups_x <= kMaxGroupsX, within every driver's limit;
// gpu::dispatch_items); item_index is the item of the invocation (x, y) (the shaders'
// gl_GlobalInvocationID.xy); items beyond the last have no work.
#define ATMOSH_ITEM_GROUP_SIZE 64  // a macro: GLSL 4.30 takes no constant in layout()
const int kMaxGroupsX = 32768;
ATMOSH_FN int item_index(int x, int y, int groups_x) { return y * groups_x * ATMOSH_ITEM_GROUP_SIZE + x; }

// Row of the spectral buffer: extinction of constituent c (rows 0..2), its
// scattering coefficient (rows 3..5), the solar irradiance (row 6); nw per row.
ATMOSH_FN int sky_spectral(int row, int nw, int i) { return row * nw + i; }

// Entry (shell k, direction j, constituent c) of a table of n directions starting at base.
ATMOSH_FN int lut_table_entry(int base, int n, int k, int j, int c) { return base + (k * n + j) * 3 + c; }

// The nodes of a closed-form column along a ray (PiecewiseLinearColumn: node radius [m],
// value, slope to the next node [1/m]; n < 2: none) and of quadratic ramps
// (QuadraticRampsColumn: radius [m], half curvature [1/m^2]), as
// piecewise_linear_column and quadratic_ramps_column take them.
struct GpuLinearNodes {
  float radius[kMaxLinearNodes];
  float value[kMaxLinearNodes];
  float slope[kMaxLinearNodes];
  int n;
};
struct GpuRamps {
  float radius[kMaxLinearNodes];
  float half_curv[kMaxLinearNodes];
  int n;
};

struct GpuSkyParams {
  // Geometry in double [m]: ground and top radius, the observer's radius, and
  // sqrt(T^2 - R^2) (the table's largest rho).
  double ground_radius_d;
  double top_radius_d;
  double observer_radius_d;
  double horizon_rho_d;
  // The view ray's cut radii (SkyIntegrator::cut_radii), the Gauss-Legendre rule of a
  // part on [-1, 1] and the part column weights (sky_part_column_weights).
  // real_array: double, stored as uvec2 in GLSL (shared/view_ray.glsl.hpp), same layout.
  real_array cut_radii[kMaxCutSpheres];
  real_array gauss_x[kMaxPartNodes];
  real_array gauss_w[kMaxPartNodes];
  real_array part_w[kMaxPartWeights];
  double build_scale_height;       // the table build's scale height (OpticalDepthLut::build_scale_height)
  // The same radii in float (closed-form columns, densities).
  float ground_radius;
  float top_radius;
  float scale_height[3];           // exponential constituents [m]
  float ext_max[3];                // largest extinction over the wavelengths [1/m]
  float phase_p[8];                // per scattering constituent: g / depolarisation, g2, weight, unused
  float sun_dir[3];                // unit vector toward the sun (observer's frame, z up)
  float max_piece_optical_depth;   // SkyOptions::max_piece_optical_depth
  float irradiance_scale;          // 1 / d_AU^2
  float albedo;                    // ground albedo
  GpuLinearNodes ozone;            // ozone's closed-form column
  GpuLinearNodes sub[2];           // OpticalDepthLut::subtracted(c)
  GpuRamps subq[2];                // OpticalDepthLut::subtracted_curvature(c)
  GpuRamps build_ramps[3];         // the same for the table build, by altitude: radius - R [m]
  int n_items;                     // invocations with work: pixels, lookups, rays, table entries
  int nw;                          // wavelengths
  int n_shells;                    // shells of the table
  int n_sun;                       // directions of the sun table
  int off_sun;                     // its offset into the tables (the sky builds no view tables)
  int n_cuts;                      // cut radii
  int off_nodes[3];                // piecewise-linear densities: altitudes[n], values[n] (n = 0: exponential)
  int n_nodes[3];
  int n_gauss;                     // Gauss-Legendre nodes per view-ray part
  int has_ext[3];                  // constituent present
  int tabulated[3];                // from the tables (log encoded)
  int phase_model[2];              // PhaseSpec::Model: 0 Rayleigh, 1 HG, 2 Cornette-Shanks, 3 double HG
  // The table build (lut_build.comp).
  int n_cross;                     // radii that cut a table ray
  int n_rule;                      // Gauss-Legendre nodes per sub-piece
  int n_dirs;                      // directions of the table being built
  int table_kind;                  // 0: toward the top, 1: toward the ground
  int log_encoded[3];              // tabulated with log encoding (output)
  // The all-orders multiple-scattering table (shared/ms_approx.glsl.hpp; sky.comp looks it
  // up, ms_build.comp builds it): rows and columns (ms_altitudes = 0: none, single
  // scattering), and the build's sphere rule and steps per ray (MultipleScatteringOptions).
  int ms_altitudes;
  int ms_suns;
  int ms_zenith;
  int ms_azimuths;
  int ms_steps;
  int ms_unused;                   // keeps the count of 4-byte members even (no padding)
};

// ATMOSH_GLSL_END

#undef ATMOSH_FN

}  // namespace atmosh::atmo::shared
