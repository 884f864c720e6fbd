#!/usr/bin/env bash
# The cluster figure on one machine: the same batch as one process and as N concurrent shards
# (--shard K/N, one thread each) plus the merge; prints both wall times, checks that the result
# documents agree, and projects 10,000 materials on 100 such machines from the per-material cost.
#
#   bench/shards.sh [BUILD_DIR] [TABLES_DIR] [MODELS] [N] [EXTRA batch options...]
#   (defaults: build, /tmp/brdffit-batch20/tables as bench/batch20.sh makes it, all, 2)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
tables=${2:-/tmp/brdffit-batch20/tables}
models=${3:-all}
shards=${4:-2}
shift $(( $# < 4 ? $# : 4 ))
brdffit=$build/apps/brdffit
work=$(mktemp -d /tmp/brdffit-shards.XXXXXX)
trap 'rm -rf "$work"' EXIT
materials=$(find "$tables" -maxdepth 1 -type f \( -name '*.binary' -o -name '*.bsdf' -o -name '*.csv' \) | wc -l)
cores=$(nproc)

now() { date +%s.%N; }
calc() { awk "BEGIN { print $1 }"; }
start=$(now)
"$brdffit" batch "$tables" --models "$models" --jobs "$cores" --out "$work/one" "$@" > "$work/one.log"
one=$(calc "$(now) - $start")

start=$(now)
pids=()
for ((k = 0; k < shards; k++)); do
  "$brdffit" batch "$tables" --models "$models" --threads $(( cores / shards > 0 ? cores / shards : 1 )) \
    --shard "$k/$shards" --out "$work/sharded" "$@" > "$work/shard-$k.log" &
  pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid"; done
"$brdffit" batch "$tables" --models "$models" --out "$work/sharded" --merge "$@" > "$work/merge.log"
sharded=$(calc "$(now) - $start")

# Same parameters in every document (timings aside).
for doc in "$work"/one/*.json; do
  name=$(basename "$doc")
  [[ $name == summary.json ]] && continue
  python3 - "$doc" "$work/sharded/$name" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
values = lambda d: [(m["model"], m["values"]) for m in d["models"]]
if values(a) != values(b):
    sys.exit(f"shards: {sys.argv[2]} differs from the single-process result")
PY
done

per_material=$(calc "$one * $cores / $materials")
printf 'shards: %d materials x models %s on %d cores\n' "$materials" "$models" "$cores"
printf '  one process (--jobs %d): %.1f s\n' "$cores" "$one"
printf '  %d shards + merge:        %.1f s (%+.1f %%)\n' "$shards" "$sharded" "$(calc "($sharded / $one - 1) * 100")"
printf '  per material: %.1f core-seconds; 10,000 materials on 100 such %d-core nodes: %.1f h\n' \
  "$per_material" "$cores" "$(calc "$per_material * 10000 / (100 * $cores) / 3600")"
