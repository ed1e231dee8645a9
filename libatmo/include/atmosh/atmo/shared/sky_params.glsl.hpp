// atmosh/atmo/shared/sky_params.glsl.hpp — the parameter block of the GPU's
// atmosphere passes (gpu/shaders/sky_lib.glsl and the shaders assembled after it:
// sky.comp, sun_lookup.comp, lut_build.comp, ozone_check.comp), declared once for
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

namespace atmosh::atmo::shared {

// ATMOSH_GLSL_BEGIN

struct GpuSkyParams {
  // Geometry in double [m]: ground and top radius, the observer's radius, and
  // sqrt(T^2 - R^2) (the table's largest rho).
  double ground_radius_d;
  double top_radius_d;
  double observer_radius_d;
  double horizon_rho_d;
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
  int n_items;                     // invocations with work: pixels, lookups, rays, table entries
  int nw;                          // wavelengths
  int n_shells;                    // shells of the table
  int n_sun;                       // directions of the sun table
  int off_sun;                     // its offset into the tables (the sky builds no view tables)
  int off_den;                     // float shells: inverse Lagrange denominators
  int off_cuts;                    // double shells: view-ray cut radii
  int n_cuts;
  int off_oz;                      // ozone's closed-form nodes (radius, value, slope)
  int n_oz;
  int off_sub[2];                  // OpticalDepthLut::subtracted(c) nodes; n < 2: none
  int n_sub[2];
  int off_subq[2];                 // OpticalDepthLut::subtracted_curvature(c): radius[n], half_curv[n]
  int n_subq[2];
  int off_nodes[3];                // piecewise-linear densities: altitudes[n], values[n] (n = 0: exponential)
  int n_nodes[3];
  int n_gauss;                     // Gauss-Legendre nodes per view-ray part
  int has_ext[3];                  // constituent present
  int tabulated[3];                // from the tables (log encoded)
  int phase_model[2];              // 0 Rayleigh, 1 HG, 2 Cornette-Shanks, 3 double HG
  // The table build (lut_build.comp).
  int n_cross;                     // radii that cut a table ray
  int n_rule;                      // Gauss-Legendre nodes per sub-piece
  int n_dirs;                      // directions of the table being built
  int table_kind;                  // 0: toward the top, 1: toward the ground
  int log_encoded[3];              // tabulated with log encoding (output)
  int tab_present[3];              // tabulated (OpticalDepthLut's present_)
  int is_exponential[3];           // scale heights in scale_height[]
  int off_q[3];                    // OpticalDepthLut::subtracted_curvature(c): altitude[n], half_curv[n]
  int n_q[3];
};

// ATMOSH_GLSL_END

}  // namespace atmosh::atmo::shared
