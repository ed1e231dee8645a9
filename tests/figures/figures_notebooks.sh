#!/usr/bin/env bash
# Test figures_notebooks: runs the quick main job (atmosh demo --quick, then
# notebooks_export/netcdf_outputs.sh --quick) into a temporary folder, executes the
# figure notebook on it headless and checks every figure listed in
# notebooks_export/figures.txt (present, non-empty, PDF/PNG signature).
#   figures_notebooks.sh ATMOSH_BIN SOURCE_DIR
set -euo pipefail
atmosh=$1
src=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/atmosh_figures.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$atmosh" demo --quick -o "$work/results" >"$work/demo.log" 2>&1 || { cat "$work/demo.log"; exit 1; }
# ... and the netCDF-CF files the notebook reads in preference to the CSV/EXR.
ATMOSH_PYTHON=${ATMOSH_PYTHON:-python3} bash "$src/notebooks_export/netcdf_outputs.sh" "$atmosh" "$work/results" --quick \
  >>"$work/demo.log" 2>&1 || { cat "$work/demo.log"; exit 1; }
# The notebook reads all of the main job's files: none may be missing here.
missing=$(ATMOSH_RESULTS=$work/results "${ATMOSH_PYTHON:-python3}" - "$src/notebooks_export/figures.ipynb" <<'PY'
import json, os, pathlib, sys
nb = json.load(open(sys.argv[1]))
files = []
for name in ("FILES = [", "NC_FILES = ["):
    line = next(l for c in nb["cells"] for l in c["source"] if l.startswith(name))
    files += json.loads(line[len(name) - 1:])
print(" ".join(f for f in files if not (pathlib.Path(os.environ["ATMOSH_RESULTS"]) / f).is_file()))
PY
)
if [ -n "$missing" ]; then
  echo "the main job did not write these inputs of the notebook: $missing" >&2
  exit 1
fi
bash "$src/notebooks_export/run_figures.sh" "$work/results" "$work/notebooks"
