#!/usr/bin/env python3
"""Writes figures.ipynb: the notebook that turns `atmosh demo` results into paper figures.

Run by hand after editing the cells below (the .ipynb is committed). The notebook needs
numpy, pandas and matplotlib; OpenEXR images are read with the `OpenEXR` Python module
when present, else the tone-mapped PNG is shown.
"""
import json
import pathlib

FILES = [
    "sun_track.csv",
    "sun_accuracy.csv",
    "lut_convergence.csv",
    "sky_convergence.csv",
    "sun_elevation_study/sun_elevation.csv",
    "sky_sh_bands.csv",
    "stability.csv",
    "optical_depth_vs_zenith.csv",
    "sky.exr",
    "sky.png",
    "prt/converge.csv",
    "prt/relight/ao.png",
    "prt/relight/frame_0000.png",
]

cells = []


def md(text):
    cells.append({"cell_type": "markdown", "metadata": {}, "source": text.strip("\n").splitlines(True)})


def code(text):
    cells.append({"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
                  "source": text.strip("\n").splitlines(True)})


md("""
# atmosh: figures from the main job

Run `bash scripts/main-job.sh` (or `build/bin/atmosh demo -o results`) first. Every CSV
starts with `# key: value` provenance lines (version, commit, command line, scene, time,
host); `read()` below returns them with the table so figures can cite their inputs.
""")
code(f"""
import pathlib
import numpy as np
import pandas as pd
import matplotlib.pyplot as plt

RESULTS = pathlib.Path("../results")
# Files this notebook reads (kept in step with `atmosh demo` by the test suite):
FILES = {json.dumps(FILES)}

def read(name):
    path = RESULTS / name
    meta = {{}}
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            key, _, value = line[1:].partition(":")
            meta[key.strip()] = value.strip()
    return pd.read_csv(path, comment="#"), meta

missing = [f for f in FILES if not (RESULTS / f).exists()]
print("missing:", missing or "none")
""")
md("## Sun position over the default day (NREL SPA)")
code("""
track, meta = read("sun_track.csv")
t = pd.to_datetime(track["time_utc"])
fig, ax = plt.subplots(figsize=(7, 3.5))
ax.plot(t, track["elevation_deg"], label="geometric elevation")
ax.plot(t, track["apparent_elevation_deg"], "--", label="apparent (refracted)")
ax.axhline(0, color="k", lw=0.5)
ax.set_xlabel("time (UTC)"); ax.set_ylabel("elevation [deg]"); ax.legend()
ax.set_title(f"lat {meta.get('latitude_deg')}, lon {meta.get('longitude_deg')}")
fig.autofmt_xdate(); fig.tight_layout()
""")


def study(name, title, err="error_max_rel", time="time_s"):
    code(f"""
df, meta = read("{name}")
fig, ax = plt.subplots(figsize=(5.5, 4))
for method, g in df.groupby("method"):
    ax.loglog(g["{time}"], g["{err}"], "o-", label=method)
ax.set_xlabel("run time [s]  ({{}} cores: {{}})".format(meta.get("host_cores"), meta.get("host")))
ax.set_ylabel("{err}")
ax.set_title("{title}"); ax.legend(fontsize=7); fig.tight_layout()
df
""")


md("## Error against run time")
study("sun_accuracy.csv", "Sun position: fast algorithms vs SPA", err="error_max_deg")
study("lut_convergence.csv", "Optical-depth tables vs exact quadrature")
study("sky_convergence.csv", "Single-scattering sky vs exact reference")
md("## Sky colour against sun elevation")
code("""
df, meta = read("sun_elevation_study/sun_elevation.csv")
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
for col, lab in [("zenith_luminance_cd_m2", "zenith"), ("horizon_sun_luminance_cd_m2", "horizon toward sun"),
                 ("horizon_away_luminance_cd_m2", "horizon away")]:
    ok = df[col] > 0
    a.semilogy(df["sun_elevation_deg"][ok], df[col][ok], label=lab)
a.set_xlabel("sun elevation [deg]"); a.set_ylabel("luminance [cd/m$^2$]"); a.legend()
b.plot(df["sun_elevation_deg"], df["horizon_sun_x"], label="horizon toward sun")
b.plot(df["sun_elevation_deg"], df["zenith_x"], label="zenith")
b.set_xlabel("sun elevation [deg]"); b.set_ylabel("CIE x"); b.legend(); fig.tight_layout()
""")
md("## The sky image")
code("""
try:
    import OpenEXR, Imath
    exr = OpenEXR.InputFile(str(RESULTS / "sky.exr"))
    dw = exr.header()["dataWindow"]; w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    Y = np.frombuffer(exr.channel("Y", Imath.PixelType(Imath.PixelType.FLOAT)), np.float32).reshape(h, w)
    plt.imshow(np.log10(np.maximum(Y, 1e-3)), extent=[0, 360, -90, 90]); plt.colorbar(label="log10 Y [cd/m$^2$]")
    plt.xlabel("azimuth from north [deg]"); plt.ylabel("elevation [deg]")
except ImportError:
    plt.imshow(plt.imread(RESULTS / "sky.png")); plt.axis("off")
""")
md("## Spherical-harmonic band energy of the sky")
code("""
df, meta = read("sky_sh_bands.csv")
plt.semilogy(df["l"], df["energy_g"], "o-"); plt.xlabel("band l"); plt.ylabel("energy (green)")
""")
md("## Precomputed radiance transfer")
study("prt/converge.csv", "PRT transfer vs high-sample reference (CPU ray casting, GPU depth maps)")
code("""
fig, (a, b) = plt.subplots(1, 2, figsize=(9, 4.5))
a.imshow(plt.imread(RESULTS / "prt/relight/ao.png")); a.set_title("ambient occlusion (SH band 0)"); a.axis("off")
b.imshow(plt.imread(RESULTS / "prt/relight/frame_0000.png")); b.set_title("relit, first light direction"); b.axis("off")
fig.tight_layout()
""")
md("## Stiff and extreme cases")
code("""
df, meta = read("stability.csv")
df
""")

nb = {"cells": cells, "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
                                   "language_info": {"name": "python"}},
      "nbformat": 4, "nbformat_minor": 5}
out = pathlib.Path(__file__).with_name("figures.ipynb")
out.write_text(json.dumps(nb, indent=1) + "\n")
print("wrote", out)
