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
  /// A background image (RGBA per pixel, row 0 at the top, as draw() returns) kept on the GPU:
  /// draw_resident() starts from it instead of 0.
  void set_background(const std::vector<float>& rgba);
  /// The draw of draw() without the read-back: the result stays in the target (background
  /// where nothing is drawn); read() reads it back (the only read-back of a resident frame).
  void draw_resident(const Program& program) const;
  std::vector<float> read() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The SH projection of radiance probes on the GPU, resident (no read-back between passes):
/// per run, the cube maps of every centre are rasterised as by render_cube_maps (at
/// `opt.size` = N S texels a side, batches of one atlas) and each batch is projected by the
/// compute pass gpu/shaders/gi_probe_project.comp into one shader storage buffer of SH
/// coefficients, as libsh's sh::project_cube does on the CPU: the basis at the centre of each
/// texel of the N x N map times the sum of its S x S sub-texels' radiance times their exact
/// solid angles (the shared block libsh/include/atmosh/sh/shared/cube.glsl.hpp, which
/// sh::cube_texel_solid_angle and sh::cube_face_point are), the environment `env` where no
/// surface is drawn; optionally a point sun's projection E Y_lm(s) added, and band l times
/// window[l]. Precision: float sums (about 1e-6 of the largest coefficient; the texel solid
/// angles in float lose ~1e-7 pi / (6 Omega) relative).
struct ProbeSun {
  bool on = false;
  std::array<double, 3> direction{0, 0, 1};   ///< towards the sun, unit
  std::array<double, 3> irradiance{0, 0, 0};  ///< at normal incidence, per channel
};

class ProbeProjector {
 public:
  /// `env`: 3 floats per texel of the N S cube ([(f N S + row) N S + col] * 3 + channel), the
  /// radiance where no surface is; `supersample` S divides opt.size; the output holds
  /// `stride` floats per probe and channel (stride >= max_bands^2), max_bands 1..16.
  ProbeProjector(const Context& ctx, const CubeRasterMesh& mesh, const std::vector<std::array<double, 3>>& centres,
                 const CubeRasterOptions& opt, int supersample, const std::vector<float>& env, int max_bands,
                 int stride);
  ~ProbeProjector();
  ProbeProjector(const ProbeProjector&) = delete;
  ProbeProjector& operator=(const ProbeProjector&) = delete;
  /// Rasterise and project (bands 1..max_bands; window: one weight per band, empty = 1).
  /// `split_seconds` (optional, 2 entries): the draws' and the projections' wall time, each
  /// batch's draws and projection then waited for (glFinish; for profiling).
  void run(int bands, const std::vector<double>& window, const ProbeSun& sun, double* split_seconds = nullptr) const;
  /// Binds the coefficient buffer ([(probe * 3 + channel) * stride + i]) to a storage binding.
  void bind_sh(unsigned binding) const;
  /// Reads the coefficients back (diagnostics and the CPU's use; not part of a resident frame).
  std::vector<float> read_sh() const;
  int stride() const;
  std::size_t probes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The sun's shadow map of gi_raster.hpp's G-buffer (orthographic depth along -s over the
/// bounding sphere of `radius` about the origin, prt_depth.{vert,frag}), kept on the GPU for
/// a later pass of the same context: `positions` a triangle soup (3 floats a vertex,
/// relative to the bounding-sphere centre).
class SunShadowMap {
 public:
  SunShadowMap(const Context& ctx, const std::vector<float>& positions, double radius, int resolution);
  ~SunShadowMap();
  SunShadowMap(const SunShadowMap&) = delete;
  SunShadowMap& operator=(const SunShadowMap&) = delete;
  /// Renders the depth map for the direction towards the sun (unit).
  void render(const std::array<double, 3>& direction) const;
  /// Binds the depth texture to texture unit `unit`; `light_proj` receives the column-major matrix.
  void bind(unsigned unit, float light_proj[16]) const;
  int resolution() const;
  double radius() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Face f's frame: the direction of (u, v) is u * axis_u + v * axis_v + axis_w (libsh's layout).
void cube_face_frame(int face, std::array<double, 3>& axis_u, std::array<double, 3>& axis_v,
                     std::array<double, 3>& axis_w);

}  // namespace atmosh::gpu
