#!/usr/bin/env bash
# The C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer, in their own build tree
# (build/asan: -DGI_SANITIZE=ON, no Python module, no Hydra plugin), compiled through ccache like
# the main build. Bounded for CI: the statistical convergence tests, which only repeat the code the
# other tests already run with more samples, are left out (GI_SANITIZE_ALL=1 runs them too), and
# every test has a time limit. (Glossy reflection through glass, 2,048 path-traced spp against four
# techniques, four seeds, took 400-450 s of the run's 560 here.)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${GI_SANITIZE_BUILD_DIR:-build/asan}
jobs=${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}

if [ ! -f "$build/CMakeCache.txt" ]; then
  launcher=()
  # Paths relative to the checkout in ccache's keys (and not the build folder's, which -g would
  # add): a fresh clone elsewhere reuses the cache.
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGI_SANITIZE=ON \
    -DGI_BUILD_PYTHON=OFF -DGI_BUILD_HYDRA=OFF -DGI_BUILD_TESTS=ON "${launcher[@]}"
fi
cmake --build "$build" --target gi_tests -j "$jobs"

# halt_on_error: the first report fails the test. Leak checking stays on (the default).
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:halt_on_error=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
exclude='Converges|ErrorFallsAsAccuracyTightens|AdaptiveHasNoMoreDiscontinuities|albedo9|ColouredCausticMatchesThePathTracer|UnbiasedAtDefaults|GlossyReflectionThroughGlassCountedOnce'
[ "${GI_SANITIZE_ALL:-0}" = 1 ] && exclude='^$'
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" --timeout 600 -E "$exclude"
