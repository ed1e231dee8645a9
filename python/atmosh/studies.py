"""The studies as tables (atmosh/studies/*.hpp): each returns a pandas.DataFrame with the
columns of the CSV the atmosh command line writes for the same study (names and order,
units in the names: _deg, _cd_m2, _s, ...), and the provenance of that CSV's "# key:
value" lines in ``df.attrs`` (version, commit, time, host, study settings). Gridded
outputs (a sky image) become an xarray.Dataset: see sky_dataset.

Function                 command line
sun_elevation(...)       atmosh study sun-elevation -o DIR      (DIR/sun_elevation.csv)
day(...)                 atmosh study day -o DIR --no-frames    (DIR/day.csv)
sweep_point(...)         one row of atmosh sweep (the sky summary of a scene)
sweep(scenes)            one row per scene file
converge_sky(...)        atmosh converge sky -o STEM            (STEM.csv)
converge_lut(...)        atmosh converge lut -o STEM            (STEM.csv)
converge_ms(...)         atmosh converge ms -o DIR              (DIR/ms_convergence.csv)
converge_sh(exr, bands)  atmosh converge sh EXR --bands L -o STEM (STEM.csv)
sun_accuracy(...)        atmosh sun accuracy -o STEM            (STEM.csv)

Bad input raises atmosh.InputError with the library's one-line message.
"""

import numpy as np

from . import _atmosh

_st = _atmosh.studies

__all__ = ["sun_elevation", "day", "sweep_point", "sweep", "converge_sky", "converge_lut", "converge_ms",
           "converge_sh", "sun_accuracy", "sky_dataset"]


def _frame(t):
    import pandas as pd
    df = pd.DataFrame({c: t["data"][c] for c in t["columns"]}, columns=t["columns"])
    for c in t["columns"]:
        if df[c].dtype == object and all(isinstance(v, (int, float)) for v in t["data"][c]):
            df[c] = df[c].astype(np.float64)
    df.attrs.update(dict(t["provenance"]))
    return df


def _scene(scene):
    return None if scene is None else str(scene)


def sun_elevation(scene=None, from_deg=-18.0, to_deg=90.0, step_deg=1.0, azimuth_deg=180.0, shells=32, segments=16,
                  samples=2, threads=0):
    """Zenith and horizon colour and luminance against sun elevation (one row per
    elevation from from_deg while <= to_deg) at the scene's observer height.

    scene   a scene file (TOML); None: the built-in scene. Angles in degrees.
    shells, segments, samples, threads: the sky integrator's quality (as the CLI's).
    Columns as sun_elevation.csv: sun_elevation_deg, then the sky summary (luminance
    [cd/m^2], linear sRGB, chromaticities) of docs/studies.md."""
    return _frame(_st.sun_elevation(_scene(scene), float(from_deg), float(to_deg), float(step_deg),
                                    float(azimuth_deg), shells, segments, samples, threads))


def day(lat, lon, date, scene=None, height_m=0.0, step_s=600.0, step_text=None, shells=32, segments=16, samples=2,
        threads=0):
    """The sky every step_s seconds over the UTC day `date` (YYYY-MM-DD) at latitude
    `lat`, longitude `lon` [deg, east positive], height_m [m]: sun by NREL SPA, the sky
    summary at the day's Earth-Sun distance. Columns as day.csv (time_utc, sun angles
    [deg], the sky summary). No frames are rendered."""
    text = step_text if step_text is not None else f"{float(step_s):g}s"
    return _frame(_st.day(_scene(scene), float(lat), float(lon), float(height_m), str(date), float(step_s), text,
                          shells, segments, samples, threads))


def sweep_point(scene=None, shells=32, segments=16, samples=2, threads=0):
    """One sweep point: a one-row DataFrame of the scene's sky summary (sun from the
    scene), its sun elevation/azimuth [deg] and the table build time [s], the outputs
    columns of `atmosh sweep`."""
    import pandas as pd
    cols, vals = _st.sweep_point(_scene(scene), shells, segments, samples, threads)
    df = pd.DataFrame([vals], columns=cols)
    df.attrs["scene"] = "built-in" if scene is None else str(scene)
    return df


def sweep(scenes, **quality):
    """sweep_point over several scene files; one row per scene, with a `scene` column."""
    import pandas as pd
    rows = []
    for s in scenes:
        r = sweep_point(s, **quality)
        r.insert(0, "scene", "built-in" if s is None else str(s))
        rows.append(r)
    if not rows:
        raise _atmosh.InputError("scenes: no scene given")
    return pd.concat(rows, ignore_index=True)


def converge_sky(scene=None, quick=False, threads=0):
    """The fast sky integrator's error against the exact reference and its run time
    (columns as sky_convergence.csv: method, setting, error_max_rel, error_rms_rel,
    time_s, ...). time_s is measured on this machine."""
    return _frame(_st.converge_sky(_scene(scene), bool(quick), threads))


def converge_lut(scene=None, preset=None, quick=False, shells=(), directions=()):
    """The optical-depth tables against the exact reference at 550 nm (columns as
    lut_convergence.csv). scene or preset (default earth-graphics), as the CLI."""
    return _frame(_st.converge_lut(_scene(scene), preset, bool(quick), list(shells), list(directions)))


def converge_ms(scene=None, quick=False, paths=0, seed=1):
    """The sky's scattering methods (single, orders, approximate) against a Monte-Carlo
    reference of all orders, by band (day, civil, ...): columns as ms_convergence.csv.
    paths: Monte-Carlo paths per reference row (0: 16000 quick, 128000 full); seed: the
    reference's RNG seed."""
    return _frame(_st.converge_ms(_scene(scene), bool(quick), int(paths), int(seed)))


def converge_sh(exr, bands, quick=False, seed=1, layout="auto"):
    """SH projection methods and sample counts of an EXR image (equirect 2:1 or cube
    cross) against its exact quadrature: columns as `atmosh converge sh`'s CSV."""
    return _frame(_st.converge_sh(str(exr), int(bands), bool(quick), int(seed), str(layout)))


def sun_accuracy(year=2024, latitudes_deg=(-75, -45, 0, 30, 60, 85), samples=20000):
    """The fast solar-position algorithms' error [deg] against NREL SPA over a year
    (columns as sun_accuracy.csv: error_max_deg, error_rms_deg, time per evaluation)."""
    return _frame(_st.sun_accuracy(int(year), [float(v) for v in latitudes_deg], int(samples)))


def sky_dataset(sun, atmosphere=None, width=256, height=128, spectral=True, projection="equirect", **kwargs):
    """A sky image as an xarray.Dataset (atmosh.sky.image(..., as_xarray=True)):
    coordinates elevation_deg, azimuth_deg, wavelength_nm (with units), variables X, Y, Z
    (Y = luminance [cd m-2]), srgb_r/g/b, valid, spectral_radiance [W m-2 sr-1 nm-1].
    Equirect only (InputError otherwise)."""
    from . import sky
    return sky.image(sun, atmosphere, width, height, projection, spectral=spectral, as_xarray=True, **kwargs)
