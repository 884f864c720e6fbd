#!/usr/bin/env bash
# Replays every fuzz target's seed corpus (tests/fuzz/corpus/<name>) through its replay_<name>
# build (tests/CMakeLists.txt), once per input: seconds, no fuzzing. scripts/test.sh runs it in
# the sanitizer build, where a seed that crashes, leaks or trips UBSan fails it; a target without
# a corpus, or a corpus without a target, fails it too.
# Usage: scripts/fuzz-replay.sh [BUILD_DIR]   (default build-asan)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-asan}
status=0
for source in tests/fuzz/fuzz_*.cc; do
  name=$(basename "$source" .cc)
  name=${name#fuzz_}
  replay="$build/tests/replay_$name"
  corpus="tests/fuzz/corpus/$name"
  if [[ ! -x "$replay" ]]; then echo "fuzz-replay: $replay was not built" >&2; status=1; continue; fi
  if [[ ! -d "$corpus" ]]; then echo "fuzz-replay: $name has no seed corpus ($corpus)" >&2; status=1; continue; fi
  "$replay" "$corpus" || { echo "fuzz-replay: $name failed on its corpus" >&2; status=1; }
done
for corpus in tests/fuzz/corpus/*/; do
  name=$(basename "$corpus")
  [[ -f "tests/fuzz/fuzz_$name.cc" ]] || { echo "fuzz-replay: $corpus has no target" >&2; status=1; }
done
exit $status
