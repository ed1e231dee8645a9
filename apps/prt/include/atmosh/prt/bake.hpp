// atmosh/prt/bake.hpp — per-vertex transfer bakes with Embree 3 ray casting, transfer
// files, relighting images.
//
// A bake computes, for every vertex of a validated mesh, the diffuse transfer vector
// of atmosh/sh/prt.hpp (L bands, L^2 coefficients, SH convention of basis.hpp):
//   unshadowed     : exact closed form (no rays);
//   shadowed       : one occlusion ray per sample direction above the tangent plane;
//   interreflected : one closest-hit ray per such direction, then `bounces` bounces.
// Rays start at the vertex offset by 1e-4 x the bounding-box diagonal along the
// normal (and along the ray) to avoid self-hits; a hit at distance < that offset does
// not count (so occluders nearer than that are missed; rays are cast in float32 by
// Embree). Accuracy: the Monte Carlo error of atmosh/sh/prt.hpp (about 1e-2 of the
// band-0 value at 2025 samples; `atmosh prt converge` measures it per mesh) plus the
// tessellation of the mesh. The sample set is jittered strata x strata (default 45 -> 2025), seeded:
// the same inputs and seed give the same transfer on any thread count.
// Threads: `threads` workers (0 = the CPUs this process may use: atmosh::resolve_threads) take vertex blocks from a
// shared counter; progress(fraction) is called from the calling thread about every
// 1% (the library never prints).
//
// Per-pixel transfer: bake_pixels() computes it on the CPU by ray casting (the
// reference) or, with `Device::gpu`, by the depth-map method of atmosh/gpu/prt.hpp
// (rasterisation through headless EGL; same camera, same sample set, so the two differ
// only by the depth-map visibility test — an error that shrinks with
// `depth_resolution`). Per-vertex bakes are CPU only.
//
// Transfer files (.ply, ASCII, written atomically through atmosh::io): the mesh with
// per-vertex properties x y z nx ny nz albedo ao t0 ... t{L^2-1} (float, 9 significant
// digits) and the faces; header comments "atmosh_prt bands L", "atmosh_prt mode M",
// "atmosh_prt samples N", "atmosh_prt seed S", "atmosh_prt bounces K" and provenance
// lines "atmosh:key value". read_transfer() reads exactly this layout.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "atmosh/io/provenance.hpp"
#include "atmosh/prt/mesh.hpp"
#include "atmosh/sh/prt.hpp"

namespace atmosh::prt {

enum class Device { cpu, gpu };
Device parse_device(const std::string& name);  ///< "cpu" | "gpu"

struct BakeOptions {
  int bands = 3;                       ///< L (L^2 coefficients), 1..16
  int strata = 45;                     ///< jittered strata per side (samples = strata^2)
  std::uint64_t seed = 1;
  sh::prt::TransferMode mode = sh::prt::TransferMode::shadowed;
  int bounces = 2;                     ///< interreflected only
  double default_albedo = 0.8;         ///< used where the mesh has none
  int threads = 0;                     ///< 0..1024; 0 = the CPUs this process may use (atmosh::resolve_threads)
  Device device = Device::cpu;
  int depth_resolution = 1024;         ///< GPU per-pixel method: depth-map texels per side (16..16384)
  std::function<void(double)> progress;  ///< optional, called with 0..1
};

struct Transfer {
  Mesh mesh;                           ///< with albedo filled in
  int bands = 0;
  sh::prt::TransferMode mode = sh::prt::TransferMode::shadowed;
  int samples = 0, bounces = 0;
  std::uint64_t seed = 0;
  std::vector<double> coeffs;          ///< vertex_count x bands^2, row-major
  std::vector<double> ao;              ///< per vertex, cosine-weighted visible fraction 0..1
  std::vector<double> bounce_energy;   ///< interreflected: sum |T^b|^2 per bounce b = 0..K
  std::uint64_t rays = 0;              ///< rays cast
  double ray_seconds = 0;              ///< wall time of the ray-casting phase
  const double* at(std::size_t v) const { return coeffs.data() + v * static_cast<std::size_t>(bands) * bands; }
};

/// Embree scene of a mesh (thread-safe queries). Ray offsets as described above.
class RayScene {
 public:
  explicit RayScene(const Mesh& mesh);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;
  /// True if the ray org + t dir, t in (tnear, tfar), hits nothing.
  bool unoccluded(const glm::dvec3& org, const glm::dvec3& dir, double tnear, double tfar = 1e30) const;
  /// Closest hit: returns false if none; else triangle index and barycentrics (u, v, t).
  bool intersect(const glm::dvec3& org, const glm::dvec3& dir, double tnear, std::uint32_t& prim, float& u, float& v,
                 double& t) const;
  double offset() const { return offset_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double offset_ = 0;
};

/// Bakes per-vertex transfer. InputError for bad options or a GPU request (per-pixel only).
Transfer bake(const Mesh& mesh, const BakeOptions& opt);

/// The camera of bake_pixels and render_vertex_values: looks at the bounding-box centre
/// from direction view_dir (from the centre towards the camera), 40 degree vertical field
/// of view, far enough for the bounding sphere to fit. Pixel (row, col), row 0 at the top,
/// sees along ray(row, col). InputError for a bad size or direction.
struct PixelCamera {
  glm::dvec3 eye, w, right, up;  ///< w: unit, towards the camera; the view looks along -w
  double tan_half_fov = 0, aspect = 1;
  int width = 1, height = 1;
  PixelCamera(const Mesh& mesh, int width, int height, const glm::dvec3& view_dir);
  glm::dvec3 ray(int row, int col) const;
};

/// Per-pixel transfer seen by a PixelCamera: for each pixel, the first surface point
/// on the primary ray, with the barycentrically interpolated normal and albedo, gets the
/// transfer of `opt.mode` (unshadowed or shadowed). CPU: Embree ray casting (unshadowed:
/// the closed form); GPU: the depth-map method (unshadowed: the same Monte Carlo sum
/// without the visibility test). Pixels that see no surface have mask 0 and zero
/// transfer. coeffs[(row * width + col) * L^2 + i]. A GPU request throws
/// gpu::Unavailable when no EGL device exists (or InputError when built without gpu/).
struct PixelTransfer {
  int width = 0, height = 0, bands = 0, samples = 0;
  std::vector<double> coeffs;
  std::vector<double> ao;      ///< cosine-weighted visible fraction per pixel
  std::vector<float> mask;     ///< 1 where a surface is seen
  Device device = Device::cpu;
  std::uint64_t rays = 0;      ///< CPU
  double ray_seconds = 0;      ///< CPU: ray-casting phase; GPU: the whole pass
  int depth_resolution = 0;    ///< GPU
  double seconds_per_direction = 0;  ///< GPU: depth map + accumulation per sample direction
};
PixelTransfer bake_pixels(const Mesh& mesh, const BakeOptions& opt, int width, int height, const glm::dvec3& view_dir);

/// Writes / reads a transfer file (.ply).
void write_transfer(const std::filesystem::path& file, const Transfer& t, const io::Provenance& prov);
Transfer read_transfer(const std::filesystem::path& file);

/// Relit exit radiance per vertex and channel: out[v][c] = T_v . light[c].
std::vector<std::vector<double>> relight_vertices(const Transfer& t, const std::vector<std::vector<double>>& light);

/// A camera image of the mesh by ray casting: each pixel shows the barycentric
/// interpolation of per-vertex values (channels), background 0. The camera is
/// PixelCamera(mesh, width, height, view_dir). Planar channel-major output
/// [c][row * width + col], row 0 at the top; values[v][c] per vertex.
std::vector<std::vector<float>> render_vertex_values(const RayScene& scene, const Mesh& mesh,
                                                     const std::vector<std::vector<double>>& values, int width,
                                                     int height, const glm::dvec3& view_dir);

}  // namespace atmosh::prt
