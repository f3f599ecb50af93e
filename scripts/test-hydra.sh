#!/usr/bin/env bash
# Builds the hdGi plugin against an OpenUSD build with imaging, installs it (cmake --install) and
# runs the Hydra tests on the installed copy
# (usdrecord, incremental edits, every integrator through the render settings).
# Usage: scripts/test-hydra.sh [OPENUSD_PREFIX]   (default $GI_OPENUSD_ROOT, else /opt/openusd)
set -euo pipefail
cd "$(dirname "$0")/.."
openusd=${1:-${GI_OPENUSD_ROOT:-/opt/openusd}}
build=build/hydra
launcher=()
# Paths relative to the checkout in ccache's keys (and not the build folder's, which -g would
# add): a fresh clone elsewhere reuses the cache.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
# The venv's pyoidn (Open Image Denoise), if any, becomes the plugin's default place to load it from
# for gi:denoise (renderer/oidn_library.h); this build's own Python is OpenUSD's, without pyoidn.
oidn=()
oidn_config=$(.venv/bin/python -c "import importlib.util as u, glob; s = u.find_spec('pyoidn'); \
print(next(iter(glob.glob(s.submodule_search_locations[0] + '/oidn/lib/cmake/OpenImageDenoise-*')), '') if s else '')" \
  2>/dev/null || true)
[ -n "$oidn_config" ] && oidn=(-DOpenImageDenoise_DIR="$oidn_config")
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -Dpxr_DIR="$openusd" \
  -DGI_BUILD_PYTHON=OFF -DGI_BUILD_TESTS=OFF "${launcher[@]}" "${oidn[@]}" > "$build.configure.log" || {
  cat "$build.configure.log"; exit 1; }
grep "hdGi:" "$build.configure.log" || true
cmake --build "$build" --target hdGi
# The tests load the installed plugin (README's install step), not the build tree's.
rm -rf "$build-install"
cmake --install "$build" --prefix "$build-install" --component hdGi > /dev/null
export GI_OPENUSD_ROOT=$openusd
export GI_HYDRA_PLUGIN=$PWD/$build-install/plugin/usd/hdGi/resources
.venv/bin/python -m pytest -q tests/hydra
