// atmosh/gpu/cube_raster.hpp — cube maps of a mesh's surface radiance rasterised at many
// centres (OpenGL 4.3 core through headless EGL): the radiance probes of atmosh::gi.
//
// The mesh carries per vertex its position, the geometric normal of its surface (the
// counter-clockwise side is the front) and the radiance leaving each side (RGB, front and
// back). For every centre q the six faces of a cube map in libsh's layout
// (atmosh/sh/projection.hpp: faces +X -X +Y -Y +Z -Z, OpenGL orientation, texel (row r,
// column c) of an N x N face looking along face_direction(f, u, v) with
// u = 2 (c + 1/2) / N - 1, v = 2 (r + 1/2) / N - 1) are rasterised with depth test: texel
// (r, c) holds the radiance of the nearest surface its centre ray from q meets at a depth
// (along the face's axis) in [near, far], the per-vertex values interpolated
// perspective-correctly (= the barycentric interpolation at the ray's hit point), the
// side chosen by the sign of normal . (hit - q); alpha 1 there, RGBA 0 where no surface is
// (the caller fills in the environment). Precision: float on the GPU, positions relative
// to the bounding-box centre; a texel whose centre ray passes within float rounding of a
// triangle's edge may see the neighbouring surface (silhouettes, creases).
// All faces of a batch of centres share one RGBA32F atlas and one depth buffer (32-bit
// float); one draw of the whole mesh per face.
// Requires a current Context; throws Unavailable (no EGL), ShaderError, or
// std::invalid_argument for inconsistent input.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "atmosh/gpu/context.hpp"

namespace atmosh::gpu {

class Program;  // atmosh/gpu/program.hpp

/// Floats per vertex of a CubeRasterMesh: position (3), normal (3), front RGB (3), back RGB (3).
inline constexpr int kCubeRasterVertexFloats = 12;

struct CubeRasterMesh {
  std::vector<float> vertices;         ///< kCubeRasterVertexFloats per vertex, positions relative to `origin`
  std::vector<std::uint32_t> indices;  ///< 3 per triangle
  std::array<double, 3> origin{0, 0, 0};
};

struct CubeRasterOptions {
  int size = 8;          ///< texels per face edge, 1..2048
  double near = 1e-3;    ///< depth range along each face's axis [mesh units], 0 < near < far
  double far = 1e3;
};

struct CubeRasterResult {
  /// [((centre * 6 + face) * size + row) * size + col] * 4 + channel (R, G, B, alpha)
  std::vector<float> texels;
  int size = 0;
  double seconds = 0;  ///< upload, draws and read-back (program compilation excluded)
};

/// The cube maps seen at `centres` (mesh units, absolute).
CubeRasterResult render_cube_maps(const Context& ctx, const CubeRasterMesh& mesh,
                                  const std::vector<std::array<double, 3>>& centres, const CubeRasterOptions& opt);

/// A mesh drawn once by a caller's vertex + fragment program into an RGBA32F target of
/// width x height with depth test (32-bit float depth, cleared to 1; no culling): the
/// vertices carry `attribute_sizes[a]` floats for attribute location a, interleaved in that
/// order; the caller has made `program` current and set its uniforms and storage buffers.
/// Returns RGBA per pixel, row 0 at the top ([(row * width + col) * 4 + channel]), 0 where
/// nothing was drawn. `seconds`: upload, draw and read-back.
std::vector<float> render_mesh_rgba(const Context& ctx, const Program& program, const std::vector<float>& vertices,
                                    const std::vector<int>& attribute_sizes, const std::vector<std::uint32_t>& indices,
                                    int width, int height, double* seconds = nullptr);

/// The same, kept for repeated frames: the mesh uploaded and the target made once; draw()
/// renders with the caller's current program (as render_mesh_rgba) and reads back.
class MeshRaster {
 public:
  MeshRaster(const Context& ctx, const std::vector<float>& vertices, const std::vector<int>& attribute_sizes,
             const std::vector<std::uint32_t>& indices, int width, int height);
  ~MeshRaster();
  MeshRaster(const MeshRaster&) = delete;
  MeshRaster& operator=(const MeshRaster&) = delete;
  std::vector<float> draw(const Program& program) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Face f's frame: the direction of (u, v) is u * axis_u + v * axis_v + axis_w (libsh's layout).
void cube_face_frame(int face, std::array<double, 3>& axis_u, std::array<double, 3>& axis_v,
                     std::array<double, 3>& axis_w);

}  // namespace atmosh::gpu
