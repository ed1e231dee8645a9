#include "atmosh/io/study.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>

#include "atmosh/io/csv.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/io/plot.hpp"

namespace atmosh::io {

PlotSpec study_plot_spec(const StudySpec& spec, const std::vector<StudyRow>& rows) {
  std::vector<std::string> order;
  std::map<std::string, Series> by_method;
  for (const auto& r : rows) {
    if (!by_method.count(r.method)) {
      order.push_back(r.method);
      by_method[r.method].label = r.method;
      // Settings vary in more than one parameter: points, not a misleading polyline.
      by_method[r.method].style = Series::Style::Scatter;
    }
    by_method[r.method].x.push_back(r.time_s);
    by_method[r.method].y.push_back(r.error_max);
  }
  PlotSpec p;
  p.title = spec.title;
  p.x_label = spec.time_axis_label;
  p.y_label = spec.error_axis_label;
  p.log_x = p.log_y = true;
  for (const auto& m : order) {
    Series s = by_method[m];
    std::vector<std::size_t> idx(s.x.size());
    std::iota(idx.begin(), idx.end(), std::size_t{0});
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return s.x[a] < s.x[b]; });
    Series sorted = s;
    for (std::size_t i = 0; i < idx.size(); ++i) {
      sorted.x[i] = s.x[idx[i]];
      sorted.y[i] = s.y[idx[i]];
    }
    p.series.push_back(std::move(sorted));
  }
  return p;
}

CsvTable study_table(const StudySpec& spec, const std::vector<StudyRow>& rows) {
  std::vector<std::string> cols = {"method", "setting", spec.error_max_column, spec.error_rms_column, spec.time_column};
  cols.insert(cols.end(), spec.extra_columns.begin(), spec.extra_columns.end());
  CsvTable t(cols);
  for (const auto& r : rows) {
    std::vector<CsvCell> row = {r.method, r.setting, r.error_max, r.error_rms, r.time_s};
    for (std::size_t i = 0; i < spec.extra_columns.size(); ++i)
      row.emplace_back(i < r.extras.size() ? r.extras[i] : std::numeric_limits<double>::quiet_NaN());
    t.add_row(std::move(row));
  }
  return t;
}

std::vector<std::filesystem::path> write_study(const std::filesystem::path& given_stem, const StudySpec& spec,
                                               const std::vector<StudyRow>& rows, const Provenance& provenance,
                                               bool netcdf) {
  const std::filesystem::path stem = table_output_stem(given_stem, netcdf);
  std::filesystem::path csv = stem, png = stem;
  csv += ".csv";
  png += ".png";
  NetcdfTableOptions o;
  o.title = spec.title.empty() ? "atmosh error against run time" : spec.title;
  auto written = write_table_files(csv, study_table(spec, rows), provenance, netcdf, o);
  write_plot_png(png, study_plot_spec(spec, rows));
  written.push_back(png);
  return written;
}

}  // namespace atmosh::io
