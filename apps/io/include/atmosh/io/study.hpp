// atmosh/io/study.hpp — error-against-run-time tables (the toolkit's standard
// way of reporting any approximate method against an exact reference).
//
// Writes <stem>.csv with columns
//   method, setting, error_max_rel, error_rms_rel, time_s [, extra columns...]
// and <stem>.png, a log-log scatter plot of error_max_rel against time_s, one
// colour per method. Error and time names may be renamed (e.g. error_max_deg) via the spec.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "atmosh/io/csv.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

struct StudyRow {
  std::string method;
  std::string setting;
  double error_max = 0.0;
  double error_rms = 0.0;
  double time_s = 0.0;
  std::vector<double> extras;  // values of StudySpec::extra_columns
};

struct StudySpec {
  std::string title;
  std::string error_max_column = "error_max_rel";
  std::string error_rms_column = "error_rms_rel";
  std::string error_axis_label = "max relative error";
  std::string time_column = "time_s";
  std::string time_axis_label = "run time [s]";
  std::vector<std::string> extra_columns;
};

// The plot of a study: log-log, one series per method (in order of first
// appearance), points only (settings vary in more than one parameter), each series'
// points sorted by run time (the CSV keeps the rows' order).
PlotSpec study_plot_spec(const StudySpec& spec, const std::vector<StudyRow>& rows);

// The study's table: columns method, setting, spec.error_max_column,
// spec.error_rms_column, spec.time_column, spec.extra_columns (NaN where a row has
// fewer extras), one row per StudyRow. The one place these columns are made: the CSV,
// the netCDF file and the Python module's DataFrames all come from it.
CsvTable study_table(const StudySpec& spec, const std::vector<StudyRow>& rows);

// Writes stem + ".csv", with netcdf also stem + ".nc" (netCDF-CF, dimension `row`,
// atmosh/io/netcdf.hpp), and stem + ".png"; returns the paths. A stem ending in ".nc"
// selects netCDF and loses the ending (io::table_output_stem).
std::vector<std::filesystem::path> write_study(const std::filesystem::path& stem, const StudySpec& spec,
                                               const std::vector<StudyRow>& rows,
                                               const Provenance& provenance, bool netcdf = false);

}  // namespace atmosh::io
