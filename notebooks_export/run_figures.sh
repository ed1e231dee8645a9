#!/usr/bin/env bash
# Regenerates the paper's figures from a results folder of the main job and checks them:
#   notebooks_export/run_figures.sh RESULTS_DIR [NOTEBOOK_OUT_DIR]
# executes figures.ipynb headless (jupyter nbconvert --execute, matplotlib's Agg backend)
# with ATMOSH_RESULTS=RESULTS_DIR, so the figures go to RESULTS_DIR/figures/ (PDF + PNG);
# the executed notebook goes to NOTEBOOK_OUT_DIR (default RESULTS_DIR/notebooks), never
# into the source tree. Then checks the figures against figures.txt (check_figures.py).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 RESULTS_DIR [NOTEBOOK_OUT_DIR]" >&2
  exit 2
fi
results=$(cd "$1" && pwd)
out=${2:-$results/notebooks}
mkdir -p "$out"
# Debian's interpreter and Jupyter (a python3 earlier on PATH may lack the modules).
python=${ATMOSH_PYTHON:-$(command -v /usr/bin/python3 || command -v python3)}
nbconvert=${ATMOSH_NBCONVERT:-$(command -v /usr/bin/jupyter-nbconvert || command -v jupyter-nbconvert || true)}
if [ -z "$nbconvert" ]; then
  echo "jupyter-nbconvert not found (Debian package jupyter-nbconvert)" >&2
  exit 1
fi
export ATMOSH_RESULTS=$results MPLBACKEND=Agg PYDEVD_DISABLE_FILE_VALIDATION=1 PYTHONDONTWRITEBYTECODE=1
"$nbconvert" --to notebook --execute --ExecutePreprocessor.timeout=600 \
  --output-dir "$out" "$here/figures.ipynb"
"$python" "$here/check_figures.py" "$results"
