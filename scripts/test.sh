#!/usr/bin/env bash
# Installs what is missing, checks the code's format, builds brdffit and runs the whole test suite
# (ctest, then the Python module's pytest suite); then builds and runs
# it once more with AddressSanitizer and UndefinedBehaviorSanitizer (skip with --no-sanitize).
set -euo pipefail
cd "$(dirname "$0")/.."
BRDFFIT_WITH_CHROMIUM=1 bash scripts/install-deps.sh
jobs=$(nproc)

run_suite() {  # build-dir, extra cmake args...
  local dir=$1; shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" > "$dir.configure.log" 2>&1 || { cat "$dir.configure.log"; exit 1; }
  cmake --build "$dir" -j "$jobs"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs"
}

echo "== format: clang-format (.clang-format) and at most 120 columns"
git ls-files '*.cc' '*.h' | xargs clang-format --dry-run --Werror
if git ls-files '*.cc' '*.h' | LC_ALL=C.UTF-8 xargs grep -nP '^.{121,}$'; then
  echo "the lines above are over 120 columns" >&2
  exit 1
fi

mkdir -p build
run_suite build
if [[ -x build/python/pytest.sh ]]; then
  echo "== Python module (pytest python/tests)"
  build/python/pytest.sh -v
else
  echo "== Python module not built (see 'Python module' in build.configure.log): pytest skipped"
fi
if [[ "${1:-}" != "--no-sanitize" ]]; then
  echo "== again with AddressSanitizer + UndefinedBehaviorSanitizer"
  mkdir -p build-asan
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    run_suite build-asan -DBRDFFIT_SANITIZE=ON -DBRDFFIT_BUILD_BENCH=OFF -DBRDFFIT_PYTHON=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 bash scripts/fuzz-replay.sh build-asan
fi
