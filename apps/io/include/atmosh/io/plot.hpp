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
