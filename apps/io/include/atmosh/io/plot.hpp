// atmosh/io/plot.hpp — PNG figures drawn with OpenCV.
//
// Line and scatter plots with axes, "nice" ticks, labels with units, a legend,
// linear or log10 axes and several series; colour-swatch strips for sky colours;
// tone-mapped images. Non-finite points (and non-positive ones on a log axis) are
// skipped, never drawn. All writes are atomic.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace atmosh::io {

struct Series {
  enum class Style { Line, Scatter, LineMarkers };
  std::string label;
  std::vector<double> x, y;
  Style style = Style::LineMarkers;
  // sRGB colour in [0,1]; negative r means "use the palette".
  std::array<double, 3> color{-1.0, 0.0, 0.0};
};

struct PlotSpec {
  std::string title;
  std::string x_label;  // include units, e.g. "run time [s]"
  std::string y_label;
  bool log_x = false;
  bool log_y = false;
  std::vector<Series> series;
  int width = 1200;
  int height = 800;
};

void write_plot_png(const std::filesystem::path& file, const PlotSpec& spec);

// Band energy sum_m c_lm^2 of SH coefficients against band l, one series per channel
// (log y). The coefficients of a quantity in `value_units` (e.g. "cd/m^2") carry
// value_units x sr, so the axis reads "energy sum_m c_lm^2 [(<value_units> sr)^2]":
// one convention for every band-energy plot. energy[c][l]: channel c, band l.
PlotSpec band_energy_plot_spec(const std::string& title, const std::vector<std::string>& names,
                               const std::vector<std::vector<double>>& energy, const std::string& value_units);

// A plot as write_plot_png draws it. On a log axis a series with no positive value
// cannot be drawn: it is kept, its points moved to the floor of that axis (y) and
// drawn as markers, its label saying so, and a note (drawn under the title) gives the
// reason; a series with some non-positive values gets a note counting the points
// left out. Series with no finite point at all are left out of the legend, with a note.
struct PreparedPlot {
  PlotSpec spec;
  std::vector<std::string> notes;
};
PreparedPlot prepare_plot(const PlotSpec& spec);

// When on, write_plot_png also writes <file>.plot.json: the prepared plot (title, axis
// labels and scales, every series' label, style and points, the notes) — the data a
// figure shows, for readers and tests. Off by default; the CLI turns it on when the
// environment variable ATMOSH_PLOT_DATA is set to 1.
void set_plot_data_files(bool on);
// The JSON text of a prepared plot (numbers in the shortest round-trip form).
std::string plot_json(const PreparedPlot& plot);

// The side file of a tone-mapped image: writes <png>.json recording the operator,
// the exposure, the rule that chose it and the source file. Returns its path.
std::filesystem::path write_tone_map_side_file(const std::filesystem::path& png, const std::string& tone_map,
                                               double exposure, const std::string& exposure_rule,
                                               const std::string& source);

struct Swatch {
  std::array<double, 3> srgb;  // display sRGB in [0,1] (already gamma-encoded)
  std::string label;
};
// A horizontal strip of colour patches with labels beneath.
void write_swatch_png(const std::filesystem::path& file, const std::string& title,
                      const std::vector<Swatch>& swatches);

// Bytes write_tonemapped_png holds for a width x height image (the 8-bit image and
// the encoder's buffer), for a budget check before the work. Saturates at SIZE_MAX.
std::size_t tonemapped_png_bytes(int width, int height);
// 8-bit sRGB PNG from linear RGB (planar, row 0 at top): value * exposure, then
// the chosen operator ("clamp" or "reinhard"), then the sRGB transfer curve.
void write_tonemapped_png(const std::filesystem::path& file, int width, int height,
                          const std::vector<float>& r, const std::vector<float>& g,
                          const std::vector<float>& b, double exposure,
                          const std::string& op = "reinhard");

}  // namespace atmosh::io
