#!/usr/bin/env bash
# Writes the netCDF-CF outputs the figure notebook reads, next to a main job's results:
#   notebooks_export/netcdf_outputs.sh ATMOSH_BIN RESULTS_DIR [--quick]
# From the scene the main job ran (RESULTS_DIR/scene.toml: its observer and sky image),
# into RESULTS_DIR/netcdf/:
#   sky.nc                          atmosh sky --spectral (the scene's sun and image size)
#   sun_track.nc                    atmosh sun over the observer's UTC day (time coordinate)
#   sun_elevation_study/sun_elevation.nc (+ .csv, plots)   atmosh study sun-elevation --format netcdf
#   day_study/day.nc (+ .csv, plots)                       atmosh study day --no-frames --format netcdf
# --quick: the main job's quick sizes and steps (what the test figures_notebooks runs).
# Run by scripts/main-job.sh after `atmosh demo`, and by the test figures_notebooks.
set -euo pipefail
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: $0 ATMOSH_BIN RESULTS_DIR [--quick]" >&2
  exit 2
fi
atmosh=$1
results=$2
quick=${3:-}
python=${ATMOSH_PYTHON:-$(command -v /usr/bin/python3 || command -v python3)}
scene=$results/scene.toml
out=$results/netcdf
mkdir -p "$out"
# The observer and the first equirect sky image of the scene (Python's tomllib).
read -r lat lon height time width height_px < <("$python" - "$scene" <<'PY'
import sys, tomllib
s = tomllib.load(open(sys.argv[1], "rb"))
o = s["observer"]
size = next((x.get("size", [512, 256]) for x in s.get("output", []) if x.get("kind") == "sky-image"), [512, 256])
print(o["latitude_deg"], o["longitude_deg"], o.get("height_m", 0.0), o["time_utc"], size[0], size[1])
PY
)
date=${time:0:10}
next=$("$python" -c "import datetime, sys; print(datetime.date.fromisoformat(sys.argv[1]) + datetime.timedelta(days=1))" "$date")
if [ "$quick" = "--quick" ]; then
  width=$((width < 64 ? width : 64)); height_px=$((height_px < 32 ? height_px : 32))
  track_step=30min; elevation_step=12; day_step=2h
else
  track_step=10min; elevation_step=1; day_step=20min
fi
"$atmosh" -q sky --scene "$scene" --size "${width}x${height_px}" --spectral -o "$out/sky.nc" >/dev/null
"$atmosh" -q sun --lat "$lat" --lon "$lon" --height "$height" --from "${date}T00:00:00Z" --to "${next}T00:00:00Z" \
  --step "$track_step" -o "$out/sun_track.nc" >/dev/null
"$atmosh" -q study sun-elevation --scene "$scene" --step "$elevation_step" --format netcdf \
  -o "$out/sun_elevation_study" >/dev/null
"$atmosh" -q study day --scene "$scene" --lat "$lat" --lon "$lon" --height "$height" --date "$date" \
  --step "$day_step" --no-frames --format netcdf -o "$out/day_study" >/dev/null
