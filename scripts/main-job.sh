#!/usr/bin/env bash
# Sets up (Debian 12, as root), builds atmosh and runs the main job on the built-in
# default scene, writing everything under results/ (list in results/MANIFEST.txt) and the
# netCDF-CF files under results/netcdf/ (notebooks_export/netcdf_outputs.sh), then
# regenerates the paper's figures from those results (results/figures/, PDF + PNG, the
# list in notebooks_export/figures.txt) by executing notebooks_export/figures.ipynb headless.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "$(id -u)" = 0 ]; then bash scripts/setup-debian.sh; fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DATMOSH_BUILD_TESTS=OFF -DATMOSH_BUILD_BENCH=OFF
cmake --build build -j "$(nproc)" --target atmosh
build/bin/atmosh demo -o results "$@"
# The netCDF-CF outputs the figures read (sky image, sun track, sun-elevation and day studies).
bash notebooks_export/netcdf_outputs.sh build/bin/atmosh results $(printf '%s\n' "$@" | grep -x -- --quick || true)
bash notebooks_export/run_figures.sh results results/notebooks
