// netCDF-CF writers of atmosh_io (atmosh/io/netcdf.hpp), read back with the netCDF C
// library and, where Debian's python3-xarray is installed, with xarray. The inputs are
// closed-form functions of their indices, so a transposed or flipped axis shows up.
#include <netcdf.h>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/netcdf.hpp"

namespace fs = std::filesystem;
using namespace atmosh::io;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_netcdf_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

struct Reader {
  int id = -1;
  explicit Reader(const fs::path& p) { EXPECT_EQ(nc_open(p.c_str(), NC_NOWRITE, &id), NC_NOERR) << p; }
  ~Reader() {
    if (id >= 0) nc_close(id);
  }
  int var(const std::string& name) const {
    int v = -1;
    EXPECT_EQ(nc_inq_varid(id, name.c_str(), &v), NC_NOERR) << name;
    return v;
  }
  bool has_var(const std::string& name) const {
    int v = -1;
    return nc_inq_varid(id, name.c_str(), &v) == NC_NOERR;
  }
  std::string text(int v, const std::string& att) const {
    std::size_t len = 0;
    if (nc_inq_attlen(id, v, att.c_str(), &len) != NC_NOERR) return "<none>";
    std::string s(len, '\0');
    EXPECT_EQ(nc_get_att_text(id, v, att.c_str(), s.data()), NC_NOERR);
    return s;
  }
  std::size_t dim(const std::string& name) const {
    int d = -1;
    std::size_t n = 0;
    EXPECT_EQ(nc_inq_dimid(id, name.c_str(), &d), NC_NOERR) << name;
    EXPECT_EQ(nc_inq_dimlen(id, d, &n), NC_NOERR);
    return n;
  }
  std::vector<std::string> dims_of(int v) const {
    int nd = 0;
    int ids[NC_MAX_VAR_DIMS];
    EXPECT_EQ(nc_inq_varndims(id, v, &nd), NC_NOERR);
    EXPECT_EQ(nc_inq_vardimid(id, v, ids), NC_NOERR);
    std::vector<std::string> out;
    for (int i = 0; i < nd; ++i) {
      char name[NC_MAX_NAME + 1];
      EXPECT_EQ(nc_inq_dimname(id, ids[i], name), NC_NOERR);
      out.emplace_back(name);
    }
    return out;
  }
  std::vector<double> doubles(const std::string& name, std::size_t n) const {
    std::vector<double> v(n);
    EXPECT_EQ(nc_get_var_double(id, var(name), v.data()), NC_NOERR) << name;
    return v;
  }
};

// Runs Debian's python3 with xarray on a script; skips where it is not available.
bool have_xarray() {
  return fs::exists("/usr/bin/python3") && std::system("/usr/bin/python3 -c 'import xarray, netCDF4' 2>/dev/null") == 0;
}
int run_python(const fs::path& dir, const std::string& script) {
  const fs::path f = dir / "check.py";
  std::ofstream(f) << script;
  return std::system(("/usr/bin/python3 " + f.string()).c_str());
}

// The test image: width 6, height 4, three wavelengths.
constexpr int kW = 6, kH = 4, kN = 3;
float spectral_value(int i, int y, int x) { return 1.0f + 100.0f * i + 10.0f * y + x; }
float xyz_value(int c, int y, int x) { return 0.5f + 1000.0f * c + 7.0f * y + 0.25f * x; }

fs::path write_test_sky(const fs::path& dir) {
  std::vector<double> wl = {400.0, 550.0, 700.0};
  std::vector<float> spectral(kW * kH * kN), X(kW * kH), Y(kW * kH), Z(kW * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      for (int i = 0; i < kN; ++i) spectral[(y * kW + x) * kN + i] = spectral_value(i, y, x);
      X[y * kW + x] = xyz_value(0, y, x);
      Y[y * kW + x] = xyz_value(1, y, x);
      Z[y * kW + x] = xyz_value(2, y, x);
    }
  NetcdfSkyImage sky;
  sky.width = kW;
  sky.height = kH;
  sky.wavelengths_nm = wl;
  sky.spectral = spectral;
  sky.X = X;
  sky.Y = Y;
  sky.Z = Z;
  sky.sun_zenith_deg = 60.0;
  sky.sun_azimuth_deg = 135.0;
  Provenance p;
  p.add("command_line", "atmosh sky --width 6");
  p.add("run_utc", "2026-11-26T00:00:00Z");
  p.add("scene.sun", "elevation 30");
  const fs::path file = dir / "sky.nc";
  write_sky_netcdf(file, sky, p);
  return file;
}

}  // namespace

TEST(Netcdf, SkyCubeReadsBackOnItsAxes) {
  const fs::path dir = fresh_dir("sky");
  const fs::path file = write_test_sky(dir);
  // Atomic write: only the target in the folder, no temporary left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);

  Reader r(file);
  EXPECT_EQ(r.text(NC_GLOBAL, "Conventions"), "CF-1.8");
  EXPECT_EQ(r.text(NC_GLOBAL, "history"), "2026-11-26T00:00:00Z atmosh sky --width 6");
  EXPECT_EQ(r.text(NC_GLOBAL, "atmosh_scene_sun"), "elevation 30");
  EXPECT_EQ(r.dim("wavelength"), 3u);
  EXPECT_EQ(r.dim("elevation"), 4u);
  EXPECT_EQ(r.dim("azimuth"), 6u);
  // Pixel centres (sky_image.hpp): elevation 90 - (y + 0.5) * 180 / 4, azimuth (x + 0.5) * 360 / 6.
  EXPECT_EQ(r.doubles("elevation", 4), (std::vector<double>{67.5, 22.5, -22.5, -67.5}));
  EXPECT_EQ(r.doubles("azimuth", 6), (std::vector<double>{30, 90, 150, 210, 270, 330}));
  EXPECT_EQ(r.doubles("wavelength", 3), (std::vector<double>{400, 550, 700}));
  EXPECT_EQ(r.text(r.var("wavelength"), "units"), "nm");
  EXPECT_EQ(r.text(r.var("elevation"), "units"), "degree");

  const int vs = r.var("spectral_radiance");
  EXPECT_EQ(r.dims_of(vs), (std::vector<std::string>{"wavelength", "elevation", "azimuth"}));
  EXPECT_EQ(r.text(vs, "units"), "W m-2 sr-1 nm-1");
  EXPECT_EQ(r.text(vs, "standard_name"), "downwelling_radiance_per_unit_wavelength_in_air");
  std::vector<float> cube(kN * kH * kW);
  ASSERT_EQ(nc_get_var_float(r.id, vs, cube.data()), NC_NOERR);
  for (int i = 0; i < kN; ++i)
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) ASSERT_EQ(cube[(i * kH + y) * kW + x], spectral_value(i, y, x)) << i << y << x;
  const char* names[3] = {"X", "Y", "Z"};
  for (int c = 0; c < 3; ++c) {
    const int v = r.var(names[c]);
    EXPECT_EQ(r.dims_of(v), (std::vector<std::string>{"elevation", "azimuth"}));
    EXPECT_EQ(r.text(v, "units"), "cd m-2");
    std::vector<float> img(kH * kW);
    ASSERT_EQ(nc_get_var_float(r.id, v, img.data()), NC_NOERR);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) ASSERT_EQ(img[y * kW + x], xyz_value(c, y, x));
  }
  EXPECT_EQ(r.text(r.var("solar_zenith_angle"), "standard_name"), "solar_zenith_angle");
  EXPECT_EQ(r.doubles("solar_zenith_angle", 1)[0], 60.0);
  EXPECT_EQ(r.doubles("solar_azimuth_angle", 1)[0], 135.0);
  fs::remove_all(dir);
}

TEST(Netcdf, SkyWithoutSpectraAndBadSizes) {
  const fs::path dir = fresh_dir("sky2");
  std::vector<float> X(6, 1.0f), Y(6, 2.0f), Z(6, 3.0f), wrong(5, 0.0f);
  NetcdfSkyImage sky;
  sky.width = 3;
  sky.height = 2;
  sky.X = X;
  sky.Y = Y;
  sky.Z = Z;
  write_sky_netcdf(dir / "xyz.nc", sky, Provenance{});
  {
    Reader r(dir / "xyz.nc");
    EXPECT_FALSE(r.has_var("spectral_radiance"));
    EXPECT_FALSE(r.has_var("solar_zenith_angle"));
    EXPECT_EQ(r.doubles("Y", 6), std::vector<double>(6, 2.0));
  }
  sky.Y = wrong;
  EXPECT_THROW(write_sky_netcdf(dir / "bad.nc", sky, Provenance{}), atmosh::InputError);
  sky.Y = Y;
  std::vector<double> wl = {500.0, 600.0};
  sky.wavelengths_nm = wl;
  sky.spectral = wrong;  // needs 12 values
  EXPECT_THROW(write_sky_netcdf(dir / "bad.nc", sky, Provenance{}), atmosh::InputError);
  EXPECT_FALSE(fs::exists(dir / "bad.nc"));
  fs::remove_all(dir);
}

TEST(Netcdf, UnitsFromColumnSuffixes) {
  EXPECT_EQ(units_from_column_name("zenith_luminance_cd_m2"), "cd m-2");
  EXPECT_EQ(units_from_column_name("mie.scattering_per_m"), "m-1");
  EXPECT_EQ(units_from_column_name("sun.elevation_deg"), "degree");
  EXPECT_EQ(units_from_column_name("table_build_time_s"), "s");
  EXPECT_EQ(units_from_column_name("sun_direct_normal_illuminance_lux"), "lx");
  EXPECT_EQ(units_from_column_name("equation_of_time_min"), "min");
  EXPECT_EQ(units_from_column_name("error_max_rel"), "1");
  EXPECT_EQ(units_from_column_name("sun_transmittance_550nm"), "");  // a label, not a unit
  EXPECT_EQ(units_from_column_name("zenith_x"), "");
  EXPECT_EQ(units_from_column_name("point"), "");
  EXPECT_EQ(netcdf_variable_name("sun.elevation_deg"), "sun__elevation_deg");
  EXPECT_EQ(netcdf_variable_name("3d-depth"), "_3d_depth");
}

TEST(Netcdf, TableColumnsReadBackExactly) {
  const fs::path dir = fresh_dir("table");
  CsvTable t({"point", "sun.elevation_deg", "sun_elevation_deg", "method", "zenith_luminance_cd_m2", "time_s"});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  t.add_row({std::int64_t{0}, 5.0, 5.000000000000001, std::string("fast"), 0.1 + 0.2, 1e-300});
  t.add_row({std::int64_t{1}, 30.0, 29.99, std::string("exact, slow"), nan, 2.5});
  t.add_row({std::int64_t{2}, -0.5, -0.25, std::string(""), 1e300, 0.0});
  write_table_netcdf(dir / "sweep.nc", t, Provenance{});
  Reader r(dir / "sweep.nc");
  EXPECT_EQ(r.dim("row"), 3u);
  long long pts[3];
  const int vp = r.var("point");
  nc_type type = 0;
  ASSERT_EQ(nc_inq_vartype(r.id, vp, &type), NC_NOERR);
  EXPECT_EQ(type, NC_INT64);
  ASSERT_EQ(nc_get_var_longlong(r.id, vp, pts), NC_NOERR);
  EXPECT_EQ(pts[0], 0);
  EXPECT_EQ(pts[2], 2);
  EXPECT_EQ(r.doubles("sun__elevation_deg", 3), (std::vector<double>{5.0, 30.0, -0.5}));
  EXPECT_EQ(r.doubles("sun_elevation_deg", 3), (std::vector<double>{5.000000000000001, 29.99, -0.25}));
  EXPECT_EQ(r.text(r.var("sun__elevation_deg"), "atmosh_column"), "sun.elevation_deg");
  EXPECT_EQ(r.text(r.var("sun__elevation_deg"), "units"), "degree");
  EXPECT_EQ(r.text(r.var("sun__elevation_deg"), "standard_name"), "<none>");
  EXPECT_EQ(r.text(r.var("sun_elevation_deg"), "standard_name"), "solar_elevation_angle");
  EXPECT_EQ(r.text(r.var("point"), "units"), "<none>");
  const auto lum = r.doubles("zenith_luminance_cd_m2", 3);
  EXPECT_EQ(lum[0], 0.1 + 0.2);
  EXPECT_TRUE(std::isnan(lum[1]));
  EXPECT_EQ(lum[2], 1e300);
  EXPECT_EQ(r.text(r.var("zenith_luminance_cd_m2"), "units"), "cd m-2");
  EXPECT_EQ(r.doubles("time_s", 3)[0], 1e-300);
  char* s[3] = {nullptr, nullptr, nullptr};
  ASSERT_EQ(nc_get_var_string(r.id, r.var("method"), s), NC_NOERR);
  EXPECT_STREQ(s[0], "fast");
  EXPECT_STREQ(s[1], "exact, slow");
  EXPECT_STREQ(s[2], "");
  nc_free_string(3, s);
  fs::remove_all(dir);
}

TEST(Netcdf, TableRefusesMixedColumnsAndNameClashes) {
  const fs::path dir = fresh_dir("bad_table");
  CsvTable mixed({"a_s"});
  mixed.add_row({1.0});
  mixed.add_row({std::string("x")});
  EXPECT_THROW(write_table_netcdf(dir / "m.nc", mixed, Provenance{}), atmosh::InputError);
  CsvTable clash({"a.b", "a__b"});
  clash.add_row({1.0, 2.0});
  EXPECT_THROW(write_table_netcdf(dir / "c.nc", clash, Provenance{}), atmosh::InputError);
  CsvTable no_jd({"zenith_deg"});
  no_jd.add_row({1.0});
  EXPECT_THROW(write_table_netcdf(dir / "t.nc", no_jd, Provenance{}, sun_track_netcdf_options()), atmosh::InputError);
  EXPECT_FALSE(fs::exists(dir / "m.nc") || fs::exists(dir / "c.nc") || fs::exists(dir / "t.nc"));
  fs::remove_all(dir);
}

// J2000.0 = JD 2451545.0 = 2000-01-01T12:00:00 UTC (as TT, but the column is UTC
// Julian date, converted as such) = 946728000 s after the Unix epoch (IERS / Meeus,
// Astronomical Algorithms ch. 7: JD 2440587.5 = 1970-01-01T00:00).
fs::path write_test_sun_track(const fs::path& dir) {
  CsvTable t({"time_utc", "jd_utc", "zenith_deg", "azimuth_deg", "elevation_deg"});
  t.add_row({std::string("2000-01-01T12:00:00Z"), 2451545.0, 70.0, 180.0, 20.0});
  t.add_row({std::string("2000-01-01T18:00:00Z"), 2451545.25, 95.5, 250.0, -5.5});
  auto o = sun_track_netcdf_options();
  o.scalars["latitude"] = {48.0, "degrees_north", "latitude"};
  o.scalars["longitude"] = {11.5, "degrees_east", "longitude"};
  const fs::path file = dir / "sun_track.nc";
  write_table_netcdf(file, t, Provenance{}, o);
  return file;
}

TEST(Netcdf, SunTrackHasACfTimeCoordinate) {
  const fs::path dir = fresh_dir("track");
  const fs::path file = write_test_sun_track(dir);
  Reader r(file);
  EXPECT_EQ(r.dim("time"), 2u);
  const int vt = r.var("time");
  EXPECT_EQ(r.text(vt, "units"), "seconds since 1970-01-01 00:00:00 UTC");
  EXPECT_EQ(r.text(vt, "standard_name"), "time");
  const auto t = r.doubles("time", 2);
  EXPECT_NEAR(t[0], 946728000.0, 1e-4);
  EXPECT_NEAR(t[1], 946728000.0 + 6 * 3600.0, 1e-4);
  EXPECT_EQ(r.dims_of(r.var("zenith_deg")), std::vector<std::string>{"time"});
  EXPECT_EQ(r.text(r.var("zenith_deg"), "standard_name"), "solar_zenith_angle");
  EXPECT_EQ(r.text(r.var("azimuth_deg"), "standard_name"), "solar_azimuth_angle");
  EXPECT_EQ(r.doubles("elevation_deg", 2), (std::vector<double>{20.0, -5.5}));
  EXPECT_EQ(r.doubles("latitude", 1)[0], 48.0);
  EXPECT_EQ(r.text(r.var("longitude"), "units"), "degrees_east");
  fs::remove_all(dir);
}

TEST(Netcdf, XarrayReadsTheSameValues) {
  if (!have_xarray()) GTEST_SKIP() << "Debian python3-xarray / python3-netcdf4 not installed";
  const fs::path dir = fresh_dir("xarray");
  write_test_sky(dir);
  write_test_sun_track(dir);
  // The same closed forms as spectral_value / xyz_value, in numpy.
  const std::string script = R"(
import sys, numpy as np, xarray as xr
d = sys.argv[0].rsplit('/', 1)[0]
ds = xr.open_dataset(d + '/sky.nc')
assert ds.attrs['Conventions'] == 'CF-1.8'
L = ds['spectral_radiance']
assert L.dims == ('wavelength', 'elevation', 'azimuth'), L.dims
i, y, x = np.meshgrid(np.arange(3), np.arange(4), np.arange(6), indexing='ij')
assert np.array_equal(L.values, (1 + 100 * i + 10 * y + x).astype(np.float32))
assert float(L.sel(wavelength=550.0, elevation=22.5, azimuth=150.0)) == 1 + 100 + 10 + 2
assert L.attrs['units'] == 'W m-2 sr-1 nm-1'
yy, xx = np.meshgrid(np.arange(4), np.arange(6), indexing='ij')
assert np.array_equal(ds['Y'].values, (0.5 + 1000 + 7 * yy + 0.25 * xx).astype(np.float32))
assert float(ds['solar_zenith_angle']) == 60.0
assert list(ds['elevation'].values) == [67.5, 22.5, -22.5, -67.5]
tr = xr.open_dataset(d + '/sun_track.nc')
t = tr['time'].values
assert t[0] == np.datetime64('2000-01-01T12:00:00'), t
assert abs((t[1] - np.datetime64('2000-01-01T18:00:00')) / np.timedelta64(1, 'ms')) < 1, t
assert list(tr['zenith_deg'].values) == [70.0, 95.5]
assert tr['zenith_deg'].attrs['standard_name'] == 'solar_zenith_angle'
assert [str(s) for s in tr['time_utc'].values] == ['2000-01-01T12:00:00Z', '2000-01-01T18:00:00Z']
print('xarray check passed')
)";
  EXPECT_EQ(run_python(dir, script), 0);
  fs::remove_all(dir);
}

// The CSV outputs of real runs (a sweep, a sun range) converted with
// write_csv_as_netcdf; xarray reads the netCDF and pandas the CSV of the same run.
TEST(Netcdf, CliTablesConvertAndMatchTheirCsv) {
  const fs::path dir = fresh_dir("cli");
  std::ofstream(dir / "sweep.toml") << "version = 1\n[[parameter]]\nkey = \"sun.elevation_deg\"\nvalues = [5.0, 40.0]\n"
                                       "[[parameter]]\nkey = \"mie.scattering_per_m\"\nvalues = [2e-6, 8e-6]\n"
                                       "[[parameter]]\nkey = \"spectrum.count\"\nvalues = [8]\n";
  const std::string bin = ATMOSH_BIN;
  ASSERT_EQ(std::system((bin + " sweep " + (dir / "sweep.toml").string() + " -o " + (dir / "sw").string() +
                         " --scattering single --threads 1 > /dev/null 2>&1")
                            .c_str()),
            0);
  ASSERT_EQ(std::system((bin + " sun --lat 48 --lon 11.5 --from 2026-06-21T00:00:00Z --to 2026-06-22T00:00:00Z "
                               "--step 1h -o " +
                         (dir / "track.csv").string() + " > /dev/null 2>&1")
                            .c_str()),
            0);
  write_csv_as_netcdf(dir / "sw" / "sweep.csv", dir / "sweep.nc");
  auto o = sun_track_netcdf_options();
  write_csv_as_netcdf(dir / "track.csv", dir / "track.nc", o);

  // C API: every numeric cell of the sweep equals the CSV's number bit for bit.
  const CsvData csv = read_csv(dir / "sw" / "sweep.csv");
  ASSERT_EQ(csv.rows.size(), 4u);
  {
    Reader r(dir / "sweep.nc");
    EXPECT_EQ(r.dim("row"), 4u);
    EXPECT_EQ(r.text(NC_GLOBAL, "atmosh_sweep_id"), csv.provenance.at("sweep_id"));
    EXPECT_NE(r.text(NC_GLOBAL, "history").find("sweep"), std::string::npos);
    for (const char* col : {"zenith_luminance_cd_m2", "sun.elevation_deg", "sun_transmittance_550nm", "zenith_x"}) {
      const auto v = r.doubles(netcdf_variable_name(col), 4);
      for (std::size_t i = 0; i < 4; ++i) {
        const double want = csv.number(i, csv.column(col));
        if (std::isnan(want)) {
          EXPECT_TRUE(std::isnan(v[i])) << col;
        }
        else EXPECT_EQ(v[i], want) << col << " row " << i;
      }
    }
    EXPECT_EQ(r.text(r.var("sun_elevation_deg"), "standard_name"), "solar_elevation_angle");
  }
  if (!have_xarray()) GTEST_SKIP() << "Debian python3-xarray not installed";
  const std::string script = R"(
import sys, numpy as np, pandas as pd, xarray as xr
d = sys.argv[0].rsplit('/', 1)[0]
csv = pd.read_csv(d + '/sw/sweep.csv', comment='#', float_precision='round_trip')
ds = xr.open_dataset(d + '/sweep.nc')
for col in csv.columns:
    v = ds[col.replace('.', '__')]
    assert v.attrs['atmosh_column'] == col
    a, b = v.values, csv[col].values
    assert np.array_equal(a, b, equal_nan=True), (col, a, b)
assert ds['zenith_luminance_cd_m2'].attrs['units'] == 'cd m-2'
tr = xr.open_dataset(d + '/track.nc')
t = pd.read_csv(d + '/track.csv', comment='#', float_precision='round_trip')
assert tr.sizes['time'] == len(t) == 25
want = pd.to_datetime(t['time_utc']).dt.tz_localize(None).values
err_ms = np.abs((tr['time'].values - want) / np.timedelta64(1, 'ms'))
assert err_ms.max() < 1, err_ms.max()
assert np.array_equal(tr['zenith_deg'].values, t['zenith_deg'].values)
assert tr['zenith_deg'].attrs['standard_name'] == 'solar_zenith_angle'
print('xarray: sweep and sun track match their CSV')
)";
  EXPECT_EQ(run_python(dir, script), 0);
  fs::remove_all(dir);
}

// `atmosh sky --spectral` of a real run: the netCDF converted from its EXR holds the
// EXR's values on the netCDF axes (cube value at (wavelength i, row y, column x) =
// channel L_<i>nm at pixel (x, y)); a fisheye EXR is refused.
TEST(Netcdf, CliSkyExrConvertsValueForValue) {
  const fs::path dir = fresh_dir("clisky");
  const std::string bin = ATMOSH_BIN;
  const std::string common = " --size 12x6 --spectral --scattering single --threads 1 ";
  ASSERT_EQ(std::system((bin + " sky" + common + "-o " + (dir / "sky.exr").string() + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((bin + " sky" + common + "--projection fisheye -o " + (dir / "fish.exr").string() +
                         " > /dev/null 2>&1")
                            .c_str()),
            0);
  write_exr_sky_as_netcdf(dir / "sky.exr", dir / "sky.nc");
  EXPECT_THROW(write_exr_sky_as_netcdf(dir / "fish.exr", dir / "fish.nc"), atmosh::InputError);
  const ExrImage e = read_exr(dir / "sky.exr");
  Reader r(dir / "sky.nc");
  const std::size_t nw = r.dim("wavelength");
  ASSERT_GE(nw, 2u);
  EXPECT_EQ(r.dim("elevation"), 6u);
  EXPECT_EQ(r.dim("azimuth"), 12u);
  const auto wl = r.doubles("wavelength", nw);
  std::vector<float> cube(nw * 6 * 12);
  ASSERT_EQ(nc_get_var_float(r.id, r.var("spectral_radiance"), cube.data()), NC_NOERR);
  for (std::size_t i = 0; i < nw; ++i) {
    if (i > 0) {
      EXPECT_GT(wl[i], wl[i - 1]);
    }
    std::ostringstream name;
    name << "L_" << wl[i] << "nm";
    const auto& ch = e.channel(name.str());
    for (std::size_t p = 0; p < 72; ++p) ASSERT_EQ(cube[i * 72 + p], ch[p]) << name.str() << " pixel " << p;
  }
  std::vector<float> y(72);
  ASSERT_EQ(nc_get_var_float(r.id, r.var("Y"), y.data()), NC_NOERR);
  EXPECT_EQ(y, e.channel("Y"));
  EXPECT_GT(*std::max_element(y.begin(), y.begin() + 36), 0.0f);  // the upper half is lit
  EXPECT_NEAR(r.doubles("solar_zenith_angle", 1)[0], 90.0 - e.float_attributes.at("sun_elevation_deg"), 1e-9);
  EXPECT_EQ(r.text(NC_GLOBAL, "atmosh_git_commit"), e.string_attributes.at("atmosh:git_commit"));
  EXPECT_NE(r.text(NC_GLOBAL, "history").find(" sky "), std::string::npos);
  fs::remove_all(dir);
}

// `atmosh sun --from --to -o FILE.nc` (or --format netcdf) writes the range as netCDF-CF
// directly: read back with the netCDF C API, every zenith angle equals the CSV's value
// of the same command bit for bit, the time coordinate is the rows' UTC instants, and
// the site is in the latitude / longitude scalars.
TEST(Netcdf, CliSunRangeWritesNetcdf) {
  const fs::path dir = fresh_dir("cli_sun");
  const std::string bin = ATMOSH_BIN;
  const std::string range = " sun --lat 48 --lon 11.5 --from 2026-06-21T00:00:00Z --to 2026-06-21T06:00:00Z --step 1h ";
  ASSERT_EQ(std::system((bin + range + "-o " + (dir / "track.csv").string() + " 2>/dev/null").c_str()), 0);
  ASSERT_EQ(std::system((bin + range + "-o " + (dir / "track.nc").string() + " 2>/dev/null").c_str()), 0);
  ASSERT_EQ(std::system((bin + range + "--format netcdf -o " + (dir / "track_fmt.nc").string() + " 2>/dev/null").c_str()), 0);
  // Bad format: exit 2 before any work.
  EXPECT_EQ(WEXITSTATUS(std::system((bin + range + "--format xml -o " + (dir / "x.nc").string() + " 2>/dev/null").c_str())), 2);
  EXPECT_FALSE(fs::exists(dir / "x.nc"));
  const CsvData csv = read_csv(dir / "track.csv");
  ASSERT_EQ(csv.rows.size(), 7u);
  for (const fs::path& f : {dir / "track.nc", dir / "track_fmt.nc"}) {
    Reader r(f);
    EXPECT_EQ(r.dim("time"), 7u);
    const auto t = r.doubles("time", 7);
    for (std::size_t i = 0; i < 7; ++i) EXPECT_NEAR(t[i], 1782000000.0 + 3600.0 * i, 1e-3) << i;  // 2026-06-21T00:00Z
    const auto z = r.doubles("zenith_deg", 7);
    for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(z[i], csv.number(i, csv.column("zenith_deg"))) << i;
    EXPECT_EQ(r.text(r.var("zenith_deg"), "standard_name"), "solar_zenith_angle");
    EXPECT_EQ(r.doubles("latitude", 1)[0], 48.0);
    EXPECT_EQ(r.doubles("longitude", 1)[0], 11.5);
    EXPECT_EQ(r.text(NC_GLOBAL, "Conventions"), "CF-1.8");
  }
  fs::remove_all(dir);
}

// `atmosh sky -o FILE.nc` (or --format netcdf) writes netCDF-CF directly: the same
// pixels as the EXR of the same command (Y, and the spectral cube channel by channel,
// bit for bit: both are the render's float32 values), the sun's zenith angle exactly 90
// minus the elevation asked for; fisheye, a .exr name with --format netcdf and --png are
// bad input (exit 2, nothing written).
TEST(Netcdf, CliSkyWritesNetcdf) {
  const fs::path dir = fresh_dir("clisky_nc");
  const std::string bin = ATMOSH_BIN;
  const std::string common = " sky --sun-elevation 12 --size 12x6 --spectral --scattering single --threads 1 ";
  ASSERT_EQ(std::system((bin + common + "-o " + (dir / "sky.exr").string() + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((bin + common + "-o " + (dir / "sky.nc").string() + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((bin + common + "--format netcdf -o " + (dir / "fmt.nc").string() + " --json > " +
                         (dir / "fmt.json").string() + " 2>/dev/null")
                            .c_str()),
            0);
  for (const std::string& bad : {"--projection fisheye -o " + (dir / "f.nc").string(),
                                "--format netcdf -o " + (dir / "b.exr").string(),
                                "-o " + (dir / "p.nc").string() + " --png " + (dir / "p.png").string()}) {
    EXPECT_EQ(WEXITSTATUS(std::system((bin + common + bad + " > /dev/null 2>&1").c_str())), 2) << bad;
  }
  for (const char* f : {"f.nc", "b.exr", "p.nc", "p.png"}) EXPECT_FALSE(fs::exists(dir / f)) << f;
  {  // the JSON summary names the netCDF file, and no EXR
    std::ifstream in(dir / "fmt.json");
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(json.find("\"netcdf\": \"" + (dir / "fmt.nc").string() + "\""), std::string::npos) << json;
    EXPECT_NE(json.find("\"exr\": null"), std::string::npos) << json;
  }
  const ExrImage e = read_exr(dir / "sky.exr");
  for (const fs::path& f : {dir / "sky.nc", dir / "fmt.nc"}) {
    Reader r(f);
    const std::size_t nw = r.dim("wavelength");
    ASSERT_GE(nw, 2u);
    EXPECT_EQ(r.dim("elevation"), 6u);
    EXPECT_EQ(r.dim("azimuth"), 12u);
    std::vector<float> y(72);
    ASSERT_EQ(nc_get_var_float(r.id, r.var("Y"), y.data()), NC_NOERR);
    EXPECT_EQ(y, e.channel("Y"));
    std::vector<float> cube(nw * 72);
    ASSERT_EQ(nc_get_var_float(r.id, r.var("spectral_radiance"), cube.data()), NC_NOERR);
    std::size_t matched = 0;  // each cube plane equals one L_<nm>nm channel of the EXR
    for (std::size_t i = 0; i < nw; ++i)
      for (std::size_t c = 0; c < e.channels.size(); ++c)
        if (e.channels[c].rfind("L_", 0) == 0 &&
            std::equal(e.data[c].begin(), e.data[c].end(), cube.begin() + static_cast<long>(i * 72))) {
          ++matched;
          break;
        }
    EXPECT_EQ(matched, nw);
    EXPECT_EQ(r.doubles("solar_zenith_angle", 1)[0], 90.0 - 12.0);
    EXPECT_EQ(r.text(NC_GLOBAL, "Conventions"), "CF-1.8");
  }
  fs::remove_all(dir);
}

// write_sweep_netcdf decides grid or points from the table alone: a complete grid (rows in
// any order) gets one dimension per key with every value at its coordinates; a grid with a
// point missing, or a combination twice, gets the `point` dimension. Values are placed by
// the keys' values, so a shuffled grid reads back at the right coordinates.
TEST(Netcdf, SweepGridOrPoints) {
  const fs::path dir = fresh_dir("sweep_layout");
  const std::vector<std::string> keys = {"sun.elevation_deg", "mie.scattering_per_m"};
  auto table = [](const std::vector<std::array<double, 2>>& pts) {
    CsvTable t({"point", "sun.elevation_deg", "mie.scattering_per_m", "zenith_luminance_cd_m2"});
    std::int64_t i = 0;
    // The output is a known function of the keys: 1000 * elevation + 1e6 * mie.
    for (const auto& p : pts) t.add_row({i++, p[0], p[1], 1000.0 * p[0] + 1e6 * p[1]});
    return t;
  };
  Provenance prov;
  prov.add("sweep_id", "0123456789abcdef");
  // 3 x 2 grid, rows shuffled (e.g. merged in another order).
  write_sweep_netcdf(dir / "grid.nc", table({{40, 2e-6}, {5, 2e-6}, {5, 8e-6}, {60, 8e-6}, {40, 8e-6}, {60, 2e-6}}),
                     prov, keys);
  {
    Reader r(dir / "grid.nc");
    EXPECT_EQ(r.text(NC_GLOBAL, "atmosh_sweep_layout"), "grid");
    EXPECT_EQ(r.text(NC_GLOBAL, "atmosh_sweep_id"), "0123456789abcdef");
    EXPECT_EQ(r.dims_of(r.var("zenith_luminance_cd_m2")),
              (std::vector<std::string>{"sun__elevation_deg", "mie__scattering_per_m"}));
    const auto el = r.doubles("sun__elevation_deg", 3), mie = r.doubles("mie__scattering_per_m", 2);
    EXPECT_EQ(el, (std::vector<double>{40, 5, 60}));  // order of first appearance
    EXPECT_EQ(mie, (std::vector<double>{2e-6, 8e-6}));
    const auto z = r.doubles("zenith_luminance_cd_m2", 6);
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 2; ++j) EXPECT_EQ(z[i * 2 + j], 1000.0 * el[i] + 1e6 * mie[j]) << i << "," << j;
    EXPECT_EQ(r.text(r.var("sun__elevation_deg"), "standard_name"), "solar_elevation_angle");
    EXPECT_EQ(r.text(r.var("mie__scattering_per_m"), "units"), "m-1");
  }
  // A point missing, and a combination twice: points.
  for (const auto& pts : {std::vector<std::array<double, 2>>{{5, 2e-6}, {5, 8e-6}, {40, 2e-6}},
                          std::vector<std::array<double, 2>>{{5, 2e-6}, {5, 8e-6}, {5, 2e-6}, {5, 8e-6}}}) {
    write_sweep_netcdf(dir / "points.nc", table(pts), prov, keys);
    Reader r(dir / "points.nc");
    EXPECT_EQ(r.text(NC_GLOBAL, "atmosh_sweep_layout"), "points");
    EXPECT_EQ(r.dim("point"), pts.size());
    EXPECT_EQ(r.text(r.var("zenith_luminance_cd_m2"), "coordinates"), "sun__elevation_deg mie__scattering_per_m");
    const auto z = r.doubles("zenith_luminance_cd_m2", pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(z[i], 1000.0 * pts[i][0] + 1e6 * pts[i][1]);
  }
  EXPECT_THROW(write_sweep_netcdf(dir / "x.nc", table({{5, 2e-6}}), prov, {"no.such_key"}), atmosh::InputError);
  fs::remove_all(dir);
}

// write_table_files writes the CSV and the netCDF from one table; a stem ending in .nc
// selects netCDF; --format values other than csv and netcdf are refused.
TEST(Netcdf, TableFilesAndFormatOption) {
  const fs::path dir = fresh_dir("table_files");
  bool nc = false;
  EXPECT_EQ(table_output_stem(dir / "a.nc", nc), dir / "a");
  EXPECT_TRUE(nc);
  nc = false;
  EXPECT_EQ(table_output_stem(dir / "a", nc), dir / "a");
  EXPECT_FALSE(nc);
  EXPECT_FALSE(parse_table_format("csv"));
  EXPECT_TRUE(parse_table_format("netcdf"));
  EXPECT_THROW(parse_table_format("hdf5"), atmosh::InputError);
  CsvTable t({"sun_elevation_deg", "zenith_luminance_cd_m2"});
  t.add_row({-3.0, 0.25});
  t.add_row({4.0, 1e3});
  NetcdfTableOptions o;
  o.coordinate_column = "sun_elevation_deg";
  const auto files = write_table_files(dir / "t.csv", t, Provenance{}, true, o);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[1], dir / "t.nc");
  Reader r(dir / "t.nc");
  EXPECT_EQ(r.dim("sun_elevation_deg"), 2u);
  EXPECT_EQ(r.doubles("sun_elevation_deg", 2), (std::vector<double>{-3.0, 4.0}));
  EXPECT_EQ(r.doubles("zenith_luminance_cd_m2", 2), (std::vector<double>{0.25, 1e3}));
  EXPECT_EQ(r.text(r.var("sun_elevation_deg"), "standard_name"), "solar_elevation_angle");
  const CsvData back = read_csv(dir / "t.csv");
  EXPECT_EQ(back.rows.size(), 2u);
  fs::remove_all(dir);
}
