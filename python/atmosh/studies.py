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
sweep_file(path)         atmosh sweep FILE -o DIR               (DIR/sweep.csv, DIR/sweep.nc)
zenith_sweep(...)        the scene output kind optical-depth    (STEM.csv)
sh_windows(coeffs, L)    the main job's SH window table         (sh_windows.csv)
prt_converge(...)        atmosh prt converge -o STEM            (STEM.csv)
gi_converge(...)         atmosh gi converge -o DIR              (DIR/gi_converge.csv)
rt_slab(...)             atmosh rt slab --json                  (one row: the JSON's fields)
rt_sky(...)              atmosh rt sky --json                   (a row per wavelength; scalars in attrs)

Every table comes from the library's own table of the study (the one the CLI's CSV and
netCDF files are written from), so the columns cannot drift from the CSV's.

Bad input raises atmosh.InputError with the library's one-line message.
"""

import numpy as np

from . import _atmosh

_st = _atmosh.studies

__all__ = ["sun_elevation", "day", "sweep_point", "sweep", "sweep_file", "converge_sky", "converge_lut",
           "converge_ms", "converge_sh", "sun_accuracy", "sky_dataset", "zenith_sweep", "sh_windows", "prt_converge", "gi_converge",
           "rt_slab", "rt_sky"]


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


def sweep_file(path, out_dir=None, shells=32, segments=16, samples=2, threads=0, netcdf=False):
    """Runs a whole sweep file (TOML, docs/sweeps.md) as `atmosh sweep FILE -o DIR` does:
    one row per point (point, one column per parameter key, the sky summary, time_s),
    the sweep's provenance (sweep, sweep_id, base_scene, settings) in df.attrs and its
    parameter keys in df.attrs["keys"]. out_dir: where the sweep writes its journal and
    sweep.csv (a temporary folder, removed afterwards, when None; a folder holding an
    earlier run of the same sweep is refused, as the CLI without --resume). netcdf: also
    out_dir/sweep.nc (grid coordinates, see atmosh.io docs/outputs.md)."""
    import tempfile
    if out_dir is None:
        if netcdf:
            raise _atmosh.InputError("netcdf: give out_dir (the netCDF file is written there)")
        with tempfile.TemporaryDirectory(prefix="atmosh_sweep_") as d:
            t = _st.sweep_file(str(path), d, shells, segments, samples, threads, False)
    else:
        t = _st.sweep_file(str(path), str(out_dir), shells, segments, samples, threads, bool(netcdf))
    df = _frame(t)
    df.attrs["keys"] = list(t["keys"])
    return df


def zenith_sweep(scene=None, preset=None, altitude_m=1000.0):
    """Optical depth at 550 nm against zenith angle 0..180 deg (0.5 deg steps) from
    altitude_m [m] above the ground: the exact reference and the default tables
    (columns zenith_deg, tau_reference, tau_lut, relative_error, hits_ground, as the scene
    output kind optical-depth writes them). scene (TOML file) or preset (default
    earth-graphics). df.attrs["lut"] names the tables."""
    t, lut = _st.zenith_sweep(_scene(scene), preset, float(altitude_m))
    df = _frame(t)
    df.attrs["lut"] = lut
    return df


def sh_windows(coefficients, bands):
    """What each SH window (none, hanning, lanczos, nonnegative) costs on one channel of
    `bands` bands (coefficients: at least bands^2, index l(l+1)+m): delta_min_rel (the
    ringing left: minimum of the windowed delta over its maximum), l2_change_rel and
    irradiance_max_change_rel (largest change of the irradiance over a 64 x 32 grid of
    directions, relative to its largest magnitude). Columns as the main job's
    sh_windows.csv."""
    c = np.asarray(coefficients, dtype=np.float64).ravel()
    return _frame(_st.sh_windows(list(c), int(bands)))


def prt_converge(mesh="sphere-on-plane", resolution=16, bands=3, mode="shadowed", reference_samples=16384,
                 strata=(4, 8, 16, 32, 45), threads=0, pixels=(96, 96), view=(1.0, -1.6, 1.1), device="cpu",
                 depth_maps=(256, 1024)):
    """Transfer error against a high-sample reference versus run time, as `atmosh prt
    converge` (columns method, setting, error_max_rel, error_rms_rel, time_s, samples,
    rays, depth_map). mesh: a built-in scene name (atmosh.prt.builtin_scene_names(),
    tessellated with `resolution`) or an .obj/.ply file path. reference_samples: a square
    count (n x n jittered strata, seed 12345); strata: n of each row (n x n samples, seed
    1). Per-pixel rows (shadowed only): a pixels = (W, H) camera image seen from `view`;
    device "cpu" (ray casting only), "gpu" or "auto" (also the GPU depth-map rows)."""
    import math
    n = int(reference_samples)
    s = int(round(math.sqrt(max(n, 0))))
    if n < 1 or s * s != n or s > 2000:
        raise _atmosh.InputError(f"reference_samples: {n} is not a square count of jittered strata n x n in "
                                 "1..4000000 (e.g. 2025 = 45 x 45)")
    from . import prt as _prt_mod
    name = str(mesh)
    builtin = name if name in _prt_mod.builtin_scene_names() else ""
    w, h = (int(v) for v in pixels)
    return _frame(_st.prt_converge(builtin, "" if builtin else name, int(resolution), int(bands), str(mode), s,
                                   [int(v) for v in strata], int(threads), w, h, [float(v) for v in view],
                                   str(device), [int(v) for v in depth_maps]))


def gi_converge(scene="cornell-box", out_dir=None, light="", size=(64, 64), bands=(1, 2, 3, 4), grids=(2, 3, 4, 6, 8),
                path_samples=(4, 16), radiosity_grids=(4, 8, 16), radiosity_bands=(1, 2), radiosity_bounces=(0, 1, 2, 3),
                lpv_grids=(8, 16, 32), reference_samples=256, samples=4, cube_size=8, pixel_samples=4, seed=1,
                threads=0):
    """Error against run time of the scene-lighting methods against a path-traced reference
    at matched lighting, as `atmosh gi converge` (columns method, setting, error_max_rel,
    error_rms_rel, time_s, leak_rel, build_s, shade_s, mean_rel; errors relative to the
    reference's mean radiance). scene: a built-in scene (cornell-box, sphere-on-plane,
    box-occluder) or an .obj/.ply file; light: "sun:AZ,EL" (degrees) or "" (the scene's own
    lights). Probes: every grid x band count, plain and visibility-weighted; the path tracer
    at each of path_samples; radiosity: grids x bands x bounces; LPV: each grid (empty
    tuples: no rows of that kind). The reference and each row's image are written to
    out_dir (default: a new temporary folder, in df.attrs["images_dir"])."""
    import tempfile
    d = str(out_dir) if out_dir is not None else tempfile.mkdtemp(prefix="atmosh_gi_")
    name = str(scene)
    builtin = name if name in ("cornell-box", "sphere-on-plane", "box-occluder") else ""
    w, h = (int(v) for v in size)
    ints = lambda v: [int(x) for x in v]  # noqa: E731
    df = _frame(_st.gi_converge(builtin, "" if builtin else name, str(light), w, h, ints(bands), ints(grids),
                                ints(path_samples), ints(radiosity_grids), ints(radiosity_bands),
                                ints(radiosity_bounces), ints(lpv_grids), int(reference_samples), int(samples),
                                int(cube_size), int(pixel_samples), int(seed), int(threads), d))
    df.attrs["images_dir"] = d
    return df


def rt_slab(tau, omega, phase, mu0, mu, g=0.0, ground_albedo=0.0, phi_deg=0.0, orders=0, paths=100000, seed=1,
            threads=0):
    """Monte-Carlo reflection R = pi I_up / (mu0 F0) and diffuse transmission
    T = pi I_down / (mu0 F0) of a homogeneous plane-parallel slab over a Lambertian ground,
    with standard errors: a one-row DataFrame with the fields of `atmosh rt slab --json`
    (tau, omega, phase, g, ground_albedo, mu0, mu, phi_deg, reflection, reflection_stderr,
    transmission, transmission_stderr, paths, seed, orders, threads, time_s).
    phase: isotropic | hg | rayleigh; phi_deg: azimuth of the viewed light's propagation
    relative to the beam's; orders 0 = all. Bit-identical for a seed on any thread count."""
    return _frame(_st.rt_slab(float(tau), float(omega), str(phase), float(g), float(ground_albedo), float(mu0),
                              float(mu), float(phi_deg), int(orders), int(paths), int(seed), int(threads)))


def rt_sky(sun_elevation_deg, view_elevation_deg, view_azimuth_deg, sun_azimuth_deg=180.0, scene=None, height_m=0.0,
           ground_albedo=None, orders=0, sun_depth="table", line_estimate="auto", paths=64000, seed=1, threads=0,
           guide="auto"):
    """Monte-Carlo spectral radiance of a scene's sky for one view, every scattering
    order, as `atmosh rt sky --json`: a DataFrame with one row per wavelength
    (wavelength_nm, radiance_w_m2_sr_nm, radiance_stderr_w_m2_sr_nm) and the JSON's scalar
    fields (luminance_cd_m2 and its stderr, xyz, paths, mean_orders, ...) in df.attrs.
    Angles in degrees (azimuths from north towards east), height_m above the ground,
    ground_albedo None: the scene's; paths in total over the wavelengths; line_estimate and
    guide: "auto" | "on" | "off", as --line-estimate and --guide."""
    t = _st.rt_sky(_scene(scene), float(sun_elevation_deg), float(sun_azimuth_deg), float(view_elevation_deg),
                   float(view_azimuth_deg), float(height_m), -1.0 if ground_albedo is None else float(ground_albedo),
                   int(orders), str(sun_depth), str(line_estimate), int(paths), int(seed), int(threads), str(guide))
    df = _frame(t)
    df.attrs.update(dict(t["scalars"]))
    return df
