#!/usr/bin/env bash
# Builds the renderer, the gi Python package (installed into .venv) and the C++ tests.
# The CMake build tree is kept in build/ so rebuilds are incremental.
set -euo pipefail
cd "$(dirname "$0")/.."
export CMAKE_BUILD_PARALLEL_LEVEL=${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}
launcher=""
# Paths relative to the checkout in ccache's keys (and not the build folder's, which -g would
# add): a fresh clone elsewhere reuses the cache.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
command -v ccache >/dev/null && launcher="-Ccmake.define.CMAKE_CXX_COMPILER_LAUNCHER=ccache"
.venv/bin/python -m pip install -q --no-build-isolation $launcher .
