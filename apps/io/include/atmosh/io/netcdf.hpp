// atmosh/io/netcdf.hpp — netCDF-4 files following the CF conventions (CF-1.8).
//
// Three kinds of file, each written atomically (write_atomically: temporary file in
// the target's folder, then rename) with the netCDF C library:
//   * sky images: the spectral radiance cube over wavelength x elevation x azimuth of
//     an equirect image, and CIE X, Y (luminance), Z over elevation x azimuth;
//   * tables (studies, sweeps, sun tracks): one dimension `row` (or `time`), one
//     variable per column, its units from the column name's suffix;
// Every file carries global attributes
//   Conventions = "CF-1.8", title, source = "atmosh <version> (<git commit>)",
//   history = "<run_utc> <command line>" (CF: one line per program that touched the
//   file), and one attribute "atmosh_<key>" per provenance entry (keys made of letters,
//   digits and '_'; other characters become '_').
// Errors: a table whose columns cannot be written (ragged types, duplicate names after
// the renaming below) throws atmosh::InputError; a netCDF library failure throws
// std::runtime_error naming the file and the library's message.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "atmosh/io/csv.hpp"
#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

// An equirect sky image as atmo::SkyImage holds it (atmosh/atmo/sky_image.hpp):
// column x at azimuth (x + 0.5) / width * 360 deg from north towards east, row y at
// elevation 90 - (y + 0.5) / height * 180 deg (row 0 at the zenith).
struct NetcdfSkyImage {
  int width = 0, height = 0;
  std::span<const double> wavelengths_nm;  // vacuum wavelengths [nm]
  // Spectral radiance [W m^-2 sr^-1 nm^-1], [(y * width + x) * n_wavelengths + i];
  // empty: the file has no spectral cube.
  std::span<const float> spectral;
  std::span<const float> X, Y, Z;  // planar [y * width + x]; Y = luminance [cd m^-2]
  std::optional<double> sun_zenith_deg, sun_azimuth_deg;  // scalar variables when set
  std::string title = "atmosh sky image";
};

// Writes `file` with dimensions wavelength, elevation, azimuth; coordinate variables
// wavelength [nm] (standard_name radiation_wavelength), elevation [degree] (decreasing:
// the image's row order), azimuth [degree]; data variables spectral_radiance(wavelength,
// elevation, azimuth) (standard_name downwelling_radiance_per_unit_wavelength_in_air,
// units "W m-2 sr-1 nm-1"), X, Y, Z (elevation, azimuth) as float32 (Y: "cd m-2"), and
// solar_zenith_angle / solar_azimuth_angle [degree] where given. Throws InputError when
// the spans' sizes do not match width, height and the wavelengths.
void write_sky_netcdf(const std::filesystem::path& file, const NetcdfSkyImage& sky, const Provenance& provenance);

// Units of a column from its name's suffix (the toolkit's snake_case-with-unit names):
// _deg -> "degree", _s -> "s", _min -> "min", _nm -> "nm", _m -> "m", _km -> "km",
// _per_m -> "m-1", _cd_m2 -> "cd m-2", _lux -> "lx", _rel -> "1", _k -> "K", _pa -> "Pa",
// _w_m2 -> "W m-2"; "" for other names (no units attribute is written).
std::string units_from_column_name(const std::string& column);

struct NetcdfTableOptions {
  std::string title = "atmosh table";
  // A numeric column of UTC Julian dates (e.g. the sun track's jd_utc): the dimension
  // is then `time`, with a coordinate variable time in "seconds since 1970-01-01
  // 00:00:00 UTC" (standard_name time, calendar "standard") computed from it. "": the
  // dimension is `row` (0, 1, ...) and there is no time coordinate.
  std::string julian_date_column;
  // A numeric column that is the table's dimension (e.g. the sun-elevation study's
  // sun_elevation_deg): the dimension takes the column's netCDF name and the column is
  // its coordinate variable. Used when there is no time coordinate; "": dimension `row`.
  std::string coordinate_column;
  // Explicit times for the `time` coordinate [s since 1970-01-01 00:00:00 UTC], one per
  // row (e.g. the day study's time_utc column parsed); used when julian_date_column is
  // empty. Empty: no time coordinate from this source.
  std::vector<double> time_unix_s;
  // CF standard names by column name, on top of default_standard_names().
  std::map<std::string, std::string> standard_names;
  // Scalar variables (e.g. latitude, longitude of a sun track's site):
  // name -> {value, units, standard_name}.
  struct Scalar {
    double value = 0;
    std::string units, standard_name;
  };
  std::map<std::string, Scalar> scalars;
};

// Column names whose CF standard name is unambiguous in any atmosh table:
// sun_elevation_deg -> solar_elevation_angle, sun_azimuth_deg -> solar_azimuth_angle,
// sun_zenith_deg -> solar_zenith_angle.
std::map<std::string, std::string> default_standard_names();
// The sun track's columns (atmosh sun track / the scene's sun-track output):
// zenith_deg -> solar_zenith_angle, azimuth_deg -> solar_azimuth_angle,
// elevation_deg -> solar_elevation_angle, with julian_date_column = "jd_utc".
NetcdfTableOptions sun_track_netcdf_options();

// netCDF name of a column: '.' (the sweep's dotted scene keys) becomes "__", any other
// character outside [A-Za-z0-9_] becomes '_', a leading digit gets a leading '_'. The
// original name is kept in the variable's attribute atmosh_column.
std::string netcdf_variable_name(const std::string& column);

// Writes a table: one variable per column over the table's dimension, double for
// columns of numbers (int64 where every cell is an integer), string where every cell
// is a string; units from units_from_column_name, long_name = the column name.
// Throws InputError for a column mixing strings and numbers or two columns with the
// same netCDF name.
void write_table_netcdf(const std::filesystem::path& file, const CsvTable& table, const Provenance& provenance,
                        const NetcdfTableOptions& options = {});

// An equirect sky EXR of `atmosh sky` (R,G,B,X,Y,Z and, with --spectral, L_<nm>nm
// channels; atmosh/io/exr.hpp) converted: X, Y, Z, the spectral cube (wavelengths from
// the channel names, which round them to 0.1 nm, in increasing order), the sun from the
// sun_elevation_deg / sun_azimuth_deg attributes (float32) and the provenance from the
// "atmosh:<key>" attributes. Throws InputError for a fisheye image (its pixels lie on
// no elevation x azimuth grid) or one without X, Y, Z.
void write_exr_sky_as_netcdf(const std::filesystem::path& exr_file, const std::filesystem::path& netcdf_file);

// A CSV the toolkit wrote (CsvTable: provenance lines, header, rows), converted: its
// provenance lines become the global attributes, a column whose every cell is an
// integer literal becomes int64, one whose every cell is a number (nan, inf included)
// double, any other string. This is what `--format netcdf` of a table output calls
// after (or instead of keeping) the CSV. Throws InputError as read_csv does.
CsvTable table_from_csv(const CsvData& csv, Provenance& provenance);
void write_csv_as_netcdf(const std::filesystem::path& csv_file, const std::filesystem::path& netcdf_file,
                         const NetcdfTableOptions& options = {});

// ---- table outputs in CSV and netCDF-CF ---------------------------------------------
// A table output (a study's table, a sweep) is always written as CSV (the plots, the
// sweep's journal and merges read it); with netCDF selected it is also written as
// netCDF-CF beside it, from the same in-memory table (not converted from the CSV).
//
// The value of a `--format` option of a table output: "csv" -> false, "netcdf" -> true;
// InputError "<what>: 'x' is not csv or netcdf" otherwise.
bool parse_table_format(const std::string& value, const std::string& what = "--format");
// An output stem or file given with the ending ".nc" (e.g. `-o results/sky_convergence.nc`):
// returns it without the ending and sets netcdf; any other name is returned as it is.
std::filesystem::path table_output_stem(const std::filesystem::path& stem, bool& netcdf);
// Writes csv_file (CsvTable::write) and, when netcdf, csv_file with the extension
// ".nc" (write_table_netcdf with `options`); returns the files written, CSV first.
std::vector<std::filesystem::path> write_table_files(const std::filesystem::path& csv_file, const CsvTable& table,
                                                     const Provenance& provenance, bool netcdf,
                                                     const NetcdfTableOptions& options = {});

// A sweep's table (the CSV of `atmosh sweep` or `sweep merge`: point, one column per
// parameter key `keys`, the outputs, time_s) as netCDF-CF. When the points form a grid (every
// combination of the keys' distinct values appears once, as mode = "grid" writes them)
// each key is a dimension with its values as coordinate variable (the keys' netCDF
// names: '.' -> "__"), and every other column a variable over those dimensions in the
// keys' order; else (mode = "zip", a shard) the dimension is `point` and the keys are
// auxiliary coordinate variables over it (CF `coordinates` attribute). The provenance
// (sweep, sweep_id, base scene, settings) becomes global attributes.
// InputError when a key is not a column of the table.
void write_sweep_netcdf(const std::filesystem::path& file, const CsvTable& table, const Provenance& provenance,
                        const std::vector<std::string>& keys);
// The sweep's result file (its CSV: the journal's rows, or the merged shards) read
// (table_from_csv) and written with write_sweep_netcdf.
void write_sweep_csv_as_netcdf(const std::filesystem::path& csv_file, const std::filesystem::path& netcdf_file,
                               const std::vector<std::string>& keys);

}  // namespace atmosh::io
