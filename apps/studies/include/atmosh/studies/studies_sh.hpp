// atmosh/studies/studies_sh.hpp — spherical-harmonic studies and steps as library
// calls: an EXR prepared for projection, its projection by any sampling method, the
// projection methods' error against run time (converge sh), the band-energy table,
// the reconstruction image, and the main job's synthetic sky and window table. No
// printing, no file names chosen inside: writers take the paths.
#pragma once

#include <cstdint>
#include <filesystem>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/sh/projection.hpp"
#include "atmosh/studies/study_table.hpp"

namespace atmosh::studies {

// An image ready for projection: planar float channels (R, G, B as r, g, b when the
// EXR has them, else every channel by its lower-case name), finite.
struct ShImage {
  int width = 0, height = 0;
  std::vector<std::string> names;
  std::vector<float> planar;  // channel-major
  bool cross = false;         // a 4:3 / 3:4 cube cross, else equirect (2:1)
  std::string value_units;    // the EXR's value_units attribute, if any
  sh::ImageView view() const { return {width, height, static_cast<int>(names.size()), planar.data()}; }
};

// layout: "equirect", "cross" or "auto" (2:1 is equirect, 4:3 / 3:4 a cross).
// InputError naming the file for an image without channels, a NaN or infinite pixel,
// a shape that fits no layout under "auto", or an unknown layout; max_bytes bounds
// what the EXR reader allocates (io::read_exr).
ShImage load_sh_image(const std::filesystem::path& file, const std::string& layout, std::size_t max_bytes);
// The image's coefficients, one vector per channel (sh::project_* by the options' method).
sh::Channels project_sh_image(const ShImage& image, int bands, const sh::ProjectOptions& options);

// Error of coefficients against reference ones over all channels:
// max |c - c_ref| / max |c_ref| and ||c - c_ref||_2 / ||c_ref||_2.
struct ShError {
  double max_rel = 0.0, rms_rel = 0.0;
};
ShError compare_sh(const sh::Channels& c, const sh::Channels& reference);

// converge sh: each projection method and sample count against the image's exact
// quadrature (Fejer's first rule on equirect pixel rings, texel solid angles on a cube
// cross): rows fejer-quadrature / cube-texel-integration (the reference, error 0),
// jittered (n x n strata), uniform (n samples), gauss-grid-bilinear (equirect only),
// one thread each, extra column samples. `source` names the input in the provenance.
StudyTable converge_sh(const ShImage& image, int bands, bool quick, std::uint64_t seed, const std::string& source);

// Band energy sum_m c_lm^2 and the cumulative energy fraction of each channel:
// BANDS.csv (l, energy_<name>..., fraction_<name>...) and, when png is not empty, the
// log plot of the energies.
void write_sh_bands(const io::ShCoefficients& c, const std::filesystem::path& csv, const std::filesystem::path& png,
                    const io::Provenance& provenance);
// The coefficients rendered to an equirect EXR of width x width/2 (channels R, G, B
// for r, g, b coefficient columns, else the columns' names).
void write_sh_reconstruction(const std::filesystem::path& file, const io::ShCoefficients& c, int width,
                             const io::Provenance& provenance);

// The main job's synthetic sky-like radiance, width x width/2 equirect, R G B: a
// gradient from horizon to zenith, a dark ground, and a normalised von Mises-Fisher
// sun lobe (kappa 400) at elevation 30 deg, azimuth 40 deg from +x.
io::ExrImage synthetic_sky(int width);

// What each SH window costs in accuracy, on one channel of `bands` bands: the L2
// change of the windowed coefficients, the ringing left (minimum of the windowed
// delta), and the largest change of the irradiance over a 64 x 32 grid of directions.
struct ShWindowRow {
  std::string window;
  double delta_min_rel = 0.0, l2_change_rel = 0.0, irradiance_max_change_rel = 0.0;
};
std::vector<ShWindowRow> sh_window_study(const std::vector<double>& channel, int bands);
// The window table (window, delta_min_rel, l2_change_rel, irradiance_max_change_rel):
// the one place its columns are made (the CSV, the Python DataFrame).
io::CsvTable sh_window_table(const std::vector<ShWindowRow>& rows);
void write_sh_windows(const std::vector<ShWindowRow>& rows, const std::filesystem::path& file,
                      const io::Provenance& provenance);

// `atmosh sh eval`: the unit direction of --dir "x,y,z" (InputError naming --dir for
// three numbers of zero length), and the coefficients' values there as JSON: bands,
// direction, values (one per channel, by name).
glm::dvec3 sh_eval_direction(const std::string& text);
nlohmann::json sh_eval_json(const io::ShCoefficients& c, const glm::dvec3& direction);
// `atmosh sh gaunt L1 M1 L2 M2 L3 M3`: the Gaunt coefficient (integral of the three real
// orthonormal SH over the sphere) as JSON, its indices checked (0 <= l <= 100000,
// |m| <= l; InputError naming L1 ... M3).
nlohmann::json gaunt_json(const std::vector<int>& lm);

// The SH step of the main job (`atmosh demo`) into `dir`: the synthetic sky
// (sh_sky_input.exr; 512 wide, 16 bands; quick: 128, 8), its coefficients, their
// reconstruction and irradiance, band energies, the windows' costs and converge_sh.
// max_image_bytes: the memory the input image may take when read back. Returns the
// files in order.
std::vector<std::filesystem::path> demo_sh(const std::filesystem::path& dir, bool quick, std::size_t max_image_bytes);

}  // namespace atmosh::studies
