"""atmosh.studies against the command line: each study's DataFrame has the columns (names
and order) and the values of the CSV `atmosh` writes for the same input (run times
aside: they are measured per run), provenance in attrs; the sky image as an
xarray.Dataset agrees with the numpy image; bad input raises atmosh.InputError."""

import os
import subprocess

import numpy as np
import pandas as pd
import pytest

import atmosh
from atmosh import studies

from conftest import _cli_path

QUALITY = dict(shells=8, segments=4)  # quick sky tables, the same on both sides
QUALITY_ARGS = ["--shells", "8", "--segments", "4"]


@pytest.fixture(scope="module")
def run_cli():
    path = _cli_path()
    if path is None:
        pytest.skip("the atmosh command line is not built")

    def run(*args):
        subprocess.run([path, *map(str, args)], capture_output=True, text=True, check=True)

    return run


def read_csv(path):
    return pd.read_csv(path, comment="#", float_precision="round_trip")


def provenance(path):
    out = {}
    with open(path) as f:
        for line in f:
            if not line.startswith("# "):
                break
            k, _, v = line[2:].rstrip("\n").partition(": ")
            out[k] = v
    return out


def assert_same_table(df, csv_path, skip=(), prov_skip=()):
    """Same columns in the same order, same row count, every cell equal (numbers exactly:
    the CSV holds round-trip doubles; NaN where the CSV has NaN)."""
    ref = read_csv(csv_path)
    assert list(df.columns) == list(ref.columns)
    assert df.shape == ref.shape
    for c in ref.columns:
        if c in skip:
            continue
        if ref[c].dtype == object:
            assert list(df[c]) == list(ref[c]), c
        else:
            np.testing.assert_array_equal(df[c].to_numpy(np.float64), ref[c].to_numpy(np.float64), err_msg=c)
    # The provenance of the CSV, but for the entries that name this run (and the commit:
    # the module and the command line may be built at different states of the tree).
    prov = provenance(csv_path)
    for k in set(prov) - {"command_line", "run_utc", "threads", "git_commit"} - set(prov_skip):
        if "time" in k:  # measured run times (reference_time_s, ...)
            continue
        assert df.attrs.get(k) == prov[k], k


def test_sun_elevation_matches_cli(run_cli, tmp_path):
    run_cli("study", "sun-elevation", "--from", -5, "--to", 30, "--step", 5, *QUALITY_ARGS, "-o", tmp_path)
    df = studies.sun_elevation(from_deg=-5, to_deg=30, step_deg=5, **QUALITY)
    assert df.shape[0] == 8  # -5, 0, ..., 30
    np.testing.assert_array_equal(df["sun_elevation_deg"], np.arange(-5.0, 31.0, 5.0))
    assert_same_table(df, tmp_path / "sun_elevation.csv")


def test_day_matches_cli(run_cli, tmp_path):
    run_cli("study", "day", "--lat", 48, "--lon", 11, "--date", "2024-06-21", "--step", "6h", "--no-frames",
            *QUALITY_ARGS, "-o", tmp_path)
    df = studies.day(48, 11, "2024-06-21", step_s=6 * 3600, step_text="6h", **QUALITY)
    assert list(df["time_utc"])[:2] == ["2024-06-21T00:00:00Z", "2024-06-21T06:00:00Z"]
    assert df.shape[0] == 4
    assert_same_table(df, tmp_path / "day.csv")


def test_sun_accuracy_matches_cli(run_cli, tmp_path):
    run_cli("sun", "accuracy", "--year", 2024, "--latitudes", "0,45", "--samples", 200, "-o", tmp_path / "acc")
    df = studies.sun_accuracy(2024, [0, 45], 200)
    assert_same_table(df, tmp_path / "acc.csv", skip=("time_s",))
    assert (df["error_max_deg"] >= df["error_rms_deg"]).all()


def test_converge_lut_matches_cli(run_cli, tmp_path):
    run_cli("converge", "lut", "--shells", 16, "--directions", 32, "-o", tmp_path / "lut")
    df = studies.converge_lut(shells=[16], directions=[32])
    skip = [c for c in df.columns if "time" in c]
    assert_same_table(df, tmp_path / "lut.csv", skip=skip)


def test_converge_sky_matches_cli(run_cli, tmp_path):
    run_cli("converge", "sky", "--quick", "-o", tmp_path / "sky")
    df = studies.converge_sky(quick=True)
    skip = [c for c in df.columns if "time" in c]
    assert_same_table(df, tmp_path / "sky.csv", skip=skip)


def test_converge_ms_matches_cli(run_cli, tmp_path):
    run_cli("converge", "ms", "--quick", "-o", tmp_path)
    df = studies.converge_ms(quick=True)
    skip = [c for c in df.columns if "time" in c]
    assert_same_table(df, tmp_path / "ms_convergence.csv", skip=skip)


def test_converge_sh_matches_cli(run_cli, tmp_path):
    run_cli("sky", "--sun-elevation", 20, "--size", "32x16", "--shells", 16, "--segments", 8, "-o",
            tmp_path / "sky.exr")
    run_cli("converge", "sh", tmp_path / "sky.exr", "--bands", 3, "--quick", "-o", tmp_path / "sh")
    df = studies.converge_sh(tmp_path / "sky.exr", 3, quick=True)
    assert_same_table(df, tmp_path / "sh.csv", skip=("time_s",))
    assert df["error_max_rel"].iloc[0] == 0  # the reference row


def test_sweep_point_is_the_sun_elevation_row():
    # The built-in scene's sun, then the sun-elevation study at that elevation and
    # azimuth: the same sky but for the Earth-Sun distance d (the sweep point takes the
    # scene date's, the study 1 au), so every luminance and colour scales by one factor
    # 1/d^2 with d in [0.983, 1.017] au (perihelion, aphelion); the chromaticities and the
    # transmittance agree.
    p = studies.sweep_point(**QUALITY)
    assert p.shape[0] == 1 and "table_build_time_s" in p.columns
    el, az = float(p["sun_elevation_deg"][0]), float(p["sun_azimuth_deg"][0])
    row = studies.sun_elevation(from_deg=el, to_deg=el, step_deg=1, azimuth_deg=az, **QUALITY)
    ratios = []
    for c in row.columns[1:]:
        if c.endswith(("_x", "_y", "_transmittance_550nm")):  # not scaled by 1/d^2
            np.testing.assert_allclose(p[c][0], row[c][0], rtol=1e-5, err_msg=c)
        elif row[c][0] != 0:
            ratios.append(p[c][0] / row[c][0])
    assert ratios
    np.testing.assert_allclose(ratios, ratios[0], rtol=1e-5)
    assert 1 / 1.017**2 <= ratios[0] <= 1 / 0.983**2


def test_sky_dataset_matches_image():
    ds = studies.sky_dataset((20.0, 180.0), width=16, height=8, **QUALITY)
    img = atmosh.sky.image((20.0, 180.0), width=16, height=8, spectral=True, **QUALITY)
    assert ds["Y"].shape == (8, 16) and ds["spectral_radiance"].dims == ("elevation_deg", "azimuth_deg",
                                                                         "wavelength_nm")
    np.testing.assert_array_equal(ds["Y"].values, img["xyz"][..., 1])
    np.testing.assert_array_equal(ds["spectral_radiance"].values, img["spectral"])
    np.testing.assert_allclose(ds["elevation_deg"].values, 90 - (np.arange(8) + 0.5) * 180 / 8)
    np.testing.assert_allclose(ds["azimuth_deg"].values, (np.arange(16) + 0.5) * 360 / 16)
    assert ds["Y"].attrs["units"] == "cd m-2" and ds["spectral_radiance"].attrs["units"] == "W m-2 sr-1 nm-1"
    # The zenith row is brighter than nothing and the image is finite.
    assert np.isfinite(ds["Y"].values).all() and (ds["Y"].values[0] > 0).all()


@pytest.mark.parametrize("call", [
    lambda: studies.sun_elevation(from_deg=-100),
    lambda: studies.sun_elevation(from_deg=0, to_deg=10, step_deg=0),
    lambda: studies.sun_elevation(from_deg=10, to_deg=0),
    lambda: studies.day(95, 0, "2024-06-21"),
    lambda: studies.day(0, 0, "2024-6-21"),
    lambda: studies.sun_accuracy(2024, [0], 0),
    lambda: studies.converge_lut(preset="no-such-preset"),
    lambda: studies.converge_sky(scene="/nonexistent/scene.toml"),
    lambda: studies.sweep([]),
    lambda: studies.converge_ms(quick=True, paths=-1),
    lambda: studies.converge_sh("/nonexistent.exr", 3),
    lambda: studies.sky_dataset((20.0, 180.0), width=4, height=2, projection="fisheye"),
])
def test_bad_input_raises(call):
    with pytest.raises(atmosh.InputError):
        call()


def test_bad_input_names_the_value_as_the_cli_does(run_cli):
    # The CLI checks --from itself (naming the option); the library names the value too.
    path = _cli_path()
    r = subprocess.run([path, "study", "sun-elevation", "--from", "-100", "-o", os.devnull], capture_output=True,
                       text=True)
    assert r.returncode == 2
    with pytest.raises(atmosh.InputError) as e:
        studies.sun_elevation(from_deg=-100)
    assert "-100" in str(e.value) and "-100" in r.stderr


# ---- the bindings added for the RT drivers, PRT converge, the zenith sweep, the SH
# window study and whole sweep files ------------------------------------------------------

def test_prt_converge_matches_cli(run_cli, tmp_path):
    run_cli("prt", "converge", "--scene-builtin", "sphere-on-plane", "--resolution", 4, "--strata", "2,3",
            "--reference-samples", 64, "--device", "cpu", "--pixels", "8x8", "--threads", 2, "-o", tmp_path / "prt")
    df = studies.prt_converge("sphere-on-plane", resolution=4, strata=(2, 3), reference_samples=64, pixels=(8, 8),
                              device="cpu", threads=2)
    assert list(df["method"]) == ["cpu-shadowed-jittered"] * 2 + ["cpu-pixel-shadowed-jittered"] * 2
    # gpu_method names how the device was chosen: "--device cpu" there, "device cpu" here
    assert_same_table(df, tmp_path / "prt.csv", skip=("time_s",), prov_skip=("gpu_method",))
    assert df.attrs["gpu_method"] == "not run (device cpu)"
    # more samples, less error (a 2x2 against a 3x3 stratification of the same reference)
    assert df["error_rms_rel"][1] < df["error_rms_rel"][0]


def test_gi_converge_matches_cli(run_cli, tmp_path):
    # Every method of the scene-lighting study at tiny settings: the same rows, errors and
    # provenance as `atmosh gi converge` (run times aside), and the images in out_dir.
    run_cli("gi", "converge", "--scene-builtin", "cornell-box", "--size", "8x8", "--bands-list", "1,2", "--grids", 2,
            "--path-samples", 2, "--radiosity-grids", 2, "--radiosity-bands", 1, "--radiosity-bounces", "0,1",
            "--lpv-grids", 4, "--reference-samples", 4, "--samples", 2, "--cube-size", 2, "--pixel-samples", 1,
            "--threads", 2, "-o", tmp_path / "gi")
    df = studies.gi_converge("cornell-box", out_dir=tmp_path / "py", size=(8, 8), bands=(1, 2), grids=(2,),
                             path_samples=(2,), radiosity_grids=(2,), radiosity_bands=(1,), radiosity_bounces=(0, 1),
                             lpv_grids=(4,), reference_samples=4, samples=2, cube_size=2, pixel_samples=1, threads=2)
    # per method, its bands in order (probes 1, 2, then probes-visibility 1, 2)
    assert list(df["method"][:5]) == ["path", "probes", "probes", "probes-visibility", "probes-visibility"]
    assert {"radiosity", "lpv"} <= set(df["method"])
    assert_same_table(df, tmp_path / "gi" / "gi_converge.csv", skip=("time_s", "build_s", "shade_s"))
    assert (tmp_path / "py" / "reference.exr").exists()
    with pytest.raises(atmosh.InputError, match="--samples"):
        studies.gi_converge("cornell-box", out_dir=tmp_path / "bad", samples=1)


def test_rt_slab_matches_cli_json(cli):
    args = dict(tau=0.5, omega=0.9, phase="hg", g=0.6, mu0=0.8, mu=0.6, phi_deg=30.0, ground_albedo=0.2,
                paths=4000, seed=7, threads=2)
    j = cli.json("rt", "slab", "--tau", 0.5, "--omega", 0.9, "--phase", "hg", "--g", 0.6, "--mu0", 0.8, "--mu", 0.6,
                 "--phi-deg", 30, "--ground-albedo", 0.2, "--paths", 4000, "--seed", 7, "--threads", 2)
    df = studies.rt_slab(**args)
    assert set(df.columns) == set(j)  # the JSON object's keys (printed sorted)
    for k, v in j.items():
        if k != "time_s":
            assert df[k][0] == v, k
    assert 0 < df["reflection"][0] < 1 and df["reflection_stderr"][0] > 0


def test_rt_sky_matches_cli_json(cli):
    j = cli.json("rt", "sky", "--sun-elevation", 20, "--view-elevation", 45, "--view-azimuth", 90, "--paths", 1600,
                 "--seed", 3, "--threads", 2)
    df = studies.rt_sky(20, 45, 90, paths=1600, seed=3, threads=2)
    np.testing.assert_array_equal(df["wavelength_nm"], j["wavelengths_nm"])
    np.testing.assert_array_equal(df["radiance_w_m2_sr_nm"], j["radiance_w_m2_sr_nm"])
    np.testing.assert_array_equal(df["radiance_stderr_w_m2_sr_nm"], j["radiance_stderr_w_m2_sr_nm"])
    for k, v in j.items():
        if k in ("time_s", "wavelengths_nm", "radiance_w_m2_sr_nm", "radiance_stderr_w_m2_sr_nm"):
            continue
        assert df.attrs[k] == v, k


def test_zenith_sweep_matches_the_scene_output(run_cli, tmp_path):
    # A scene whose one output is the optical-depth sweep (at 1000 m, as run_scene runs it).
    scene = tmp_path / "scene.toml"
    scene.write_text('version = 1\nname = "od"\n[[output]]\nkind = "optical-depth"\nfile = "od.csv"\n')
    run_cli("run", scene, "-o", tmp_path / "out")
    df = studies.zenith_sweep(scene=scene, altitude_m=1000.0)
    assert_same_table(df, tmp_path / "out" / "od.csv")
    assert df.shape[0] == 361 and df["zenith_deg"].iloc[-1] == 180.0
    # looking down from 1 km hits the ground; straight up the total is the vertical column
    assert df["hits_ground"].iloc[-1] == 1 and df["hits_ground"].iloc[0] == 0


def test_sh_windows_against_the_windowed_coefficients():
    # An independent check of two columns: l2_change_rel = |c_w - c| / |c| with the window
    # applied by atmosh.sh.apply_window, 0 for "none"; and the row order of the CSV.
    rng = np.random.default_rng(5)
    bands = 6
    c = rng.normal(size=bands * bands)
    c[0] = 4.0
    df = studies.sh_windows(c, bands)
    assert list(df.columns) == ["window", "delta_min_rel", "l2_change_rel", "irradiance_max_change_rel"]
    assert list(df["window"])[0] == "none"
    assert df["l2_change_rel"][0] == 0 and df["irradiance_max_change_rel"][0] == 0
    for i, w in enumerate(df["window"]):
        cw = atmosh.sh.apply_window(c, w)
        np.testing.assert_allclose(df["l2_change_rel"][i], np.linalg.norm(cw - c) / np.linalg.norm(c), rtol=1e-12,
                                   atol=1e-15, err_msg=w)
    assert df.attrs["sh_bands"] == "6"


SWEEP = """version = 1
[[parameter]]
key = "sun.elevation_deg"
values = [5.0, 30.0]
[[parameter]]
key = "mie.scattering_per_m"
values = [2e-6, 8e-6]
[[parameter]]
key = "scattering.method"
values = ["single"]
[[parameter]]
key = "spectrum.count"
values = [8]
"""


def test_sweep_file_matches_cli(run_cli, tmp_path):
    f = tmp_path / "sweep.toml"
    f.write_text(SWEEP)
    run_cli("sweep", f, *QUALITY_ARGS, "--threads", 1, "-o", tmp_path / "cli")
    df = studies.sweep_file(f, threads=1, **QUALITY)
    assert df.attrs["keys"] == ["sun.elevation_deg", "mie.scattering_per_m", "scattering.method", "spectrum.count"]
    assert list(df["sun.elevation_deg"]) == [5.0, 5.0, 30.0, 30.0]
    assert_same_table(df, tmp_path / "cli" / "sweep.csv", skip=("time_s", "table_build_time_s"))
    # with a folder: the CSV and the netCDF grid there
    d = studies.sweep_file(f, out_dir=tmp_path / "py", threads=1, netcdf=True, **QUALITY)
    assert (tmp_path / "py" / "sweep.csv").is_file() and (tmp_path / "py" / "sweep.nc").is_file()
    assert d.attrs["sweep_id"] == df.attrs["sweep_id"]
    # a sweep CSV (e.g. merged shards) converted afterwards: the keys from its sweep file
    xr = pytest.importorskip("xarray")
    atmosh.io.sweep_to_netcdf(tmp_path / "cli" / "sweep.csv", tmp_path / "merged.nc")
    with xr.open_dataset(tmp_path / "merged.nc") as ds, xr.open_dataset(tmp_path / "py" / "sweep.nc") as py:
        assert ds.attrs["atmosh_sweep_layout"] == "grid" == py.attrs["atmosh_sweep_layout"]
        assert ds["zenith_luminance_cd_m2"].dims == py["zenith_luminance_cd_m2"].dims
        np.testing.assert_array_equal(ds["zenith_luminance_cd_m2"].values, py["zenith_luminance_cd_m2"].values)


@pytest.mark.parametrize("call", [
    lambda: studies.rt_slab(tau=-1, omega=0.5, phase="isotropic", mu0=1, mu=1),
    lambda: studies.rt_slab(tau=1, omega=0.5, phase="mie", mu0=1, mu=1),
    lambda: studies.rt_sky(100, 45, 0),
    lambda: studies.rt_sky(20, 45, 0, sun_depth="fast"),
    lambda: studies.prt_converge(reference_samples=50),
    lambda: studies.prt_converge(mode="unshadowed"),
    lambda: studies.zenith_sweep(preset="no-such-preset"),
    lambda: studies.sh_windows([1.0, 0.0], 2),
    lambda: studies.sweep_file("/nonexistent/sweep.toml"),
])
def test_bad_input_of_the_new_bindings_raises(call):
    with pytest.raises(atmosh.InputError):
        call()
