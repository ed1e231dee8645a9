// atmosh/prt/mesh.hpp — triangle meshes for precomputed radiance transfer.
//
// Input: Wavefront OBJ (tinyobjloader; faces triangulated, material Kd -> albedo as the
// mean of its three components), PLY ASCII or binary (Open Asset Import Library; vertex
// colours -> albedo as the mean of r, g, b). Vertices are the file's positions (shared
// between faces); normals are always recomputed as area-weighted face-normal averages
// so that they are consistent with the geometry the rays see. Units: whatever the
// file uses (ray offsets scale with the bounding box); directions in the mesh frame.
//
// Built-in scenes (no download needed), z up, unit scale:
//   sphere-on-plane : a 4 x 4 plane (z = 0) and a sphere of radius 0.5 centred at z = 0.5
//   box-occluder    : a 4 x 4 floor, the four single-sheet walls of an open 1 x 1 x 1 box and
//                     a floating 1.6 x 1.6 plate (two sheets, 0.02 apart) above it
//   torus           : a torus, major radius 1, minor radius 0.35, axis z
//   sphere          : a lone sphere of radius 1 (convex: shadowed = unshadowed)
// `resolution` scales the tessellation (>= 4).
//
// validate() throws atmosh::InputError (one line naming the mesh and the fault) for an
// empty mesh, a non-finite vertex, an index out of range, a degenerate (repeated-index)
// triangle and a non-manifold edge (shared by more than two triangles).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace atmosh::prt {

struct Mesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;  ///< unit, per vertex
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<double> albedo;       ///< per vertex, 0..1 (empty: use a default)
  std::string name;                 ///< for messages
  std::size_t vertex_count() const { return positions.size(); }
};

/// Loads .obj or .ply (by extension); validates; computes normals. InputError on any fault.
Mesh load_mesh(const std::filesystem::path& file);
/// Built-in scene by name (see above). InputError for an unknown name.
Mesh builtin_scene(const std::string& name, int resolution = 32);
/// Names accepted by builtin_scene.
std::vector<std::string> builtin_scene_names();
/// Throws InputError for the faults listed above.
void validate(const Mesh& mesh);
/// Recomputes area-weighted vertex normals (vertices on no triangle get +z).
void compute_normals(Mesh& mesh);
/// Length of the bounding-box diagonal (for ray offsets).
double bounding_diagonal(const Mesh& mesh);

}  // namespace atmosh::prt
