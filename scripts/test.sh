#!/usr/bin/env bash
# Sets up (Debian 12, as root), builds and runs the whole atmosh test suite:
#   1. Release build with the default compiler: unit tests, CLI and end-to-end tests,
#      install + consumer project;
#   2. clang + AddressSanitizer + UndefinedBehaviorSanitizer build running the suite;
#   3. libFuzzer on the scene parser for a bounded time (ATMOSH_FUZZ_SECONDS, 60 s).
set -euo pipefail  # pipefail: a failing ctest fails the script even through tee
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}
FUZZ_SECONDS=${ATMOSH_FUZZ_SECONDS:-60}

if [ "$(id -u)" = 0 ]; then bash scripts/setup-debian.sh; fi
export ATMOSH_REQUIRE_GPU_CONTEXT=1   # Mesa llvmpipe is installed: EGL must work

LOGS=$(mktemp -d)
passed=0
count_passed() {  # adds ctest's "out of N" of a fully green run to $passed
  local n
  n=$(sed -n 's/^100% tests passed, 0 tests failed out of \([0-9]*\)$/\1/p' "$1" | tail -n 1)
  passed=$((passed + ${n:-0}))
}

echo "== [1/3] Release build and tests"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$JOBS"
ctest --test-dir build -j "$JOBS" --output-on-failure --timeout 900 | tee "$LOGS/release.log"
count_passed "$LOGS/release.log"

echo "== [2/3] clang AddressSanitizer + UndefinedBehaviorSanitizer"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DATMOSH_SANITIZE=address,undefined -DATMOSH_BUILD_BENCH=OFF
cmake --build build-asan -j "$JOBS"
ctest --test-dir build-asan -j "$JOBS" --output-on-failure --timeout 1800 | tee "$LOGS/asan.log"
count_passed "$LOGS/asan.log"

echo "== [3/3] libFuzzer: scene parser for ${FUZZ_SECONDS} s"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DATMOSH_SANITIZE=address,undefined -DATMOSH_BUILD_FUZZ=ON -DATMOSH_BUILD_BENCH=OFF -DATMOSH_WITH_GPU=OFF
cmake --build build-fuzz -j "$JOBS" --target fuzz_scene
mkdir -p build-fuzz/corpus
build-fuzz/bin/fuzz_scene -max_total_time="$FUZZ_SECONDS" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1 build-fuzz/corpus tests/fuzz/corpus
echo "fuzzing: no findings in ${FUZZ_SECONDS} s"
passed=$((passed + 1))
echo "all stages green: Release suite, sanitizer suite, fuzzing"
echo "${passed} passed, 0 failed"
