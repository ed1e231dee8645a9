#!/usr/bin/env bash
# Installs every build and test dependency of atmosh from Debian 12 packages.
# Idempotent: packages already present are skipped by apt. Run as root.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build ccache git pkg-config
  file  # cpack -G DEB runs dpkg-shlibdeps on the ELF files file(1) finds
  clang libclang-rt-14-dev
  libglm-dev libfftw3-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev
  libopenexr-dev
  libgeographiclib-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev libtinyobjloader-dev libassimp-dev
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pandas python3-pytest
  # the figure notebooks (notebooks_export/), executed headless by the test suite and the main job
  jupyter-nbconvert python3-nbconvert python3-ipykernel python3-nbformat python3-nbclient
  python3-matplotlib python3-openimageio
  slurm-wlm munge  # the slurm_sweep test starts a one-node cluster (docs/sweeps.md)
  libnetcdf-dev libnetcdf-c++4-dev python3-xarray python3-netcdf4
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
