// atmosh/gpu/prt.hpp — per-pixel diffuse transfer by the depth-map method
// (rasterisation on the GPU, OpenGL 4.3 core through headless EGL).
//
// For a camera view of a triangle mesh the pass computes, for every pixel, the
// Monte Carlo diffuse transfer of the surface point it sees (atmosh/sh/prt.hpp):
//   T_i = (rho / pi) (4 pi / N) sum_s V(p, w_s) max(0, n . w_s) Y_i(w_s)
// over the N directions w_s of a SampleSet (the same set, and so the same estimator,
// as the CPU ray-casting reference prt::bake_pixels), with
//   1. a G-buffer pass: the mesh rasterised from the camera into float targets
//      (position, interpolated normal, albedo) — one surface point per pixel centre;
//   2. per sample direction w_s: a depth map of the whole mesh by parallel
//      (orthographic) projection along w_s, `depth_resolution`^2 texels covering the
//      bounding sphere (both faces drawn: open meshes cast shadows too); then a
//      full-screen pass over the G-buffer that tests each pixel against that depth
//      map and adds max(0, n . w_s) Y_i(w_s) into RGBA32F render targets with additive
//      blending (coefficients 4 to a target, the cosine sum for ambient occlusion
//      after the last coefficient; as many targets as the driver allows per pass,
//      more passes for more bands);
//   3. read-back; rho (4 pi / N) / pi is applied on the CPU in double.
// Visibility test: the point is moved off the surface along its normal by
// `offset` + half a depth-map texel and compared with the stored depth plus a
// slope bias of one texel times tan(angle to the normal) (capped at 8). Both
// biases are O(texel size): the transfer error against the ray-cast reference
// shrinks as the depth map grows (measured in docs/prt.md and tests/gpu/test_prt.cpp).
// Precision: float everywhere on the GPU (positions relative to the bounding-box
// centre); accumulation of N terms in float (relative ~N x 6e-8).
//
// Camera: a pinhole at `eye` looking along -back, `right`/`up` spanning the image,
// vertical half-angle tangent `tan_half_fov`, width/height pixels; pixel (row, col)
// (row 0 at the top) looks along -back + x right + y up with
// x = (2 (col + 0.5) / width - 1) tan_half_fov width / height,
// y = (1 - 2 (row + 0.5) / height) tan_half_fov — the rays of prt::bake_pixels.
// Requires a current Context; throws Unavailable (no EGL), ShaderError, or
// std::invalid_argument for inconsistent input (the caller validates the mesh).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gpu/context.hpp"
#include "atmosh/sh/prt.hpp"

namespace atmosh::gpu {

struct PrtMeshView {
  const std::vector<glm::dvec3>* positions = nullptr;
  const std::vector<glm::dvec3>* normals = nullptr;   ///< unit, per vertex
  const std::vector<double>* albedo = nullptr;        ///< per vertex, 0..1
  const std::vector<std::array<std::uint32_t, 3>>* triangles = nullptr;
};

struct PrtCamera {
  glm::dvec3 eye{0, 0, 1}, right{1, 0, 0}, up{0, 1, 0}, back{0, 0, 1};
  double tan_half_fov = 0.36397023426620234;  ///< tan(20 deg)
  int width = 256, height = 256;
};

struct PrtPixelOptions {
  int depth_resolution = 1024;  ///< depth-map texels per side, 16..16384
  bool visibility = true;       ///< false: unshadowed Monte Carlo estimate (no depth maps)
  double offset = 0;            ///< surface offset along the normal [mesh units] (the CPU ray offset)
};

struct PrtPixelResult {
  int width = 0, height = 0, bands = 0, samples = 0, depth_resolution = 0;
  std::vector<double> coeffs;  ///< [(row * width + col) * bands^2 + i], row 0 at the top
  std::vector<double> ao;      ///< cosine-weighted visible fraction per pixel
  std::vector<float> mask;     ///< 1 where a surface is seen
  int targets_per_pass = 0, passes_per_direction = 0;
  double seconds = 0;                ///< whole pass, upload to read-back
  double seconds_per_direction = 0;  ///< depth map + accumulation, per sample direction
};

PrtPixelResult prt_pixel_transfer(const Context& ctx, const PrtMeshView& mesh, const PrtCamera& camera,
                                  const sh::prt::SampleSet& samples, const PrtPixelOptions& opt);

}  // namespace atmosh::gpu
