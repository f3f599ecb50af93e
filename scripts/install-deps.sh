#!/usr/bin/env bash
# Installs the Debian packages hdGi builds against (only those missing), then a Python venv
# in .venv with the Python dependencies. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake ninja-build pkg-config ccache libembree-dev libtbb-dev libopenimageio-dev
          libopencolorio-dev libosd-dev libtinygltf-dev libtinyobjloader-dev libgtest-dev python3-venv)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing Debian packages: ${missing[*]}"
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
fi

python=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  "$python" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
# pyoidn ships Intel Open Image Denoise 2.x (gi render --denoise, gi study's denoised rows); optional
# for users, installed here so that CI tests the denoiser. openjd-cli runs the farm-job tests
# (openjd check / openjd run).
.venv/bin/python -m pip install -q scikit-build-core nanobind numpy usd-core tqdm matplotlib flip-evaluator pytest pyoidn openjd-cli
