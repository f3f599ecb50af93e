#!/usr/bin/env bash
# README's first command: sets everything up on a fresh Debian 12 machine (packages, venv,
# build), imports the Sibenik and Sponza sources and renders the Cornell box to out/cornell.exr and out/cornell.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
bash scripts/import-scenes.sh   # Sibenik and Sponza from $GI_ASSETS (default ../shared/assets)
mkdir -p out
.venv/bin/gi render scenes/cornell/cornell.usda --integrator path --spp 64 -o out/cornell.exr
