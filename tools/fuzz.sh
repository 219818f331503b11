#!/usr/bin/env bash
# Fuzzes the scene loader and validator (fuzz/fuzz_scene_loader.cpp) with
# libFuzzer for a bounded time: installs clang from Debian if missing, builds
# with ASan + UBSan and coverage instrumentation in ./build-fuzz, and runs on a
# seed corpus of problems/*.toml, tests/bad_scenes/ and tests/fuzz_regressions/.
#
# Usage: bash tools/fuzz.sh [--study] [SECONDS] [LIBFUZZER OPTION...]
#   --study   fuzz the study-file loader and planner (fuzz/fuzz_study_loader.cpp)
#             instead, seeded with studies/ and tests/bad_studies/
#   SECONDS   total run time (default 300)
#   e.g.      bash tools/fuzz.sh 600 -jobs=2 -workers=2
# The growing corpus is kept in build-fuzz/corpus (reused by the next run);
# inputs that crash, hang or trip a sanitizer land in build-fuzz/findings/.
# RIGIDAE_FUZZ_BUILD=DIR builds and keeps both in DIR instead of build-fuzz.
# Each finding, once fixed, belongs in tests/fuzz_regressions/ (see
# docs/robustness.md): the test suite loads every file there.
set -euo pipefail
cd "$(dirname "$0")/.."
target=fuzz_scene_loader
dict=fuzz/scene.dict
if [ "${1:-}" = "--study" ]; then
  target=fuzz_study_loader
  dict=fuzz/study.dict
  shift
fi
seconds=${1:-300}
shift || true

packages=(clang libclang-rt-14-dev cmake ninja-build pkg-config
          libsundials-dev libeigen3-dev libsuitesparse-dev libfmt-dev doctest-dev
          libtomlplusplus-dev nlohmann-json3-dev)
bash tools/install_missing.sh fuzz "${packages[@]}"

build=${RIGIDAE_FUZZ_BUILD:-build-fuzz}
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRIGIDAE_FUZZ=ON >/dev/null
cmake --build "$build" --target "$target" -j"$(nproc)"

corpus="$build/corpus"
seeds=(problems tests/bad_scenes)
[ -d tests/fuzz_regressions ] && seeds+=(tests/fuzz_regressions)
if [ "$target" = fuzz_study_loader ]; then
  corpus="$build/corpus_study"
  seeds=(studies)
fi
mkdir -p "$corpus" "$build/findings"
exec "$build/$target" "$corpus" "${seeds[@]}" \
  -dict="$dict" -max_total_time="$seconds" -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
  -artifact_prefix="$build/findings/" -print_final_stats=1 "$@"
