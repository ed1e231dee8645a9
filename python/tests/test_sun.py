"""atmosh.sun against `atmosh sun` (the same C++ entry point) and the NREL SPA report."""

import io

import numpy as np
import pandas as pd
import pytest

import atmosh
from conftest import cli_message

# Reda & Andreas (2008), NREL/TP-560-34302, Table A4.1 example: 2003-10-17 12:30:30
# local time (-7 h), 39.742476 N, 105.1786 W, 1830.14 m, 820 mbar, 11 C, Delta T 67 s,
# UT1 - UTC 0 -> topocentric zenith 50.11162 deg, azimuth 194.34024 deg (Table A5.1),
# geometric elevation e0 = 39.872046 deg; pvlib's test prints its equation of time as 14.64 min.
SPA_EXAMPLE = dict(latitude=39.742476, longitude=-105.1786, height=1830.14, pressure=820.0, temperature=11.0,
                   delta_t=67.0, delta_ut1=0.0)


def test_spa_report_example_and_cli(cli):
    t = np.array(["2003-10-17T19:30:30"], dtype="datetime64[s]")
    df = atmosh.sun.position(t, **SPA_EXAMPLE)
    assert isinstance(df, pd.DataFrame) and len(df) == 1
    r = df.iloc[0]
    assert abs(r["apparent_zenith_deg"] - 50.11162) < 5e-6
    assert abs(r["azimuth_deg"] - 194.34024) < 5e-6
    assert abs(r["elevation_deg"] - 39.872046) < 5e-7
    assert abs(r["equation_of_time_min"] - 14.64) < 5e-3
    j = cli.json("sun", "--lat", 39.742476, "--lon", -105.1786, "--height", 1830.14, "--pressure", 820,
                 "--temperature", 11, "--delta-t", 67, "--delta-ut1", 0, "--time", "2003-10-17T12:30:30-07:00")
    for k in ("zenith_deg", "azimuth_deg", "elevation_deg", "apparent_zenith_deg", "apparent_elevation_deg",
              "declination_deg", "hour_angle_deg", "equation_of_time_min", "earth_sun_distance_au"):
        assert r[k] == pytest.approx(j[k], rel=0, abs=1e-9), k


@pytest.mark.parametrize("algorithm", ["spa", "fast"])
def test_time_series_matches_cli_csv(cli, algorithm):
    text = cli.text("sun", "--lat", 48.2, "--lon", 16.37, "--height", 200, "--from", "2024-06-21T00:00Z",
                    "--to", "2024-06-22T00:00Z", "--step", "20min", "--algorithm", algorithm)
    ref = pd.read_csv(io.StringIO(text), comment="#")
    times = pd.date_range("2024-06-21", "2024-06-22", freq="20min")
    df = atmosh.sun.position(times, 48.2, 16.37, 200.0, algorithm=algorithm)
    assert len(df) == len(ref) == 73
    assert (df.index == times).all()
    for k in ("zenith_deg", "azimuth_deg", "apparent_elevation_deg", "equation_of_time_min", "hour_angle_deg"):
        # A Julian day from datetime64 and from the ISO string differ by rounding (~1e-5 s).
        np.testing.assert_allclose(df[k].to_numpy(), ref[k].to_numpy(), rtol=0, atol=1e-7, err_msg=k)


def test_broadcasting_timezones_and_shapes():
    t = np.array(["2024-03-20T12:00", "2024-03-20T18:00"], dtype="datetime64[m]")
    lat = np.array([[0.0], [45.0], [-60.0]])
    d = atmosh.sun.position(t, lat, 10.0, output="dict")
    assert d["zenith_deg"].shape == (3, 2)
    one = atmosh.sun.position(t[1:], -60.0, 10.0, output="dict")
    assert d["zenith_deg"][2, 1] == one["zenith_deg"][0]
    # tz-aware pandas times and ISO strings with offsets are the same instants
    local = pd.DatetimeIndex(["2024-03-20T14:00"]).tz_localize("Europe/Vienna")
    a = atmosh.sun.position(local, 45.0, 10.0, output="dict")
    b = atmosh.sun.position(["2024-03-20T14:00+01:00"], 45.0, 10.0, output="dict")
    # (Julian days from datetime64 and from text may differ by an ulp, 40 us ~ 2e-7 deg)
    assert a["azimuth_deg"][0] == pytest.approx(b["azimuth_deg"][0], abs=1e-6)
    empty = atmosh.sun.position(np.array([], dtype="datetime64[s]"), 0.0, 0.0)
    assert len(empty) == 0 and "elevation_deg" in empty.columns
    assert len(atmosh.sun.position(t[:1], 0.0, 0.0)) == 1
    assert len(atmosh.sun.position(t[0], 0.0, 0.0)) == 1  # a scalar instant
    # instants outside numpy's nanosecond range (1677..2262) within SPA's -2000..6000
    far = np.array(["-1500-03-01T06:00", "1000-06-01T12:00", "4000-12-31T23:59"], dtype="datetime64[m]")
    iso = ["-1500-03-01T06:00Z", "1000-06-01T12:00Z", "4000-12-31T23:59Z"]
    np.testing.assert_allclose(atmosh.sun.julian_day(far), atmosh.sun.julian_day(iso), rtol=0, atol=1e-9)


def test_bad_input_raises_the_cli_message(cli):
    code, err = cli.error("sun", "--lat", 10, "--lon", 0, "--time", "7000-01-01T00:00Z")
    assert code == 2
    with pytest.raises(atmosh.InputError) as e:
        atmosh.sun.position(["7000-01-01T00:00Z"], 10.0, 0.0)
    assert str(e.value) == cli_message(err)
    assert isinstance(e.value, ValueError)
    with pytest.raises(atmosh.InputError, match="latitude"):
        atmosh.sun.position(np.array(["2024-01-01"], dtype="datetime64[D]"), 95.0, 0.0)
    with pytest.raises(atmosh.InputError, match="2010"):  # the fast algorithm's range
        atmosh.sun.position(np.array(["2200-01-01"], dtype="datetime64[D]"), 0.0, 0.0, algorithm="fast")
    with pytest.raises(atmosh.InputError, match="NaT"):
        atmosh.sun.position(np.array(["NaT"], dtype="datetime64[s]"), 0.0, 0.0)
