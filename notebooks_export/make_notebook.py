#!/usr/bin/env python3
"""Writes figures.ipynb: the notebook that turns the main job's results into paper figures.

Run by hand after editing the cells below (the .ipynb is committed; every cell has a fixed
id, so a regenerated notebook differs only where a cell changed):

    /usr/bin/python3 notebooks_export/make_notebook.py

The notebook reads the netCDF-CF, CSV and OpenEXR outputs of the main job (`atmosh demo`
and notebooks_export/netcdf_outputs.sh, docs/outputs.md) from the folder named by the
environment variable ATMOSH_RESULTS
(default: results/ at the top of the source tree) and saves every figure as PDF and PNG
under $ATMOSH_RESULTS/figures/. netCDF files are read with xarray (Debian python3-xarray,
python3-netcdf4) and preferred where the main job writes one (the sky image, the sun
track, the sun-elevation and day studies); the CSV or EXR of `atmosh demo` is read where
it does not. EXR images are read with OpenImageIO (Debian python3-openimageio): all
channels and all header attributes. The figures it writes are
listed in figures.txt; run_figures.sh executes the notebook headless and checks that list.
"""
import json
import pathlib
import re

# Files of the main job that the notebook reads (the test Cli.DemoQuickEndToEnd checks
# that the main job writes each of them).
FILES = [
    "sky.exr",
    "sun_track.csv",
    "sun_elevation_study/sun_elevation.csv",
    "sun_accuracy.csv",
    "lut_convergence.csv",
    "sky_convergence.csv",
    "ms_convergence.csv",
    "ms_convergence_points.csv",
    "sh_converge.csv",
    "prt/converge.csv",
    "sky_sh_bands.csv",
    "sh_bands.csv",
    "sh_windows.csv",
    "sky_sh.csv",
    "sh_coeffs.csv",
    "sh_irradiance.csv",
    "sh_sky_input.exr",
    "sh_reconstruct.exr",
    "optical_depth_vs_zenith.csv",
    "stability.csv",
    "prt/relight/ao.exr",
    "prt/relight/frame_0000.exr",
]

# netCDF-CF files of the main job (notebooks_export/netcdf_outputs.sh, run after `atmosh
# demo` by scripts/main-job.sh and the test figures_notebooks), read in preference to the
# CSV/EXR of the same quantity.
NC_FILES = [
    "netcdf/sky.nc",
    "netcdf/sun_track.nc",
    "netcdf/sun_elevation_study/sun_elevation.nc",
    "netcdf/day_study/day.nc",
]

cells = []


def _id(text):
    return re.sub(r"[^a-z0-9-]+", "-", text.lower()).strip("-")[:60]


def md(cell_id, text):
    cells.append({"cell_type": "markdown", "id": _id("md-" + cell_id), "metadata": {},
                  "source": text.strip("\n").splitlines(True)})


def code(cell_id, text):
    cells.append({"cell_type": "code", "id": _id(cell_id), "metadata": {}, "execution_count": None,
                  "outputs": [], "source": text.strip("\n").splitlines(True)})


md("title", """
# atmosh: figures from the main job

Run `bash scripts/main-job.sh` (or `build/bin/atmosh demo -o results`) first. This notebook
reads the results folder named by `ATMOSH_RESULTS` (default `results/`) and writes every
figure as PDF and PNG to `$ATMOSH_RESULTS/figures/` (the list: `notebooks_export/figures.txt`).
Every CSV starts with `# key: value` provenance lines; `read()` returns them with the table.
Column names carry their units (`time_s`, `zenith_luminance_cd_m2`, `error_max_deg`);
axis labels are made from them. A figure whose input file is absent is skipped with a note.
""")
code("setup", f"""
import os, pathlib, re
import numpy as np
import pandas as pd
import matplotlib
import matplotlib.pyplot as plt

RESULTS = pathlib.Path(os.environ.get("ATMOSH_RESULTS") or (pathlib.Path.cwd().parent / "results")).resolve()
FIGURES = RESULTS / "figures"
FIGURES.mkdir(parents=True, exist_ok=True)
# Files this notebook reads (kept in step with `atmosh demo` by the test suite):
FILES = {json.dumps(FILES)}
NC_FILES = {json.dumps(NC_FILES)}
SAVED = []
plt.rcParams.update({{"figure.dpi": 110, "savefig.dpi": 150, "font.size": 9, "axes.grid": True,
                      "grid.alpha": 0.3, "pdf.fonttype": 42}})
INTERACTIVE = "inline" in matplotlib.get_backend() or "ipympl" in matplotlib.get_backend()

def have(*names):
    missing = [n for n in names if not (RESULTS / n).is_file()]
    if missing:
        print("skipped: input absent:", ", ".join(missing))
    return not missing

def pick(*names):
    \"\"\"The first of the files that exists (netCDF first, then the CSV/EXR), or None.\"\"\"
    for n in names:
        if (RESULTS / n).is_file():
            print("reading", n)
            return n
    print("skipped: input absent:", ", ".join(names))
    return None

def read_nc(name):
    \"\"\"A netCDF-CF file as an xarray.Dataset (CF-decoded: `time` as datetime64) and its
    provenance (the global attributes atmosh_<key>, plus history) as a dict.\"\"\"
    import xarray as xr
    ds = xr.open_dataset(RESULTS / name).load()
    meta = {{k[len("atmosh_"):]: v for k, v in ds.attrs.items() if k.startswith("atmosh_")}}
    meta["history"] = ds.attrs.get("history", "")
    return ds, meta

def read(name):
    \"\"\"A table as a DataFrame and its provenance as a dict: a netCDF-CF table (one
    variable per column, the coordinates as columns too) or a CSV with its '# key: value'
    lines.\"\"\"
    if name.endswith(".nc"):
        ds, meta = read_nc(name)
        return ds.to_dataframe().reset_index(), meta
    path = RESULTS / name
    meta = {{}}
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            key, _, value = line[1:].partition(":")
            meta[key.strip()] = value.strip()
    return pd.read_csv(path, comment="#"), meta

def read_exr(name):
    \"\"\"All channels of an OpenEXR image as {{name: (H, W) float32}} and all header attributes.\"\"\"
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(RESULTS / name))
    if inp is None:
        raise OSError(f"cannot open {{name}}: {{oiio.geterror()}}")
    spec = inp.spec()
    pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
    inp.close()
    pixels = np.asarray(pixels).reshape(spec.height, spec.width, spec.nchannels)
    channels = {{c: pixels[:, :, i] for i, c in enumerate(spec.channelnames)}}
    attrs = {{a.name: a.value for a in spec.extra_attribs}}
    return channels, attrs

UNITS = [("_cd_m2", "cd/m$^2$"), ("_deg", "deg"), ("_s", "s"), ("_ns", "ns"), ("_lux", "lx"),
         ("_nm", "nm"), ("_m", "m"), ("_km", "km"), ("_au", "au"), ("_rel", "relative"),
         ("_bytes", "bytes"), ("_min", "min")]

NAMES = {{"zenith_deg": "zenith angle [deg]", "sun_elevation_deg": "sun elevation [deg]"}}

def label(col):
    \"\"\"An axis label from a column name whose suffix is its unit: 'time_s' -> 'time [s]'.\"\"\"
    if col in NAMES:
        return NAMES[col]
    for suffix, unit in sorted(UNITS, key=lambda u: -len(u[0])):
        if col.endswith(suffix):
            return col[: -len(suffix)].replace("_", " ") + f" [{{unit}}]"
    return col.replace("_", " ")

def cite(name, meta=None):
    \"\"\"A title suffix naming the input file (and the commit that wrote it).\"\"\"
    commit = (meta or {{}}).get("git_commit")
    return f"{{name}}" + (f" (atmosh {{commit}})" if commit else "")

def save(fig, stem):
    \"\"\"Writes figures/<stem>.pdf and figures/<stem>.png.\"\"\"
    fig.savefig(FIGURES / f"{{stem}}.pdf", bbox_inches="tight")
    fig.savefig(FIGURES / f"{{stem}}.png", bbox_inches="tight")
    SAVED.append(stem)
    if not INTERACTIVE:
        plt.close(fig)

def tonemap(rgb, exposure=None):
    \"\"\"Linear RGB -> sRGB-encoded display values: scale so the 99th percentile of the
    luminance is 1 (or by `exposure`), clip, sRGB transfer curve.\"\"\"
    rgb = np.nan_to_num(np.asarray(rgb, dtype=np.float64), nan=0.0, posinf=0.0)
    if exposure is None:
        lum = 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]
        p = np.percentile(lum[lum > 0], 99) if np.any(lum > 0) else 1.0
        exposure = 1.0 / p
    v = np.clip(rgb * exposure, 0, 1)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)

print("results:", RESULTS)
missing = [f for f in FILES + NC_FILES if not (RESULTS / f).exists()]
print("missing inputs:", missing or "none")
""")

# --------------------------------------------------------------------------------------
md("sky", """
## The sky image (`netcdf/sky.nc`, else `sky.exr`)

Equirect: azimuth 0..360° from north towards east, left to right; elevation +90° at the top.
Left: the linear sRGB channels tone-mapped for display; right: log10 of the luminance Y.
""")
code("fig-sky", """
NAME = pick("netcdf/sky.nc", "sky.exr")
if NAME and NAME.endswith(".nc"):
    ds, meta = read_nc(NAME)
    print(ds)
    Y = ds["Y"].values
    # XYZ -> linear sRGB (IEC 61966-2-1, D65), the scale of Y (cd/m^2)
    M = np.array([[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]])
    rgb = np.einsum("ij,jhw->hwi", M, np.stack([ds["X"].values, Y, ds["Z"].values]))
    el, az = ds["elevation"].values, ds["azimuth"].values  # pixel centres [degree]
    de, da = abs(el[0] - el[1]) / 2 if el.size > 1 else 90.0, (az[1] - az[0]) / 2 if az.size > 1 else 180.0
    ext = [az[0] - da, az[-1] + da, el[-1] - de, el[0] + de]
    sun_el = 90.0 - float(ds["solar_zenith_angle"]) if "solar_zenith_angle" in ds else np.nan
    sun_az = float(ds["solar_azimuth_angle"]) if "solar_azimuth_angle" in ds else np.nan
    unit, scattering, commit = "cd/m$^2$", meta.get("scattering", ""), meta.get("git_commit")
elif NAME:
    ch, attrs = read_exr(NAME)
    print("channels:", list(ch)); print("attributes:"); [print(f"  {k}: {v}") for k, v in attrs.items()]
    Y = ch["Y"]; rgb = np.dstack([ch["R"], ch["G"], ch["B"]])
    # 'projection' says: azimuth 0..360 deg from north towards east left to right,
    # elevation +90..-90 deg top to bottom
    m = re.search(r"elevation ([+-]?[0-9.]+)[.][.]([+-]?[0-9.]+)", str(attrs.get("projection", "")))
    el_top, el_bottom = (float(m.group(1)), float(m.group(2))) if m else (90.0, -90.0)
    ext = [0, 360, el_bottom, el_top]
    sun_el = float(attrs.get("sun_elevation_deg", np.nan)); sun_az = float(attrs.get("sun_azimuth_deg", np.nan))
    unit = attrs.get("value_units", "cd/m^2").replace("^2", "$^2$")
    scattering, commit = attrs.get("atmosh:scattering", ""), attrs.get("atmosh:git_commit")
if NAME:
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 3.4))
    a.imshow(tonemap(rgb), extent=ext, aspect="auto", interpolation="nearest")
    a.set_title("sky, linear sRGB tone-mapped (99th percentile of Y = 1)")
    floor = max(np.nanmax(Y) * 1e-8, np.nanmin(Y[Y > 0]) if np.any(Y > 0) else 1e-12)
    im = b.imshow(np.log10(np.maximum(Y, floor)), extent=ext, aspect="auto", cmap="magma", interpolation="nearest")
    fig.colorbar(im, ax=b, label=f"log$_{{10}}$ luminance Y [{unit}]")
    b.set_title("luminance")
    for ax in (a, b):
        ax.set_xlabel("azimuth from north towards east [deg]"); ax.set_ylabel("elevation [deg]")
        ax.set_xticks(np.arange(0, 361, 45)); ax.grid(False)
        if np.isfinite(sun_el):
            ax.plot([sun_az], [sun_el], marker="o", mfc="none", mec="cyan", ms=9)
    fig.suptitle(f"Sky, sun at elevation {sun_el:.2f}°, azimuth {sun_az:.2f}° ({scattering}) — {cite(NAME, {'git_commit': commit})}", fontsize=9)
    fig.tight_layout(); save(fig, "sky")
""")

# --------------------------------------------------------------------------------------
md("day", "## The sun over the scene's UTC day (`netcdf/sun_track.nc`, else `sun_track.csv`; NREL SPA)")
code("fig-sun-track", """
NAME = pick("netcdf/sun_track.nc", "sun_track.csv")
if NAME:
    df, meta = read(NAME)
    t = pd.to_datetime(df["time_utc"])
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.4))
    a.plot(t, df["elevation_deg"], label="geometric")
    a.plot(t, df["apparent_elevation_deg"], "--", label="apparent (refracted)")
    a.axhline(0, color="k", lw=0.6)
    a.set_xlabel("time [UTC]"); a.set_ylabel(label("elevation_deg")); a.legend()
    az = df["azimuth_deg"].to_numpy(dtype=float).copy()
    az[1:][np.abs(np.diff(az)) > 180] = np.nan  # no line across the 360 -> 0 wrap
    b.plot(t, df["azimuth_deg"], ".", ms=3, color="tab:blue"); b.plot(t, az, "-", color="tab:blue")
    b.set_xlabel("time [UTC]"); b.set_ylabel("azimuth from north towards east [deg]"); b.set_ylim(0, 360)
    b.set_yticks(np.arange(0, 361, 90))
    for ax in (a, b):
        ax.xaxis.set_major_formatter(matplotlib.dates.DateFormatter("%H:%M"))
    fig.suptitle(f"Sun at lat {meta.get('latitude_deg')}°, lon {meta.get('longitude_deg')}°, {meta.get('from_utc', '')[:10]} — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "sun_track")
""")

# --------------------------------------------------------------------------------------
md("sun-elevation", """
## Sky colour against sun elevation (`netcdf/sun_elevation_study/sun_elevation.nc`, else the CSV)

Colour strips: the linear sRGB of each view divided by its largest channel (so the strip
shows chromaticity, not brightness) and sRGB-encoded; luminance on a log scale (it spans
many decades from night to noon); CIE 1931 chromaticity x and y.
""")
code("fig-sun-elevation", """
NAME = pick("netcdf/sun_elevation_study/sun_elevation.nc", "sun_elevation_study/sun_elevation.csv")
if NAME:
    df, meta = read(NAME)
    df = df.sort_values("sun_elevation_deg")
    el = df["sun_elevation_deg"].to_numpy()
    views = [("zenith", "zenith"), ("horizon_sun", "horizon toward the sun")]

    # colour strips
    fig, axes = plt.subplots(len(views), 1, figsize=(9, 2.2), sharex=True)
    for ax, (key, what) in zip(axes, views):
        rgb = df[[f"{key}_r", f"{key}_g", f"{key}_b"]].to_numpy(dtype=float)
        rgb = np.nan_to_num(np.maximum(rgb, 0))
        peak = rgb.max(axis=1, keepdims=True)
        sw = tonemap(np.where(peak > 0, rgb / np.where(peak > 0, peak, 1), 0), exposure=1.0)
        edges = np.concatenate([[el[0] - (el[1] - el[0]) / 2], (el[1:] + el[:-1]) / 2, [el[-1] + (el[-1] - el[-2]) / 2]])
        for i in range(len(el)):
            ax.axvspan(edges[i], edges[i + 1], color=sw[i], lw=0)
        ax.set_xlim(edges[0], edges[-1]); ax.set_yticks([]); ax.set_ylabel(what, rotation=0, ha="right", va="center")
        ax.grid(False)
    axes[-1].set_xlabel(label("sun_elevation_deg"))
    fig.suptitle(f"Sky colour (chromaticity, brightness normalised) — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "sun_elevation_colour")

    # luminance
    fig, ax = plt.subplots(figsize=(6, 4))
    for col, what in [("zenith_luminance_cd_m2", "zenith"), ("horizon_sun_luminance_cd_m2", "horizon toward the sun"),
                      ("horizon_away_luminance_cd_m2", "horizon away from the sun")]:
        ok = df[col] > 0
        ax.semilogy(df["sun_elevation_deg"][ok], df[col][ok], "o-", ms=3, label=what)
    ax.axvline(0, color="k", lw=0.6)
    ax.set_xlabel(label("sun_elevation_deg")); ax.set_ylabel("luminance [cd/m$^2$]")
    if "sun_direct_normal_illuminance_lux" in df:
        ax2 = ax.twinx(); ok = df["sun_direct_normal_illuminance_lux"] > 0
        ax2.semilogy(df["sun_elevation_deg"][ok], df["sun_direct_normal_illuminance_lux"][ok], "k:", label="sun, direct normal illuminance")
        ax2.set_ylabel("direct normal illuminance of the sun [lx]"); ax2.grid(False)
        ax2.legend(loc="lower right", fontsize=7)
    ax.legend(loc="upper left", fontsize=7)
    ax.set_title(f"Luminance against sun elevation — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "sun_elevation_luminance")

    # chromaticity
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.8))
    for key, what in views + [("horizon_away", "horizon away from the sun"), ("sun", "sun (direct)")]:
        if f"{key}_x" not in df:
            continue
        ok = np.isfinite(df[f"{key}_x"]) & np.isfinite(df[f"{key}_y"])
        a.plot(df["sun_elevation_deg"][ok], df[f"{key}_x"][ok], "o-", ms=3, label=what)
        b.plot(df[f"{key}_x"][ok], df[f"{key}_y"][ok], "o-", ms=3, label=what)
    b.plot([0.3127], [0.3290], "k+", ms=10, label="D65 white")
    a.set_xlabel(label("sun_elevation_deg")); a.set_ylabel("CIE 1931 x")
    b.set_xlabel("CIE 1931 x"); b.set_ylabel("CIE 1931 y"); b.set_aspect("equal", adjustable="datalim")
    a.legend(fontsize=7); b.legend(fontsize=7)
    fig.suptitle(f"Chromaticity against sun elevation — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "sun_elevation_chromaticity")
""")

# --------------------------------------------------------------------------------------
md("day-study", """
## The sky through the day (`netcdf/day_study/day.nc`)

The day study at the scene's observer: luminance of the zenith and the horizon against
UTC time (the file's CF time coordinate), and the zenith's colour strip (chromaticity,
brightness normalised: a night sky keeps its colour here; its luminance is in the plot).
""")
code("fig-day-study", """
NAME = pick("netcdf/day_study/day.nc")
if NAME:
    ds, meta = read_nc(NAME)
    t = ds["time"].values
    fig, (a, b) = plt.subplots(2, 1, figsize=(8, 4.8), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    for col, what in [("zenith_luminance_cd_m2", "zenith"), ("horizon_sun_luminance_cd_m2", "horizon toward the sun"),
                      ("horizon_away_luminance_cd_m2", "horizon away from the sun")]:
        v = ds[col].values
        a.semilogy(t[v > 0], v[v > 0], "o-", ms=3, label=what)
    a2 = a.twinx(); a2.plot(t, ds["sun_elevation_deg"].values, "k:", label="sun elevation")
    a2.set_ylabel(label("sun_elevation_deg")); a2.grid(False); a2.legend(loc="lower right", fontsize=7)
    a.set_ylabel("luminance [cd/m$^2$]"); a.legend(loc="upper left", fontsize=7)
    rgb = np.nan_to_num(np.maximum(np.stack([ds[f"zenith_{c}"].values for c in "rgb"], axis=1), 0))
    peak = rgb.max(axis=1, keepdims=True)
    sw = tonemap(np.where(peak > 0, rgb / np.where(peak > 0, peak, 1), 0), exposure=1.0)
    step = (t[1] - t[0]) if t.size > 1 else np.timedelta64(3600, "s")
    for i in range(t.size):
        b.axvspan(t[i] - step / 2, t[i] + step / 2, color=sw[i], lw=0)
    b.set_yticks([]); b.set_ylabel("zenith", rotation=0, ha="right", va="center"); b.grid(False)
    b.set_xlabel("time [UTC]"); b.xaxis.set_major_formatter(matplotlib.dates.DateFormatter("%H:%M"))
    fig.suptitle(f"Sky through {meta.get('date_utc', '')} at lat {float(ds['latitude']):.4f}°, "
                 f"lon {float(ds['longitude']):.4f}° — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "day_study")
""")

# --------------------------------------------------------------------------------------
md("error-time", """
## Error against run time

One line per method (and band, where the study has one), its points sorted by run time
(so lines never zig-zag back). Both axes are logarithmic. Rows with zero error (the exact
reference of a study) cannot be drawn on a log axis; they are listed under the figure.
""")
code("error-time-helper", """
def error_vs_time(name, stem, err="error_max_rel", time="time_s", group=("method",), title="", style="o-", strip=None):
    if not have(name):
        return
    df, meta = read(name)
    if strip:  # a refinement level written into the method name (sky_convergence.csv: 'day q=2')
        df["method"] = df["method"].str.replace(strip, "", regex=True)
    keys = [g for g in group if g in df]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    zero = df[~(df[err] > 0)]
    # a second grouping column (the band of ms_convergence.csv) changes marker and line style,
    # so groups with equal rows stay visible
    sub = list(dict.fromkeys(df[keys[1]])) if len(keys) > 1 else [None]
    looks = [("o", "-", None), ("s", "--", "none"), ("^", ":", "none"), ("v", "-.", "none")]
    for key, g in df[df[err] > 0].groupby(keys, sort=False):
        g = g.sort_values(time)
        mk, ls, mfc = looks[sub.index(key[1]) % len(looks)] if len(keys) > 1 else looks[0]
        if style == "o":
            ls = "none"
        ax.loglog(g[time], g[err], marker=mk, ls=ls, mfc=mfc, ms=5, lw=1, label=" / ".join(map(str, key if isinstance(key, tuple) else (key,))))
        if style != "o" and "setting" in g and (len(keys) < 2 or sub.index(key[1]) == 0):  # each point's setting
            for x, y, t in zip(g[time], g[err], g["setting"]):
                ax.annotate(str(t)[:48], (x, y), xytext=(3, 3), textcoords="offset points", fontsize=5, alpha=0.8)
    ax.set_xlabel(label(time) + f"  (host with {meta.get('host_cores', '?')} cores)")
    ax.set_ylabel(label(err) if not err.endswith("_rel") else err.replace("_rel", "").replace("_", " ") + " [relative]")
    ax.legend(fontsize=7); ax.grid(True, which="both", alpha=0.25)
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if hi / lo < 30:  # less than 1.5 decades: label 1, 2, 5 x 10^k
            axis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%.2g"))
        axis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # no overlapping minor labels
    ax.set_title(f"{title} — {cite(name, meta)}", fontsize=9)
    notes = []
    if meta.get(time):  # what the run time covers, as the file says
        notes.append(f"{time}: {meta[time]}")
    if len(zero):
        notes.append("zero error (reference): " + ", ".join(f"{m} {s}" for m, s in zip(zero.get("method", zero.index), zero.get("setting", [""] * len(zero))))[:160])
    if notes:
        fig.text(0.01, -0.02, "\\n".join(notes), fontsize=6, va="top")
    fig.tight_layout(); save(fig, stem)
""")
for name, stem, err, group, title in [
    ("sun_accuracy.csv", "sun_accuracy", "error_max_deg", ("method",), "Sun position: fast algorithms against SPA (one point per latitude)"),
    ("lut_convergence.csv", "lut_convergence", "error_max_rel", ("method",), "Optical-depth tables against exact quadrature"),
    ("sky_convergence.csv", "sky_convergence", "error_max_rel", ("method",), "Single-scattering sky integrator against the exact reference (day and twilight rays)"),
    ("ms_convergence.csv", "ms_convergence", "error_max_rel", ("method", "band"), "Scattering methods against the Monte-Carlo reference"),
    ("sh_converge.csv", "sh_converge", "error_max_rel", ("method",), "SH projection methods against the exact quadrature"),
    ("prt/converge.csv", "prt_converge", "error_max_rel", ("method",), "PRT transfer against the high-sample reference"),
]:
    # The sun-accuracy rows are latitudes, not refinements: points only (a scatter).
    style = "o" if stem == "sun_accuracy" else "o-"
    strip = r"\s+q=\S+$" if stem == "sky_convergence" else None
    code("fig-" + stem, f"""
error_vs_time({name!r}, {stem!r}, err={err!r}, group={group!r}, title={title!r}, style={style!r}, strip={strip!r})
""")
code("fig-ms-points", """
NAME = "ms_convergence_points.csv"
if have(NAME):
    df, meta = read(NAME)
    ref, se = df["reference_luminance_cd_m2"], df["reference_luminance_stderr_cd_m2"]
    methods = [c for c in df.columns if c not in ("sun_elevation_deg", "view_elevation_deg", "view_relative_azimuth_deg",
                                                  "reference_luminance_cd_m2", "reference_luminance_stderr_cd_m2")]
    order = np.argsort(ref.to_numpy())
    x = np.arange(len(df))
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.fill_between(x, -3 * (se / ref).to_numpy()[order], 3 * (se / ref).to_numpy()[order], color="0.85",
                    label="reference ±3 standard errors")
    for m in methods:
        ax.plot(x, ((df[m] - ref) / ref).to_numpy()[order], "o-", ms=4, label=m)
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xticks(x, [f"sun {s:g}°\\nview {v:g}°/{a:g}°" for s, v, a in df[["sun_elevation_deg", "view_elevation_deg",
                                                                            "view_relative_azimuth_deg"]].to_numpy()[order]], fontsize=6)
    ax.set_xlabel("point (sorted by reference luminance)"); ax.set_ylabel("(method − reference) / reference [relative]")
    ax.legend(fontsize=6)
    ax.set_title(f"Scattering methods at each point — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "ms_convergence_points")
""")

# --------------------------------------------------------------------------------------
md("sh", """
## Spherical harmonics: band energies, windows, reconstruction

Band energy E_l = Σ_m c_lm² per colour channel (log scale: it falls by decades), with the
cumulative fraction of the total; the SH demonstration's input and its reconstruction.
""")
code("fig-sh-bands", """
for name, stem, what in [("sky_sh_bands.csv", "sky_sh_bands", "the default scene's sky"),
                         ("sh_bands.csv", "sh_bands", "the synthetic SH test sky")]:
    if not have(name):
        continue
    df, meta = read(name)
    unit = meta.get("value_units", "").replace("^2", "$^2$")
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.6))
    for c, colour in zip("rgb", ("tab:red", "tab:green", "tab:blue")):
        ok = df[f"energy_{c}"] > 0
        a.semilogy(df["l"][ok], df[f"energy_{c}"][ok], "o-", color=colour, ms=4, label=c.upper())
    a.set_xlabel("band l"); a.set_ylabel(f"band energy Σ$_m$ c$_{{lm}}^2$ [({unit} sr)$^2$]" if unit else "band energy Σ$_m$ c$_{lm}^2$")
    a.legend()
    cum = [c for c in df.columns if c.startswith("cumulative_fraction") or c.startswith("fraction_")]
    for c in cum:
        b.plot(df["l"], df[c], "o-", ms=4, label=c.replace("_", " "))
    if not cum:
        tot = df["energy_g"].sum(); b.plot(df["l"], df["energy_g"].cumsum() / tot, "o-", label="cumulative fraction g")
    b.set_xlabel("band l"); b.set_ylabel("cumulative fraction of the energy"); b.set_ylim(0, 1.02); b.legend(fontsize=7)
    fig.suptitle(f"SH band energy of {what} — {cite(name, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, stem)
""")
code("fig-sh-coefficients", """
# Left: log10 |c_lm| of the sky's SH coefficients (sky_sh.csv, green channel) on the (l, m)
# triangle. Right: irradiance coefficients over radiance coefficients (sh_irradiance.csv /
# sh_coeffs.csv, per coefficient) against the closed form of the clamped-cosine kernel
# A_l (Ramamoorthi & Hanrahan 2001, "An efficient representation for irradiance environment
# maps", eq. 8-9): A_0 = pi, A_1 = 2 pi / 3, A_l = 0 for odd l > 1, and for even l
# A_l = 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2).
from math import factorial, pi
def clamped_cosine(l):
    if l == 0: return pi
    if l == 1: return 2 * pi / 3
    if l % 2: return 0.0
    return 2 * pi * (-1) ** (l // 2 - 1) / ((l + 2) * (l - 1)) * factorial(l) / (2 ** l * factorial(l // 2) ** 2)
if have("sky_sh.csv", "sh_coeffs.csv", "sh_irradiance.csv"):
    sky, meta = read("sky_sh.csv")
    L = int(sky["l"].max()) + 1
    grid = np.full((L, 2 * L - 1), np.nan)
    for l, m, g in sky[["l", "m", "g"]].to_numpy():
        grid[int(l), int(m) + L - 1] = np.log10(max(abs(g), 1e-300))
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 3.8))
    im = a.imshow(grid, origin="upper", cmap="viridis", extent=[-L + 0.5, L - 0.5, L - 0.5, -0.5], aspect="auto")
    fig.colorbar(im, ax=a, label="log$_{10}$ |c$_{lm}$| (green) [cd/m$^2$ sr]")
    a.set_xlabel("order m"); a.set_ylabel("band l"); a.grid(False)
    a.set_title("sky_sh.csv", fontsize=9)
    rad, _ = read("sh_coeffs.csv"); irr, meta_i = read("sh_irradiance.csv")
    both = rad.merge(irr, on=["l", "m"], suffixes=("_rad", "_irr"))
    ok = both["g_rad"].abs() > 1e-9 * both["g_rad"].abs().max()
    b.plot(both["l"][ok], (both["g_irr"] / both["g_rad"])[ok], "o", ms=5, mfc="none", label="sh_irradiance.csv / sh_coeffs.csv (each c$_{lm}$, green)")
    ls = np.arange(int(both["l"].max()) + 1)
    b.plot(ls, [clamped_cosine(int(l)) for l in ls], "k+", ms=12, mew=1.5, label="A$_l$, closed form (Ramamoorthi & Hanrahan 2001)")
    b.axhline(0, color="k", lw=0.5)
    b.set_xlabel("band l"); b.set_ylabel("irradiance / radiance coefficient [sr]"); b.legend(fontsize=7)
    b.set_title("sh_coeffs.csv, sh_irradiance.csv", fontsize=9)
    fig.suptitle(f"SH coefficients of the sky and the irradiance kernel — {cite('sky_sh.csv', meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "sh_coefficients")
""")
code("fig-sh-windows", """
NAME = "sh_windows.csv"
if have(NAME):
    df, meta = read(NAME)
    cols = [c for c in df.columns if c != "window"]
    fig, ax = plt.subplots(figsize=(7, 3.6))
    x = np.arange(len(df)); w = 0.8 / len(cols)
    for i, c in enumerate(cols):
        ax.bar(x + (i - (len(cols) - 1) / 2) * w, np.maximum(df[c].abs(), 1e-12), w, label=f"|{c}|")
    ax.set_xticks(x, df["window"]); ax.set_yscale("log"); ax.set_ylim(3e-13, 3 * df[cols].abs().to_numpy().max())
    ax.set_xlabel("window"); ax.set_ylabel("|value| [relative] (zero drawn at 1e-12)"); ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1))
    ax.set_title(f"Ringing windows: overshoot left and what each costs — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "sh_windows")
""")
code("fig-sh-reconstruction", """
if have("sh_sky_input.exr", "sh_reconstruct.exr"):
    a_ch, a_attr = read_exr("sh_sky_input.exr"); b_ch, b_attr = read_exr("sh_reconstruct.exr")
    print("input attributes:", a_attr); print("reconstruction attributes:", b_attr)
    lum = lambda ch: 0.2126 * ch["R"] + 0.7152 * ch["G"] + 0.0722 * ch["B"]
    la, lb = lum(a_ch), lum(b_ch)
    exposure = 1.0 / np.percentile(la[la > 0], 99)
    ext = [0, 360, -90, 90]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.3))
    axes[0].imshow(tonemap(np.dstack([a_ch[c] for c in "RGB"]), exposure), extent=ext, aspect="auto")
    axes[0].set_title("input (sh_sky_input.exr)")
    axes[1].imshow(tonemap(np.dstack([b_ch[c] for c in "RGB"]), exposure), extent=ext, aspect="auto")
    axes[1].set_title(f"reconstruction, {b_attr.get('sh_bands', '?')} bands (sh_reconstruct.exr)")
    rel = np.abs(lb - la) / max(np.abs(la).max(), 1e-30)
    im = axes[2].imshow(np.log10(np.maximum(rel, 1e-6)), extent=ext, aspect="auto", cmap="viridis")
    fig.colorbar(im, ax=axes[2], label="log$_{10}$ |reconstruction − input| / max input")
    axes[2].set_title("error of the luminance")
    for ax in axes:
        ax.set_xlabel("azimuth from +x towards +y [deg]"); ax.set_ylabel("elevation [deg]"); ax.grid(False)
    fig.suptitle(f"SH projection and reconstruction ({a_attr.get('atmosh:value_units', '')}) — sh_sky_input.exr, sh_reconstruct.exr", fontsize=9)
    fig.tight_layout(); save(fig, "sh_reconstruction")
""")

# --------------------------------------------------------------------------------------
md("optical-depth", "## Optical depth against zenith angle (`optical_depth_vs_zenith.csv`)")
code("fig-optical-depth", """
NAME = "optical_depth_vs_zenith.csv"
if have(NAME):
    df, meta = read(NAME)
    df = df.sort_values("zenith_deg")
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.8))
    a.semilogy(df["zenith_deg"], df["tau_reference"], "-", lw=2, label="exact quadrature (reference)")
    a.semilogy(df["zenith_deg"], df["tau_lut"], "--", label="multi-shell table")
    if "hits_ground" in df and df["hits_ground"].any():
        a.axvline(df.loc[df["hits_ground"] > 0, "zenith_deg"].min(), color="k", lw=0.6, ls=":", label="rays hit the ground beyond")
    a.set_xlabel(label("zenith_deg")); a.set_ylabel(f"optical depth at {meta.get('wavelength_nm', '?')} nm [1]"); a.legend(fontsize=7)
    ok = df["relative_error"].abs() > 0
    b.semilogy(df["zenith_deg"][ok], df["relative_error"].abs()[ok], "-")
    b.set_xlabel(label("zenith_deg")); b.set_ylabel("|table − reference| / reference [relative]")
    fig.suptitle(f"Optical depth from {meta.get('altitude_m', '?')} m, {meta.get('atmosphere', '')} — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "optical_depth_vs_zenith")
""")

# --------------------------------------------------------------------------------------
md("prt", """
## Precomputed radiance transfer: ambient occlusion and relit frames

All frames with one exposure (the 99th percentile of the first frame), so their brightness
compares; ambient occlusion with its own colour bar.
""")
code("fig-prt", """
if have("prt/relight/ao.exr", "prt/relight/frame_0000.exr"):
    ao, ao_attr = read_exr("prt/relight/ao.exr")
    frames = sorted((RESULTS / "prt/relight").glob("frame_*.exr"))
    shown = frames if len(frames) <= 4 else [frames[i] for i in np.linspace(0, len(frames) - 1, 4).astype(int)]
    imgs = [read_exr(f.relative_to(RESULTS).as_posix()) for f in shown]
    print("ao attributes:", ao_attr)
    first = imgs[0][0]; lum0 = 0.2126 * first["R"] + 0.7152 * first["G"] + 0.0722 * first["B"]
    exposure = 1.0 / np.percentile(lum0[lum0 > 0], 99) if np.any(lum0 > 0) else 1.0
    fig, axes = plt.subplots(1, 1 + len(imgs), figsize=(3.2 * (1 + len(imgs)), 3.4))
    im = axes[0].imshow(ao["G"], cmap="gray", vmin=0)
    fig.colorbar(im, ax=axes[0], fraction=0.046, label="ambient occlusion (SH band 0) [1]")
    axes[0].set_title("ao.exr")
    for ax, f, (ch, at) in zip(axes[1:], shown, imgs):
        ax.imshow(tonemap(np.dstack([ch[c] for c in "RGB"]), exposure))
        ax.set_title(f.name)
    for ax in axes:
        ax.set_xticks([]); ax.set_yticks([]); ax.grid(False)
    fig.suptitle(f"PRT, {ao_attr.get('atmosh:transfer_mode', '')} transfer, {ao_attr.get('atmosh:transfer_bands', '?')} bands — prt/relight/ ({len(frames)} frames)", fontsize=9)
    fig.tight_layout(); save(fig, "prt_images")
""")

# --------------------------------------------------------------------------------------
md("stability", """
## Stiff and extreme cases (`stability.csv`)

Each case's error against its bound (log scale); cases with zero error sit on the axis floor.
""")
code("fig-stability", """
NAME = "stability.csv"
if have(NAME):
    df, meta = read(NAME)
    floor = 1e-17
    y = np.arange(len(df))
    fig, ax = plt.subplots(figsize=(7, 0.18 * len(df) + 1.2))
    ax.barh(y, np.maximum(df["error"].abs(), floor), color=np.where(df["pass"] > 0, "tab:blue", "tab:red"), label="error")
    ax.scatter(np.maximum(df["bound"], floor), y, marker="|", color="k", s=60, label="bound", zorder=3)
    ax.set_xscale("log"); ax.set_xlim(left=floor / 2)
    ax.set_yticks(y, df["case"], fontsize=5); ax.invert_yaxis()
    ax.set_xlabel("error (column 'error', in the unit of each case's quantity; zero drawn at 1e-17)"); ax.legend(fontsize=7)
    ax.set_title(f"{int((df['pass'] > 0).sum())} of {len(df)} cases within their bounds — {cite(NAME, meta)}", fontsize=9)
    fig.tight_layout(); save(fig, "stability")
""")

code("summary", """
print(f"{len(SAVED)} figures written to {FIGURES}:")
for s in SAVED:
    print(f"  {s}.pdf  {s}.png")
""")

nb = {"cells": cells, "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
                                   "language_info": {"name": "python"}},
      "nbformat": 4, "nbformat_minor": 5}
ids = [c["id"] for c in cells]
assert len(ids) == len(set(ids)), "cell ids must be unique"
out = pathlib.Path(__file__).with_name("figures.ipynb")
out.write_text(json.dumps(nb, indent=1, ensure_ascii=False) + "\n")
print("wrote", out)
