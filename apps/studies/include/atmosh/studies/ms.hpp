// atmosh/studies/ms.hpp — the sky's scattering methods (single, the all-orders
// approximation, successive orders, table sizes) against the Monte-Carlo reference:
// luminance error against run time (the computation: atmo::ms_convergence_study).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "atmosh/atmo/ms_convergence.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/scene/scene.hpp"

namespace atmosh::studies {

struct ConvergeMsOptions {
  std::int64_t paths = 0;  // Monte-Carlo paths per reference row; 0: the mode's default (quick 16000, full 128000)
  std::uint64_t seed = 1;  // of the reference
  bool quick = false;      // 4 rows (zenith and horizon, sun 30 and 10 deg), 3 settings
};
struct ConvergeMs {
  atmo::MsStudyOptions options;  // as run (settings, views, suns)
  atmo::MsStudyResult result;
  std::int64_t paths = 0;
  io::Provenance provenance;
};
// InputError for paths outside [1, 2^40].
ConvergeMs converge_ms(const scene::Scene& s, const ConvergeMsOptions& o);
// The study's table (ms_convergence.csv): method, setting, band, error_max_rel,
// error_rms_rel, time_s, reference_rel_stderr_max, error_max_sigma,
// error_max_rel_minus_3sigma, build_time_s, eval_time_s, rows, rows_skipped. The one
// place its columns are made (CSV, netCDF, the Python module's DataFrame).
io::CsvTable converge_ms_table(const ConvergeMs& c);
// dir/ms_convergence.csv (with netcdf also dir/ms_convergence.nc, netCDF-CF),
// dir/ms_convergence.png (day and civil bands), dir/ms_convergence_points.csv;
// returns the files written.
std::vector<std::filesystem::path> write_converge_ms(const ConvergeMs& c, const std::filesystem::path& dir,
                                                     bool netcdf = false);
// The demo's step: converge ms --quick on the default scene into dir.
std::vector<std::filesystem::path> demo_ms(const std::filesystem::path& dir);

}  // namespace atmosh::studies
