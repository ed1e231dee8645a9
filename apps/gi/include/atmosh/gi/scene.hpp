// atmosh/gi/scene.hpp — scenes for diffuse global illumination: triangle meshes with a
// Lambertian material per triangle, a distant sun, an environment light (SH coefficients or
// an equirectangular image) and a pinhole camera.
//
// Units: lengths in the mesh's own unit (the Cornell box in millimetres, the prt built-ins
// unit scale); radiance in the units of the lights (emitted radiance, environment radiance,
// sun irradiance per steradian): a sun of irradiance E in W m^-2 gives radiance in
// W m^-2 sr^-1. Albedo in [0, 1] per RGB channel. Directions need not be unit length.
//
// Surfaces are two-sided Lambertian reflectors with the flat (geometric) triangle normal
// turned towards the incoming ray. Emission is two-sided unless Material::one_sided: then
// only the side the triangle's counter-clockwise winding faces (right-hand rule) emits.
//
// Frames: each scene names its `up` and `north` axes; a sun given by azimuth (from north
// towards east = north x up, degrees) and elevation (degrees above the horizon) is turned
// into a direction in that frame. The environment light is defined in the scene's frame
// as well: SH coefficients in the frame (x, y, z) = (east, north, up); the equirectangular
// image's polar angle from `up`, its azimuth from north towards east (environment_radiance()).
//
// Built-in scenes:
//   cornell-box     : the Cornell Program of Computer Graphics "Cornell Box Data"
//                     (www.graphics.cornell.edu/online/box/data.html): the published
//                     vertices in mm (floor, ceiling, back wall, red left wall, green right
//                     wall, short and tall blocks, the 130 x 105 mm light), camera at
//                     (278, 273, -800) looking along +z, up +y, focal length 35 mm on a
//                     25 x 25 mm film. Reflectances: the page's measured spectra read at
//                     three wavelengths, R = 612 nm, G = 548 nm, B = 464 nm (no colour-matching
//                     conversion); light: the page's emission spectrum (400:0, 500:8,
//                     600:15.6, 700:18.4) linearly interpolated at the same wavelengths.
//                     The light quad is lowered 0.5 mm below the ceiling (the page puts it in
//                     the ceiling's plane) and emits downwards only. Frame: up +y, north +z.
//   sphere-on-plane, box-occluder : the meshes of atmosh::prt::builtin_scene (z up, north
//                     +y), albedo per triangle the mean of the mesh's per-vertex albedo.
// Mesh files: atmosh::prt::load_mesh (.obj, .ply), grey albedo per triangle as above
// (default_albedo where the file gives none).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/prt/mesh.hpp"

namespace atmosh::gi {

struct Material {
  glm::dvec3 albedo{0.8};    ///< Lambertian reflectance per channel, 0..1
  glm::dvec3 emission{0.0};  ///< emitted radiance per channel, >= 0
  bool one_sided = false;    ///< emission only on the counter-clockwise (front) side
};

/// A distant light: `direction` points from the scene towards the sun; `irradiance` is the
/// irradiance on a surface facing it (per channel). angular_radius 0 = a point (delta) light;
/// > 0: a disc of uniform radiance E / (pi sin^2 r) (so its irradiance at normal incidence is E).
struct Sun {
  glm::dvec3 direction{0, 0, 1};
  glm::dvec3 irradiance{0.0};
  double angular_radius = 0;  ///< radians, 0 .. 0.5
};

/// Equirectangular environment image: row 0 at polar angle 0 (the scene's up), rows step the
/// polar angle uniformly to pi; column c covers azimuth [2 pi c / width, 2 pi (c + 1) / width)
/// from north towards east. Nearest texel (piecewise-constant radiance). rgb[c][row * width + col].
struct EnvironmentMap {
  int width = 0, height = 0;
  std::array<std::vector<float>, 3> rgb;
};

struct Camera {
  glm::dvec3 eye{0, 0, 0};
  glm::dvec3 forward{0, 0, -1};  ///< view direction
  glm::dvec3 up{0, 1, 0};        ///< roughly up on the image
  double vertical_fov_deg = 40;  ///< full angle, 0 < fov < 180
};

struct Scene {
  prt::Mesh mesh;                       ///< geometry (its albedo/normals are not used)
  std::vector<std::uint32_t> material;  ///< per triangle, index into materials
  std::vector<Material> materials;
  std::optional<Sun> sun;
  int env_bands = 0;                            ///< SH environment: bands (0 = none)
  std::array<std::vector<double>, 3> env_sh;    ///< per channel, env_bands^2 coefficients (basis.hpp)
  std::optional<EnvironmentMap> env_map;        ///< equirect environment (adds to the SH one)
  glm::dvec3 up{0, 0, 1}, north{0, 1, 0};       ///< the scene's frame (unit, orthogonal)
  Camera camera;                                ///< default view
  std::string name;
};

/// Names accepted by builtin_scene: cornell-box, sphere-on-plane, box-occluder.
std::vector<std::string> builtin_scene_names();
/// A built-in scene (see above); InputError naming an unknown name. `resolution`: tessellation
/// of the prt built-ins (4..4096); the Cornell box is its published quads, two triangles each.
Scene builtin_scene(const std::string& name, int resolution = 32);
/// A mesh file (.obj, .ply via atmosh::prt::load_mesh), grey Lambertian, no lights; z up,
/// north +y; camera as atmosh::prt::PixelCamera with view direction (1, -1.6, 1.1).
Scene scene_from_mesh(const std::filesystem::path& file, double default_albedo = 0.8);
/// Scene from a mesh, one material for every triangle; camera as for scene_from_mesh.
Scene scene_from_mesh(const prt::Mesh& mesh, const Material& material);

/// Direction of a sun at azimuth / elevation (degrees) in the scene's frame. InputError for
/// non-finite angles or an elevation outside [-90, 90].
glm::dvec3 sun_direction(const Scene& scene, double azimuth_deg, double elevation_deg);
/// Environment radiance arriving from direction `dir` (towards the light), per channel:
/// sum_i c_i Y_i(dir') (negative lobes as given) plus the equirect texel, where dir' is dir
/// expressed in the frame (east, north, up) so that SH "+z" is the scene's up.
glm::dvec3 environment_radiance(const Scene& scene, const glm::dvec3& dir);
/// An equirect environment from an EXR with channels R, G, B (atmosh::io::read_exr).
EnvironmentMap read_environment_map(const std::filesystem::path& exr);

/// Throws InputError (one line naming the fault) for: an empty or invalid mesh, a material
/// count / index mismatch, albedo outside [0, 1] or emission < 0 or not finite, a bad sun,
/// environment coefficients of the wrong length, a bad camera.
void validate(const Scene& scene);
/// The triangles whose material emits (emission summed over the channels > 0).
std::size_t emitting_triangles(const Scene& scene);
/// Throws InputError (one line naming the fault) for an image size outside 1..16384 a side
/// or a camera without a finite eye, with forward and up parallel (or zero), or with a
/// field of view outside (0, 180) degrees: what every renderer checks before its work.
void check_view(const Camera& camera, int width, int height);

}  // namespace atmosh::gi
