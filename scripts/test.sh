#!/usr/bin/env bash
# Installs what is missing, checks the code's format, builds brdffit and runs the numerical tests
# (ctest, then the Python module's pytest suite); then builds it with AddressSanitizer and
# UndefinedBehaviorSanitizer and runs the other tests, whose code paths differ under them
# (tests/CMakeLists.txt). With --no-sanitize, every test in the first build only. At the end: each
# phase's wall time, the skipped tests and the ten slowest tests. Under CI (CI set to anything but
# empty) a Python module that was not built, or a skip that tests/allowed_skips.txt does not list,
# fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

phases=()
timed() {  # phase name, command...: runs the command and keeps its wall time
  local name=$1 start=$SECONDS
  shift
  "$@"
  phases+=("$(printf '%6d s  %s' $((SECONDS - start)) "$name")")
}
print_phases() {
  echo "== wall time per phase"
  printf '%s\n' "${phases[@]}"
}
trap print_phases EXIT

# Both builds are unity builds (CMake joins the sources of a target, 16 at a time, into one file):
# every file parses the same heavy headers (Ceres, Eigen, fmt, nlohmann::json, CLI11, gtest) and
# instantiates the same templates, and compiling them together cut the builds' CPU time by a
# third at 8 files (Release: 720 → 480 CPU s) and a sixth more at 16 (the files but
# src/registry.cc: 407 → 336 CPU s); 32 saved little more and made one test file of 95 s, which the
# other core waits for at the end. docs/testing.md has the phases' times. A developer's
# `cmake -S . -B build` compiles file by file, which rebuilds less after an edit; these runs keep
# the sources safe to join (no two files may define the same name in an anonymous namespace:
# shared test helpers live in tests/*_util.h).
# With Ninja, which compiles a target's files while the libraries it links are still being built
# (make waits for them, and one core idled while the other compiled src/registry.cc), unless the
# folder was configured earlier with another generator, which CMake cannot switch.
configure_and_build() {  # build-dir, extra cmake args...
  local dir=$1
  shift
  mkdir -p "$dir"
  local generator=(-G Ninja)
  if [[ -f $dir/CMakeCache.txt ]] && ! grep -qx 'CMAKE_GENERATOR:INTERNAL=Ninja' "$dir/CMakeCache.txt"; then
    generator=()
  fi
  cmake -S . -B "$dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON \
    -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 "$@" > "$dir.configure.log" 2>&1 || { cat "$dir.configure.log"; exit 1; }
  cmake --build "$dir" -j "$jobs"
}
run_ctest() {  # build-dir: every test it lists, with a JUnit report for the summary
  ctest --test-dir "$1" --output-on-failure -j "$jobs" --output-junit "$PWD/$1/ctest.junit.xml"
}
check_format() {
  git ls-files '*.cc' '*.h' | xargs clang-format --dry-run --Werror
  if git ls-files '*.cc' '*.h' | LC_ALL=C.UTF-8 xargs grep -nP '^.{121,}$'; then
    echo "the lines above are over 120 columns" >&2
    exit 1
  fi
}

timed "dependencies" env BRDFFIT_WITH_CHROMIUM=1 bash scripts/install-deps.sh
echo "== format: clang-format (.clang-format) and at most 120 columns"
timed "format check" check_format

# Replays: in the sanitizer build. The benchmarks (bench/, not tests) are left to the default
# build, which every developer's `cmake -S . -B build` makes: here they were 30 s of the 15 minutes.
# Each test runs once, in the build that suits it (tests/CMakeLists.txt): the numerical ones here,
# the others under the sanitizers; without those, all of them here.
sanitize=true
[[ "${1:-}" == "--no-sanitize" ]] && sanitize=false
release_tests=numerical
$sanitize || release_tests=all
timed "Release build" configure_and_build build -DBRDFFIT_FUZZ_REPLAY=OFF -DBRDFFIT_BUILD_BENCH=OFF \
  -DBRDFFIT_TEST_FILES=$release_tests
timed "Release suite (ctest)" run_ctest build
reports=("Release suite=build/ctest.junit.xml")
if [[ -x build/python/pytest.sh ]]; then
  echo "== Python module (pytest python/tests)"
  timed "Python module (pytest)" build/python/pytest.sh -v --durations=5 --junitxml="$PWD/build/pytest.junit.xml"
  reports+=("Python module=build/pytest.junit.xml")
elif [[ -n "${CI:-}" ]]; then
  echo "== the Python module was not built (see 'Python module' in build.configure.log): CI needs it" >&2
  exit 1
else
  echo "== Python module not built (see 'Python module' in build.configure.log): pytest skipped"
fi
if $sanitize; then
  echo "== the other tests with AddressSanitizer + UndefinedBehaviorSanitizer"
  timed "sanitizer build" configure_and_build build-asan -DBRDFFIT_SANITIZE=ON -DBRDFFIT_BUILD_BENCH=OFF \
    -DBRDFFIT_PYTHON=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRDFFIT_TEST_FILES=other
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 timed "sanitizer suite (ctest)" run_ctest build-asan
  reports+=("sanitizer suite=build-asan/ctest.junit.xml")
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 timed "fuzz corpora (replay)" \
    bash scripts/fuzz-replay.sh build-asan
fi
python3 scripts/test_summary.py tests/allowed_skips.txt "${reports[@]}"
