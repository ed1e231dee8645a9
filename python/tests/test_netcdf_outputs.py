"""netCDF-CF written directly by the studies and sweeps (`--format netcdf`, or a stem ending
in .nc): each file opened with xarray and compared with the CSV of the same run, cell for
cell (every column, run times included: one run writes both from the same table), with
the CF attributes (Conventions, units, standard names, the time coordinate) and the
provenance (global attributes atmosh_<key>, history)."""

import subprocess

import numpy as np
import pandas as pd
import pytest

from conftest import _cli_path

xr = pytest.importorskip("xarray")

FAST = ["--shells", "8", "--segments", "4", "--scattering", "single"]  # quick sky tables


@pytest.fixture(scope="module")
def run_cli():
    path = _cli_path()
    if path is None:
        pytest.skip("the atmosh command line is not built")

    def run(*args):
        return subprocess.run([path, "-q", *map(str, args)], capture_output=True, text=True, check=True)

    return run


def read_csv(path):
    prov = {}
    with open(path) as f:
        for line in f:
            if not line.startswith("# "):
                break
            k, _, v = line[2:].rstrip("\n").partition(": ")
            prov[k] = v
    return pd.read_csv(path, comment="#", float_precision="round_trip"), prov


def var(column):
    """The netCDF name of a column (io::netcdf_variable_name)."""
    return column.replace(".", "__")


def assert_same(values, ref, name):
    if ref.dtype == object:
        assert [str(v) for v in values] == list(ref), name
    else:
        np.testing.assert_array_equal(np.asarray(values, dtype=np.float64), ref.to_numpy(np.float64), err_msg=name)


def assert_table(ds, csv_path, dim="row"):
    """Every column of the CSV is a variable over `dim` with the CSV's values; the CSV's
    provenance is in the global attributes."""
    ref, prov = read_csv(csv_path)
    assert ds.attrs["Conventions"] == "CF-1.8"
    assert ds.sizes[dim] == len(ref)
    for c in ref.columns:
        v = ds[var(c)]
        assert v.dims == (dim,), c
        assert v.attrs["atmosh_column"] == c
        assert_same(v.values, ref[c], c)
    for k, v in prov.items():
        assert ds.attrs["atmosh_" + k.replace(".", "_")] == v, k
    assert ds.attrs["history"].startswith(prov["run_utc"]) if "run_utc" in prov else ds.attrs["history"]
    return ref


def test_sun_elevation_study(run_cli, tmp_path):
    run_cli("study", "sun-elevation", "--from", -4, "--to", 10, "--step", 7, "--azimuth", 150, *FAST,
            "--format", "netcdf", "-o", tmp_path)
    with xr.open_dataset(tmp_path / "sun_elevation.nc") as ds:
        assert_table(ds, tmp_path / "sun_elevation.csv", dim="sun_elevation_deg")
        e = ds["sun_elevation_deg"]  # the coordinate: CF standard name and units
        assert list(e.values) == [-4.0, 3.0, 10.0]
        assert e.attrs["standard_name"] == "solar_elevation_angle" and e.attrs["units"] == "degree"
        assert float(ds["solar_azimuth_angle"]) == 150.0
        assert ds["solar_azimuth_angle"].attrs["standard_name"] == "solar_azimuth_angle"
        assert ds["zenith_luminance_cd_m2"].attrs["units"] == "cd m-2"
        assert "study sun-elevation" in ds.attrs["history"]
        # xarray selects by elevation
        assert float(ds["zenith_luminance_cd_m2"].sel(sun_elevation_deg=10.0)) > float(
            ds["zenith_luminance_cd_m2"].sel(sun_elevation_deg=3.0)) > 0


def test_day_study_has_a_cf_time_coordinate(run_cli, tmp_path):
    run_cli("study", "day", "--lat", 48.2, "--lon", 16.37, "--height", 200, "--date", "2024-06-21", "--step", "6h",
            "--no-frames", *FAST, "--format", "netcdf", "-o", tmp_path)
    with xr.open_dataset(tmp_path / "day.nc") as ds:
        ref = assert_table(ds, tmp_path / "day.csv", dim="time")
        # CF decoding turns seconds since 1970 into the CSV's UTC times.
        want = pd.to_datetime(ref["time_utc"]).dt.tz_localize(None).to_numpy("datetime64[ns]")
        np.testing.assert_array_equal(ds["time"].values, want)
        assert ds["time"].encoding["units"] == "seconds since 1970-01-01 00:00:00 UTC"
        assert ds["time"].attrs["standard_name"] == "time"
        assert float(ds["latitude"]) == 48.2 and ds["latitude"].attrs["units"] == "degree_north"
        assert float(ds["longitude"]) == 16.37 and ds["longitude"].attrs["standard_name"] == "longitude"
        assert ds["sun_azimuth_deg"].attrs["standard_name"] == "solar_azimuth_angle"
    with xr.open_dataset(tmp_path / "day.nc", decode_times=False) as raw:
        np.testing.assert_array_equal(raw["time"].values, [1718928000.0 + 6 * 3600 * i for i in range(4)])


@pytest.fixture(scope="module")
def sky_exr(run_cli, tmp_path_factory):
    p = tmp_path_factory.mktemp("exr") / "sky.exr"
    run_cli("sky", "--sun-elevation", 20, "--size", "32x16", *FAST, "-o", p)
    return p


CONVERGE = {
    # name: (arguments before -o, stem; "--format netcdf" or a stem ending in .nc)
    "sky": lambda d, exr: ["converge", "sky", "--quick", "-o", d / "sky.nc"],
    "lut": lambda d, exr: ["converge", "lut", "--shells", 16, "--directions", 32, "--format", "netcdf", "-o", d / "sky"],
    "sh": lambda d, exr: ["converge", "sh", exr, "--bands", 3, "--quick", "--format", "netcdf", "-o", d / "sky"],
    "prt": lambda d, exr: ["prt", "converge", "--scene-builtin", "sphere-on-plane", "--resolution", 4, "--strata", "2,3",
                           "--reference-samples", 64, "--device", "cpu", "--pixels", "8x8", "-o", d / "sky.nc"],
    "ms": lambda d, exr: ["converge", "ms", "--quick", "--paths", 400, "--format", "netcdf", "-o", d],
    "gi": lambda d, exr: ["gi", "converge", "--scene-builtin", "sphere-on-plane", "--resolution", 4, "--light",
                          "sun:0,40", "--size", "8x8", "--grids", 2, "--bands-list", 1, "--path-samples", 2,
                          "--reference-samples", 4, "--samples", 2, "--cube-size", 2, "--pixel-samples", 1,
                          "--format", "netcdf", "-o", d],
}
STEM = {"ms": "ms_convergence", "gi": "gi_converge"}


@pytest.mark.parametrize("name", sorted(CONVERGE))
def test_converge_studies(run_cli, tmp_path, sky_exr, name):
    run_cli(*CONVERGE[name](tmp_path, sky_exr))
    stem = tmp_path / STEM.get(name, "sky")
    with xr.open_dataset(stem.with_suffix(".nc")) as ds:
        ref = assert_table(ds, stem.with_suffix(".csv"))
        assert ds["time_s"].attrs["units"] == "s"
        assert "error_max_rel" in ref.columns and ds["error_max_rel"].attrs["units"] == "1"
        assert ds.attrs["title"]


SWEEP_GRID = """version = 1
[[parameter]]
key = "sun.elevation_deg"
values = [5.0, 40.0, 60.0]
[[parameter]]
key = "mie.scattering_per_m"
values = [2e-6, 8e-6]
[[parameter]]
key = "spectrum.count"
values = [8]
"""

SWEEP_ZIP = """version = 1
mode = "zip"
[[parameter]]
key = "sun.elevation_deg"
values = [5.0, 40.0, 5.0]
[[parameter]]
key = "mie.scattering_per_m"
values = [2e-6, 8e-6, 8e-6]
"""


def test_sweep_grid_has_the_parameters_as_coordinates(run_cli, tmp_path):
    (tmp_path / "grid.toml").write_text(SWEEP_GRID)
    run_cli("sweep", tmp_path / "grid.toml", *FAST, "--threads", 1, "--format", "netcdf", "-o", tmp_path / "g")
    ref, prov = read_csv(tmp_path / "g" / "sweep.csv")
    with xr.open_dataset(tmp_path / "g" / "sweep.nc") as ds:
        assert ds.attrs["atmosh_sweep_layout"] == "grid" and ds.attrs["atmosh_sweep_id"] == prov["sweep_id"]
        assert ds["zenith_luminance_cd_m2"].dims == ("sun__elevation_deg", "mie__scattering_per_m", "spectrum__count")
        assert list(ds["sun__elevation_deg"].values) == [5.0, 40.0, 60.0]
        assert ds["sun__elevation_deg"].attrs["standard_name"] == "solar_elevation_angle"
        assert ds["sun__elevation_deg"].attrs["units"] == "degree"
        assert ds["mie__scattering_per_m"].attrs["units"] == "m-1"
        assert list(ds["mie__scattering_per_m"].values) == [2e-6, 8e-6]
        # every CSV row at its coordinates, every column
        for _, row in ref.iterrows():
            at = ds.sel(sun__elevation_deg=row["sun.elevation_deg"], mie__scattering_per_m=row["mie.scattering_per_m"],
                        spectrum__count=row["spectrum.count"])
            for c in ref.columns:
                if c in ("sun.elevation_deg", "mie.scattering_per_m", "spectrum.count"):
                    continue
                a, b = float(at[var(c)]), float(row[c])
                assert a == b or (np.isnan(a) and np.isnan(b)), c


def test_sweep_zip_has_a_point_dimension(run_cli, tmp_path):
    (tmp_path / "zip.toml").write_text(SWEEP_ZIP)
    run_cli("sweep", tmp_path / "zip.toml", *FAST, "--threads", 1, "--format", "netcdf", "-o", tmp_path / "z")
    with xr.open_dataset(tmp_path / "z" / "sweep.nc") as ds:
        assert ds.attrs["atmosh_sweep_layout"] == "points"
        assert_table(ds, tmp_path / "z" / "sweep.csv", dim="point")
        # the CF `coordinates` attribute: xarray makes the keys coordinates of every variable
        assert ds["zenith_luminance_cd_m2"].encoding["coordinates"] == "sun__elevation_deg mie__scattering_per_m"
        assert {"sun__elevation_deg", "mie__scattering_per_m"} <= set(ds["zenith_luminance_cd_m2"].coords)


def test_bad_format_is_refused_before_work(run_cli, tmp_path):
    path = _cli_path()
    r = subprocess.run([path, "study", "sun-elevation", "--format", "hdf5", "-o", tmp_path], capture_output=True,
                       text=True)
    assert r.returncode == 2 and "--format: 'hdf5' is not csv or netcdf" in r.stderr
    assert not any(tmp_path.iterdir())
