#!/usr/bin/env bash
# Builds rigidae and its whole test suite with AddressSanitizer and
# UndefinedBehaviorSanitizer (g++, -fno-sanitize-recover=all: the first report
# aborts) in ./build-asan and runs every test with CTest. The command-line
# tests run the sanitized rigidae binary too.
#
# Usage: bash tools/sanitize.sh        (RIGIDAE_ASAN_BUILD=DIR to build elsewhere)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake ninja-build pkg-config
          libsundials-dev libeigen3-dev libsuitesparse-dev libfmt-dev doctest-dev
          libtomlplusplus-dev nlohmann-json3-dev)
bash tools/install_missing.sh sanitize "${packages[@]}"

build=${RIGIDAE_ASAN_BUILD:-build-asan}
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -g1"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j"$(nproc)"

export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build" --output-on-failure -j2
