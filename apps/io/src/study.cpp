#include "atmosh/io/study.hpp"

#include <limits>
#include <map>

#include "atmosh/io/csv.hpp"
#include "atmosh/io/plot.hpp"

namespace atmosh::io {

std::vector<std::filesystem::path> write_study(const std::filesystem::path& stem, const StudySpec& spec,
                                               const std::vector<StudyRow>& rows, const Provenance& provenance) {
  std::vector<std::string> cols = {"method", "setting", spec.error_max_column, spec.error_rms_column, spec.time_column};
  cols.insert(cols.end(), spec.extra_columns.begin(), spec.extra_columns.end());
  CsvTable t(cols);
  std::vector<std::string> order;
  std::map<std::string, Series> by_method;
  for (const auto& r : rows) {
    std::vector<CsvCell> row = {r.method, r.setting, r.error_max, r.error_rms, r.time_s};
    for (std::size_t i = 0; i < spec.extra_columns.size(); ++i)
      row.emplace_back(i < r.extras.size() ? r.extras[i] : std::numeric_limits<double>::quiet_NaN());
    t.add_row(std::move(row));
    if (!by_method.count(r.method)) {
      order.push_back(r.method);
      by_method[r.method].label = r.method;
      // Settings vary in more than one parameter: points, not a misleading polyline.
      by_method[r.method].style = Series::Style::Scatter;
    }
    by_method[r.method].x.push_back(r.time_s);
    by_method[r.method].y.push_back(r.error_max);
  }
  std::filesystem::path csv = stem, png = stem;
  csv += ".csv";
  png += ".png";
  t.write(csv, provenance);
  PlotSpec p;
  p.title = spec.title;
  p.x_label = spec.time_axis_label;
  p.y_label = spec.error_axis_label;
  p.log_x = p.log_y = true;
  for (const auto& m : order) p.series.push_back(by_method[m]);
  write_plot_png(png, p);
  return {csv, png};
}

}  // namespace atmosh::io
