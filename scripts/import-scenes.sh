#!/usr/bin/env bash
# Imports the Sibenik and Sponza sources from the asset folder ($GI_ASSETS, default ../shared/assets)
# into scenes/*/generated/ (git-ignored), which scenes/sibenik/sibenik.usda and
# scenes/sponza/sponza.usda sublayer. Textures stay in the asset folder; the generated layers name
# them relative to themselves. Skips a scene whose sources are absent.
set -euo pipefail
cd "$(dirname "$0")/.."
assets=${GI_ASSETS:-../shared/assets}
gi=${GI:-.venv/bin/gi}
if [ -f "$assets/sibenik/sibenik.obj" ]; then
  "$gi" import "$assets/sibenik/sibenik.obj" -o scenes/sibenik/generated/sibenik.usdc
  "$gi" import "$assets/sibenik/extras/staklo.obj" -o scenes/sibenik/generated/staklo.usdc
else
  echo "import-scenes: no $assets/sibenik/sibenik.obj; scenes/sibenik is not set up (set GI_ASSETS)" >&2
fi
if [ -f "$assets/sponza/dabrovic/sponza.obj" ]; then
  "$gi" import "$assets/sponza/dabrovic/sponza.obj" -o scenes/sponza/generated/sponza.usdc
else
  echo "import-scenes: no $assets/sponza/dabrovic/sponza.obj; scenes/sponza is not set up (set GI_ASSETS)" >&2
fi
