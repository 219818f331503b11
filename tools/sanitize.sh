#!/usr/bin/env bash
# Builds rigidae and its test suite with AddressSanitizer and
# UndefinedBehaviorSanitizer (g++, -fno-sanitize-recover=all: the first report
# aborts) and runs the tests with CTest. The command-line tests run the
# sanitized rigidae binary too.
#
# Usage: bash tools/sanitize.sh            every test, -O2, in ./build-asan
#        bash tools/sanitize.sh --subset   the CI subset (docs/robustness.md):
#                                          -Og, no Python module, the tests that
#                                          reach the loaders, the assemblers, the
#                                          Jacobians, the recorders and the
#                                          failure paths, not the accuracy sweeps;
#                                          in ./build-asan-subset
# RIGIDAE_ASAN_BUILD=DIR builds in DIR instead.
set -euo pipefail
cd "$(dirname "$0")/.."

subset=0
if [ "${1:-}" = "--subset" ]; then subset=1; shift; fi

packages=(g++ cmake ninja-build pkg-config
          libsundials-dev libeigen3-dev libsuitesparse-dev libfmt-dev doctest-dev
          libtomlplusplus-dev nlohmann-json3-dev)
bash tools/install_missing.sh sanitize "${packages[@]}"

sanitizers="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
if [ "$subset" = 1 ]; then
  build=${RIGIDAE_ASAN_BUILD:-build-asan-subset}
  # -Og: with both sanitizers it compiles the Eigen-heavy sources in about
  # half the time of -O1 (multibody_problem.cpp: 9.4 s against 18.0 s; -O0
  # 13.7 s, plain -O2 6.6 s) and still runs the tests at a usable speed;
  # the sanitizers see the same code paths.
  # The library in unity batches (CMakeLists.txt, RIGIDAE_UNITY_CORE).
  config=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-Og" -DRIGIDAE_PYTHON=OFF
          -DRIGIDAE_UNITY_CORE=ON)
  targets=(--target rigidae rigidae_tests)
else
  build=${RIGIDAE_ASAN_BUILD:-build-asan}
  config=(-DCMAKE_BUILD_TYPE=Release)
  targets=()
fi
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$PWD"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$build" -G Ninja "${config[@]}" "${launcher[@]}" -DRIGIDAE_VIEWER=OFF \
  -DCMAKE_CXX_FLAGS="$sanitizers -g1" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j"$(nproc)" "${targets[@]}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
if [ "$subset" = 1 ]; then
  # What the subset covers: every input path (bad scenes, fuzz regressions,
  # schema 2, the command line), every assembled residual and iteration
  # matrix (dense, sparse, every joint and combination), the recorders and
  # the checked output files with their failures, and one short run of every
  # shipped scene. Left out: the accuracy sweeps that integrate every
  # combination to tight tolerances (minutes under the sanitizers, and the
  # code they run is the code above, run for longer).
  # Also left out: the multibody matrix-against-differences sweep over every
  # joint x representation x form x scheme (208 s here under the
  # sanitizers); its residuals and matrices are assembled by the same code
  # the allocate-nothing test runs for every representation x form x scheme.
  # Likewise the ODE-form accuracy sweep over every shipped mechanism (IDA
  # references at rtol 1e-11: minutes under the sanitizers); the other
  # 'multibody ode' cases run the same code briefly.
  ctest --test-dir "$build" --output-on-failure -j2 -R \
    'bad input|fuzz regressions|schema 2|exact iteration matrix|allocate nothing|sparse pattern|KLU|multibody|output:|columns:|cli|every scene in problems|a run that fails|flat body: moments|layering' \
    -E 'exact iteration matrix = differences, every joint|run every shipped mechanism to IDA'
else
  ctest --test-dir "$build" --output-on-failure -j2
fi
