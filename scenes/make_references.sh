#!/usr/bin/env bash
# Converged references (unbounded depth, the path tracer's defaults) of the untuned scenes of
# issue 15, written to out/references/: `gi reference` renders batches until the image mean's
# relative standard error is under --target-error or --max-seconds pass. Where the sun is seen
# only through glass (the glazed room, Sibenik) the path tracer cannot converge on it, and
# --sun-by-photons renders the sun alone with the progressive photon map (README, "A reference
# per light"); Sponza's sun the path tracer sees directly.
# Usage: scenes/make_references.sh [MAX_SECONDS_PER_SCENE] [W H]   (default 1800 s, 512 384)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-1800}
width=${2:-512} height=${3:-384}
mkdir -p out/references
for scene in scenes/window_room/window_room.usda scenes/sponza/sponza.usda scenes/sibenik/sibenik_sky.usda; do
  name=$(basename "$scene" .usda)
  sun=()
  [[ $name == sponza ]] || sun=(--sun-by-photons)
  .venv/bin/gi reference "$scene" -o "out/references/$name.exr" --max-seconds "$seconds" \
    --resolution "$width" "$height" --target-error 0.002 "${sun[@]}"
done
