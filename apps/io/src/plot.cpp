#include "atmosh/io/plot.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "atmosh/io/atomic.hpp"
#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

namespace {

// Okabe–Ito colour-blind-safe palette (sRGB), as BGR for OpenCV.
const cv::Scalar kPalette[] = {{178, 114, 0},  {0, 159, 230},  {115, 158, 0}, {167, 121, 204},
                               {0, 94, 213},   {233, 180, 86}, {66, 228, 240}, {0, 0, 0}};

cv::Scalar bgr(const std::array<double, 3>& c) {
  auto q = [](double v) { return std::clamp(v, 0.0, 1.0) * 255.0; };
  return {q(c[2]), q(c[1]), q(c[0])};
}

void save_png(const std::filesystem::path& file, const cv::Mat& img) {
  write_atomically(file, [&](const std::filesystem::path& tmp) {
    if (!cv::imwrite(tmp.string(), img)) throw std::runtime_error("cannot write PNG " + file.string());
  });
}

struct Axis {
  double lo, hi;
  bool log;
  double map(double v) const {  // to [0,1]
    if (log) return (std::log10(v) - lo) / (hi - lo);
    return (v - lo) / (hi - lo);
  }
};

double nice_step(double range, int target) {
  const double raw = range / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double nf = f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10;
  return nf * mag;
}

std::string tick_label(double v) {
  char buf[32];
  if (v == 0) return "0";
  const double a = std::fabs(v);
  if (a >= 1e-3 && a < 1e5)
    std::snprintf(buf, sizeof buf, "%.6g", v);
  else
    std::snprintf(buf, sizeof buf, "%.0e", v);
  return buf;
}

// Ticks: (value in axis space, label).
std::vector<std::pair<double, std::string>> make_ticks(const Axis& a) {
  std::vector<std::pair<double, std::string>> t;
  if (a.log) {
    const int d0 = static_cast<int>(std::ceil(a.lo - 1e-9)), d1 = static_cast<int>(std::floor(a.hi + 1e-9));
    const int stride = std::max(1, (d1 - d0 + 1) / 8);
    for (int d = d0; d <= d1; d += stride) {
      char buf[16];
      std::snprintf(buf, sizeof buf, "1e%d", d);
      t.emplace_back(static_cast<double>(d), buf);
    }
  } else {
    const double step = nice_step(a.hi - a.lo, 6);
    for (double v = std::ceil(a.lo / step) * step; v <= a.hi + step * 1e-9; v += step)
      t.emplace_back(v, tick_label(std::fabs(v) < step * 1e-9 ? 0.0 : v));
  }
  return t;
}

Axis fit_axis(const std::vector<double>& vals, bool log) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : vals) {
    if (!std::isfinite(v) || (log && v <= 0)) continue;
    const double w = log ? std::log10(v) : v;
    lo = std::min(lo, w);
    hi = std::max(hi, w);
  }
  if (!std::isfinite(lo)) {
    lo = 0;
    hi = 1;
  }
  if (hi - lo < 1e-12 * std::max(1.0, std::fabs(hi))) {
    lo -= log ? 0.5 : std::max(0.5, std::fabs(lo) * 0.1);
    hi += log ? 0.5 : std::max(0.5, std::fabs(hi) * 0.1);
  }
  if (log) {
    lo = std::floor(lo);
    hi = std::ceil(hi);
  } else {
    const double step = nice_step(hi - lo, 6);
    lo = std::floor(lo / step) * step;
    hi = std::ceil(hi / step) * step;
  }
  return {lo, hi, log};
}

void put_text(cv::Mat& img, const std::string& s, cv::Point p, double scale, int thick = 1,
              const cv::Scalar& col = {0, 0, 0}) {
  cv::putText(img, s, p, cv::FONT_HERSHEY_SIMPLEX, scale, col, thick, cv::LINE_AA);
}

cv::Size text_size(const std::string& s, double scale, int thick = 1) {
  int base = 0;
  return cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, thick, &base);
}

bool g_plot_data_files = false;

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      o += buf;
    } else {
      o += c;
    }
  }
  return o + "\"";
}

std::string json_number(double v) { return std::isfinite(v) ? format_double(v) : std::string("null"); }

const char* style_name(Series::Style s) {
  return s == Series::Style::Line ? "line" : s == Series::Style::Scatter ? "points" : "line+points";
}

}  // namespace

PlotSpec band_energy_plot_spec(const std::string& title, const std::vector<std::string>& names,
                               const std::vector<std::vector<double>>& energy, const std::string& value_units) {
  PlotSpec p;
  p.title = title;
  p.x_label = "band l";
  p.y_label = "energy sum_m c_lm^2 [(" + value_units + " sr)^2]";
  p.log_y = true;
  for (std::size_t c = 0; c < energy.size(); ++c) {
    Series s;
    s.label = c < names.size() ? names[c] : "channel " + std::to_string(c);
    for (std::size_t l = 0; l < energy[c].size(); ++l) {
      s.x.push_back(static_cast<double>(l));
      s.y.push_back(energy[c][l]);
    }
    p.series.push_back(std::move(s));
  }
  return p;
}

void set_plot_data_files(bool on) { g_plot_data_files = on; }

PreparedPlot prepare_plot(const PlotSpec& in) {
  PreparedPlot out;
  out.spec = in;
  out.spec.series.clear();
  auto usable = [&](double x, double y) {
    return std::isfinite(x) && std::isfinite(y) && (!in.log_x || x > 0) && (!in.log_y || y > 0);
  };
  // The y axis as the drawable points of every series set it: the floor for series
  // that have none.
  std::vector<double> ys;
  for (const auto& s : in.series)
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], s.y[i])) ys.push_back(s.y[i]);
  const Axis ay = fit_axis(ys, in.log_y);
  const double floor_y = in.log_y ? std::pow(10.0, ay.lo) : ay.lo;
  for (std::size_t si = 0; si < in.series.size(); ++si) {
    Series s = in.series[si];
    const std::size_t n = std::min(s.x.size(), s.y.size());
    std::size_t drawable = 0, finite = 0, floor_points = 0;
    for (std::size_t i = 0; i < n; ++i) {
      drawable += usable(s.x[i], s.y[i]);
      finite += std::isfinite(s.x[i]) && std::isfinite(s.y[i]);
      floor_points += in.log_y && std::isfinite(s.y[i]) && s.y[i] <= 0 && std::isfinite(s.x[i]) && (!in.log_x || s.x[i] > 0);
    }
    const std::string name = s.label.empty() ? "series " + std::to_string(si + 1) : "'" + s.label + "'";
    if (n > 0 && drawable == 0 && floor_points > 0) {
      // Nothing to draw on the log axis: markers on its floor, and say why.
      const bool all_zero = std::all_of(s.y.begin(), s.y.begin() + static_cast<std::ptrdiff_t>(n),
                                        [](double v) { return !std::isfinite(v) || v == 0.0; });
      for (std::size_t i = 0; i < n; ++i)
        if (std::isfinite(s.y[i]) && s.y[i] <= 0) s.y[i] = floor_y;
      s.style = Series::Style::Scatter;
      const std::string what = all_zero ? "all values 0" : "no value > 0";
      if (!s.label.empty()) s.label += " (" + what + ": on the axis floor)";
      out.notes.push_back(name + ": " + what + ", below the log axis: drawn as markers on its floor");
    } else if (n > 0 && finite == 0) {
      out.notes.push_back(name + ": no finite value: not drawn, left out of the legend");
      s.label.clear();
    } else if (drawable < n) {
      const std::size_t left = n - drawable;
      out.notes.push_back(name + ": " + std::to_string(left) + " of " + std::to_string(n) +
                          (in.log_x || in.log_y ? " points non-finite or <= 0 on a log axis" : " points non-finite") +
                          ": not drawn");
    }
    out.spec.series.push_back(std::move(s));
  }
  return out;
}

std::string plot_json(const PreparedPlot& p) {
  const PlotSpec& s = p.spec;
  std::string o = "{\n  \"title\": " + json_string(s.title) + ",\n  \"x_label\": " + json_string(s.x_label) +
                  ",\n  \"y_label\": " + json_string(s.y_label) + ",\n  \"log_x\": " + (s.log_x ? "true" : "false") +
                  ",\n  \"log_y\": " + (s.log_y ? "true" : "false") + ",\n  \"notes\": [";
  for (std::size_t i = 0; i < p.notes.size(); ++i) o += (i ? ", " : "") + json_string(p.notes[i]);
  o += "],\n  \"series\": [";
  for (std::size_t k = 0; k < s.series.size(); ++k) {
    const Series& r = s.series[k];
    o += std::string(k ? "," : "") + "\n    {\"label\": " + json_string(r.label) + ", \"style\": \"" +
         style_name(r.style) + "\", \"x\": [";
    // The comma appended on its own: GCC 12 warns falsely (-Wrestrict, its bug 105329) on "," + string.
    for (std::size_t i = 0; i < r.x.size(); ++i) {
      if (i) o += ',';
      o += json_number(r.x[i]);
    }
    o += "], \"y\": [";
    for (std::size_t i = 0; i < r.y.size(); ++i) {
      if (i) o += ',';
      o += json_number(r.y[i]);
    }
    o += "]}";
  }
  return o + "\n  ]\n}\n";
}

std::filesystem::path write_tone_map_side_file(const std::filesystem::path& png, const std::string& tone_map,
                                               double exposure, const std::string& exposure_rule,
                                               const std::string& source) {
  std::filesystem::path side = png;
  side += ".json";
  write_text_atomically(side, "{\n  \"tone_map\": " + json_string(tone_map) + ",\n  \"exposure\": " +
                                  json_number(exposure) + ",\n  \"exposure_rule\": " + json_string(exposure_rule) +
                                  ",\n  \"source\": " + json_string(source) + "\n}\n");
  return side;
}

void write_plot_png(const std::filesystem::path& file, const PlotSpec& given) {
  const PreparedPlot prepared = prepare_plot(given);
  const PlotSpec& spec = prepared.spec;
  const int W = spec.width, H = spec.height;
  if (W < 200 || H < 150) throw std::invalid_argument("plot size too small");
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 120, right = 40, top = 70 + 20 * static_cast<int>(prepared.notes.size()), bottom = 100;
  const cv::Rect frame(left, top, W - left - right, H - top - bottom);

  std::vector<double> xs, ys;
  for (const auto& s : spec.series) {
    xs.insert(xs.end(), s.x.begin(), s.x.end());
    ys.insert(ys.end(), s.y.begin(), s.y.end());
  }
  const Axis ax = fit_axis(xs, spec.log_x), ay = fit_axis(ys, spec.log_y);
  auto px = [&](double v) { return frame.x + ax.map(v) * frame.width; };
  auto py = [&](double v) { return frame.y + frame.height - ay.map(v) * frame.height; };

  // Grid and ticks.
  for (const auto& [v, lab] : make_ticks(ax)) {
    const int x = static_cast<int>(std::lround(frame.x + (v - ax.lo) / (ax.hi - ax.lo) * frame.width));
    cv::line(img, {x, frame.y}, {x, frame.y + frame.height}, {225, 225, 225}, 1);
    cv::line(img, {x, frame.y + frame.height}, {x, frame.y + frame.height + 6}, {0, 0, 0}, 1);
    const auto ts = text_size(lab, 0.5);
    put_text(img, lab, {x - ts.width / 2, frame.y + frame.height + 24}, 0.5);
  }
  for (const auto& [v, lab] : make_ticks(ay)) {
    const int y = static_cast<int>(std::lround(frame.y + frame.height - (v - ay.lo) / (ay.hi - ay.lo) * frame.height));
    cv::line(img, {frame.x, y}, {frame.x + frame.width, y}, {225, 225, 225}, 1);
    cv::line(img, {frame.x - 6, y}, {frame.x, y}, {0, 0, 0}, 1);
    const auto ts = text_size(lab, 0.5);
    put_text(img, lab, {frame.x - 10 - ts.width, y + ts.height / 2}, 0.5);
  }
  cv::rectangle(img, frame, {0, 0, 0}, 1);

  // Series, clipped to the frame.
  cv::Mat plot_area = img(frame);
  for (std::size_t si = 0; si < spec.series.size(); ++si) {
    const auto& s = spec.series[si];
    const cv::Scalar col = s.color[0] >= 0 ? bgr(s.color) : kPalette[si % 8];
    std::vector<cv::Point> run;
    auto flush = [&] {
      if (run.size() >= 2 && s.style != Series::Style::Scatter)
        cv::polylines(plot_area, run, false, col, 2, cv::LINE_AA);
      run.clear();
    };
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      const double x = s.x[i], y = s.y[i];
      const bool ok = std::isfinite(x) && std::isfinite(y) && (!spec.log_x || x > 0) && (!spec.log_y || y > 0);
      if (!ok) {
        flush();
        continue;
      }
      const cv::Point p(static_cast<int>(std::lround(px(x) - frame.x)), static_cast<int>(std::lround(py(y) - frame.y)));
      run.push_back(p);
      if (s.style != Series::Style::Line) cv::circle(plot_area, p, 4, col, cv::FILLED, cv::LINE_AA);
    }
    flush();
  }

  // Labels.
  if (!spec.title.empty()) {
    const auto ts = text_size(spec.title, 0.8, 2);
    put_text(img, spec.title, {(W - ts.width) / 2, 40}, 0.8, 2);
  }
  for (std::size_t i = 0; i < prepared.notes.size(); ++i) {
    const std::string note = "note: " + prepared.notes[i];
    const auto ts = text_size(note, 0.5);
    put_text(img, note, {std::max(10, (W - ts.width) / 2), 64 + 20 * static_cast<int>(i)}, 0.5, 1, {60, 60, 160});
  }
  {
    const auto ts = text_size(spec.x_label, 0.65);
    put_text(img, spec.x_label, {frame.x + (frame.width - ts.width) / 2, H - 30}, 0.65);
  }
  if (!spec.y_label.empty()) {
    const auto ts = text_size(spec.y_label, 0.65);
    cv::Mat lab(ts.height + 14, ts.width + 10, CV_8UC3, cv::Scalar(255, 255, 255));
    put_text(lab, spec.y_label, {5, ts.height + 4}, 0.65);
    cv::Mat rot;
    cv::rotate(lab, rot, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int y0 = std::max(0, frame.y + (frame.height - rot.rows) / 2);
    const int h = std::min(rot.rows, H - y0);
    rot(cv::Rect(0, 0, rot.cols, h)).copyTo(img(cv::Rect(8, y0, rot.cols, h)));
  }
  // Legend (top-right inside the frame).
  int max_w = 0, rows = 0;
  for (const auto& s : spec.series)
    if (!s.label.empty()) {
      max_w = std::max(max_w, text_size(s.label, 0.5).width);
      ++rows;
    }
  if (rows > 0) {
    const int lw = max_w + 60, lh = rows * 24 + 12;
    const cv::Rect box(frame.x + frame.width - lw - 10, frame.y + 10, lw, lh);
    cv::rectangle(img, box, {255, 255, 255}, cv::FILLED);
    cv::rectangle(img, box, {120, 120, 120}, 1);
    int r = 0;
    for (std::size_t si = 0; si < spec.series.size(); ++si) {
      const auto& s = spec.series[si];
      if (s.label.empty()) continue;
      const cv::Scalar col = s.color[0] >= 0 ? bgr(s.color) : kPalette[si % 8];
      const int y = box.y + 20 + r * 24;
      cv::line(img, {box.x + 8, y - 5}, {box.x + 40, y - 5}, col, 2, cv::LINE_AA);
      if (s.style != Series::Style::Line) cv::circle(img, {box.x + 24, y - 5}, 4, col, cv::FILLED, cv::LINE_AA);
      put_text(img, s.label, {box.x + 50, y}, 0.5);
      ++r;
    }
  }
  save_png(file, img);
  if (g_plot_data_files) {
    std::filesystem::path data = file;
    data += ".plot.json";
    write_text_atomically(data, plot_json(prepared));
  }
}

void write_swatch_png(const std::filesystem::path& file, const std::string& title, const std::vector<Swatch>& swatches) {
  if (swatches.empty()) throw std::invalid_argument("swatch strip needs at least one colour");
  const int n = static_cast<int>(swatches.size());
  const int cell = std::clamp(1600 / n, 12, 120);
  const int W = std::max(cell * n + 40, 400), H = 60 + cell + 80;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  put_text(img, title, {20, 35}, 0.7, 2);
  const int stride = std::max(1, static_cast<int>(std::ceil(n * 60.0 / (cell * n))));
  for (int i = 0; i < n; ++i) {
    const cv::Rect r(20 + i * cell, 50, cell, cell);
    cv::rectangle(img, r, bgr(swatches[static_cast<std::size_t>(i)].srgb), cv::FILLED);
    if (i % stride == 0) {
      cv::Mat lab(20, 70, CV_8UC3, cv::Scalar(255, 255, 255));
      put_text(lab, swatches[static_cast<std::size_t>(i)].label, {2, 15}, 0.42);
      cv::Mat rot;
      cv::rotate(lab, rot, cv::ROTATE_90_COUNTERCLOCKWISE);
      const int x = std::min(r.x + cell / 2 - 10, W - rot.cols);
      rot.copyTo(img(cv::Rect(x, 50 + cell + 4, rot.cols, std::min(rot.rows, H - (50 + cell + 4)))));
    }
  }
  save_png(file, img);
}

std::size_t tonemapped_png_bytes(int width, int height) {
  if (width < 1 || height < 1) return 0;
  const long double b = 6.0L * width * height;  // CV_8UC3 image + encoded buffer (at most ~ the raw size)
  return b >= static_cast<long double>(SIZE_MAX) ? SIZE_MAX : static_cast<std::size_t>(b);
}

void write_tonemapped_png(const std::filesystem::path& file, int width, int height, const std::vector<float>& r,
                          const std::vector<float>& g, const std::vector<float>& b, double exposure,
                          const std::string& op) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (r.size() != n || g.size() != n || b.size() != n) throw std::invalid_argument("tone map: size mismatch");
  if (op != "clamp" && op != "reinhard") throw std::invalid_argument("unknown tone-map operator '" + op + "'");
  auto encode = [](double v) {  // sRGB transfer (IEC 61966-2-1)
    v = std::clamp(v, 0.0, 1.0);
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    return static_cast<unsigned char>(std::lround(s * 255.0));
  };
  cv::Mat img(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      double c[3] = {r[i] * exposure, g[i] * exposure, b[i] * exposure};
      for (double& v : c) {
        if (!std::isfinite(v) || v < 0) v = 0;
        if (op == "reinhard") v = v / (1.0 + v);
      }
      img.at<cv::Vec3b>(y, x) = {encode(c[2]), encode(c[1]), encode(c[0])};
    }
  save_png(file, img);
}

}  // namespace atmosh::io
