// Private to atmosh::gi: what the probe grid, the radiosity volume and the light propagation
// volume share — the trilinear lookup of a regular grid of cell centres, the receivers'
// packing for the GPU passes, and the image made from a G-buffer's shaded receivers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/radiosity.hpp"

namespace atmosh::gi::detail {

// The 8 cells around p of a grid of g.n per axis over [g.lo, g.hi] (cell i centred at
// (i + 1/2) / n of the extent) and their trilinear weights, p clamped to the centres' span.
template <class Grid>
void trilinear_corners(const Grid& g, const glm::dvec3& p, std::size_t idx[8], double w[8]) {
  int i0[3], i1[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    const double ext = g.hi[a] - g.lo[a];
    double x = ext > 0 ? (p[a] - g.lo[a]) / ext * g.n - 0.5 : 0.0;
    if (!std::isfinite(x)) x = 0;
    x = std::clamp(x, 0.0, static_cast<double>(g.n - 1));
    i0[a] = std::min(static_cast<int>(std::floor(x)), g.n - 1);
    i1[a] = std::min(i0[a] + 1, g.n - 1);
    f[a] = x - i0[a];
  }
  for (int c = 0; c < 8; ++c) {
    const int ii = c & 1 ? i1[0] : i0[0], jj = c & 2 ? i1[1] : i0[1], kk = c & 4 ? i1[2] : i0[2];
    w[c] = (c & 1 ? f[0] : 1 - f[0]) * (c & 2 ? f[1] : 1 - f[1]) * (c & 4 ? f[2] : 1 - f[2]);
    idx[c] = (static_cast<std::size_t>(kk) * g.n + jj) * g.n + ii;
  }
}

// The receivers as the GPU passes read them: 15 floats each (position, normal, albedo,
// emission, direct irradiance); at least one receiver's room so the buffer is never empty.
inline std::vector<float> pack_receivers(const RadiosityReceivers& r) {
  const std::size_t nr = r.size();
  std::vector<float> rec(std::max<std::size_t>(nr, 1) * 15, 0.0f);
  for (std::size_t i = 0; i < nr; ++i)
    for (int c = 0; c < 3; ++c) {
      rec[i * 15 + c] = static_cast<float>(r.position[i][c]);
      rec[i * 15 + 3 + c] = static_cast<float>(r.normal[i][c]);
      rec[i * 15 + 6 + c] = static_cast<float>(r.albedo[i][c]);
      rec[i * 15 + 9 + c] = static_cast<float>(r.emission[i][c]);
      rec[i * 15 + 12 + c] = static_cast<float>(r.direct[i][c]);
    }
  return rec;
}

// The first nr radiances of a GPU pass's output, 4 floats (R, G, B, unused) per receiver.
inline std::vector<glm::dvec3> unpack_rgb(const std::vector<float>& out, std::size_t nr) {
  std::vector<glm::dvec3> L(nr);
  for (std::size_t i = 0; i < nr; ++i) L[i] = {out[i * 4], out[i * 4 + 1], out[i * 4 + 2]};
  return L;
}

// One-sample image of width x height from a G-buffer: the background where no receiver
// is, L[k] at receiver k's pixel; stderr_ zero. stats.rays from the G-buffer; the caller
// sets stats.seconds.
inline RadianceImage gbuffer_image(const RadiosityGBuffer& g, const std::vector<glm::dvec3>& L, int width,
                                   int height) {
  RadianceImage img;
  img.width = width;
  img.height = height;
  img.samples = 1;
  const std::size_t np = static_cast<std::size_t>(width) * height;
  for (int c = 0; c < 3; ++c) {
    img.mean[c].assign(np, 0.0f);
    img.stderr_[c].assign(np, 0.0f);
    for (std::size_t i = 0; i < np; ++i) img.mean[c][i] = static_cast<float>(g.background[i][c]);
    for (std::size_t k = 0; k < L.size(); ++k) img.mean[c][g.pixel[k]] = static_cast<float>(L[k][c]);
  }
  img.stats.rays = g.rays;
  return img;
}

}  // namespace atmosh::gi::detail
