// sky_impl.hpp (private to libatmo) — the view-ray types and the spectral loop of
// SkyIntegrator (sky.cpp); tests of the loop include it from libatmo/src.
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "atmosh/atmo/shared/view_ray.glsl.hpp"

namespace atmosh::atmo {

namespace detail {
// A view ray reduced to the planet-centred 2-D geometry, clipped to the atmosphere,
// and a quadrature node along it: the shared types (shared/view_ray.glsl.hpp), which
// the GPU's sky pass uses too.
using SkyRay = shared::SkyViewRay;
using SkyViewNode = shared::SkyViewNode;
// What the spectral loop needs of one quadrature node, in single precision
// (shared/view_ray.glsl.hpp, sky_node_terms): the column from the sun through the node
// to the observer per constituent (Rayleigh, Mie, ozone) [m], and the node's
// scattering weights sr = rho_R p_R w, sm = rho_M p_M w.
using SkyNodeTerms = shared::SkyNodeTerms;
// The spectral loop of a view ray over `count` nodes, in order: for every wavelength
// i < n, acc[i] += sum over the nodes of exp(-tau_i) (cr[i] sr + cm[i] sm) with
// tau_i = er[i] x0 + em[i] x1 + eo[i] x2, where ext = [er | em | eo] and sca = [cr | cm]
// hold n values each [1/m]. The terms are formed in single precision (exp_neg_f:
// relative error ~1e-6 for tau <= 10, far below the quadrature's) and summed into the
// double accumulators node by node, so the result does not depend on how a ray's
// nodes are split into calls. Runs on AVX-512 (16 wavelengths per instruction) where
// atmosh::cpu_has_avx512(), else on AVX2/FMA or the baseline (atmosh/dispatch.hpp);
// the paths differ by float rounding only. n a multiple of sky_spectral_lanes() (16 on
// AVX-512, else 8) wastes no lane: the integrator pads its wavelengths with zero
// coefficients to it.
std::size_t sky_spectral_lanes();
void accumulate_sky_nodes(std::size_t n, const float* ext, const float* sca, const SkyNodeTerms* nodes,
                          std::size_t count, double* acc);
}  // namespace detail

}  // namespace atmosh::atmo
