#!/usr/bin/env bash
# The cluster figures on one machine: the same batch as one process, as N concurrent shards
# (--shard K/N) plus the merge, and under mpirun with N and N+1 ranks (rank 0 hands the materials
# out; with N+1 ranks, N of them fit). Prints each wall time against the single process, checks
# that every run's result documents hold the single process's values, and projects 10,000
# materials on 100 such machines from the per-material cost.
#
#   bench/cluster.sh [BUILD_DIR] [TABLES_DIR] [MODELS] [N] [EXTRA batch options...]
#   (defaults: build, /tmp/brdffit-batch20/tables as bench/batch20.sh makes it, all, 2)
# The MPI runs are skipped when brdffit-mpi was not built or mpirun is missing.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
tables=${2:-/tmp/brdffit-batch20/tables}
models=${3:-all}
n=${4:-2}
shift $(($# < 4 ? $# : 4))
brdffit=$build/apps/brdffit
work=$(mktemp -d /tmp/brdffit-cluster.XXXXXX)
trap 'rm -rf "$work"' EXIT
materials=$(find "$tables" -maxdepth 1 -type f \( -name '*.binary' -o -name '*.bsdf' -o -name '*.csv' \) | wc -l)
cores=$(nproc)
threads=$((cores / n > 0 ? cores / n : 1))

now() { date +%s.%N; }
calc() { awk "BEGIN { print $1 }"; }

# Every result document of run $1 holds the same models and values (to 1e-6 relative) as the single process's.
same_as_one() {
  for doc in "$work"/one/*.json; do
    local name
    name=$(basename "$doc")
    [[ $name == summary.json ]] && continue
    python3 - "$doc" "$work/$1/$name" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
# A fit on another number of threads sums in another order: the same values to rounding (1e-15
# relative; 1e-8 for parameters the data do not determine), not bit for bit.
for x, y in zip(a["models"], b["models"]):
    close = x["model"] == y["model"] and len(x["values"]) == len(y["values"]) and all(
        abs(p - q) <= 1e-6 * max(abs(p), abs(q), 1e-12) for p, q in zip(x["values"], y["values"]))
    if not close:
        sys.exit(f"cluster: {sys.argv[2]}: {x['model']} differs from the single-process result")
PY
  done
}

report() {  # label, seconds
  printf '  %-28s %7.1f s (%+.1f %% against one process)\n' "$1" "$2" "$(calc "($2 / $one - 1) * 100")"
}

start=$(now)
"$brdffit" batch "$tables" --models "$models" --jobs "$cores" --out "$work/one" "$@" > "$work/one.log"
one=$(calc "$(now) - $start")
printf 'cluster: %d materials x models %s on %d cores\n' "$materials" "$models" "$cores"
printf '  %-28s %7.1f s\n' "one process (--jobs $cores)" "$one"

start=$(now)
pids=()
for ((k = 0; k < n; k++)); do
  "$brdffit" batch "$tables" --models "$models" --threads "$threads" --shard "$k/$n" --out "$work/sharded" "$@" \
    > "$work/shard-$k.log" &
  pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid"; done
"$brdffit" batch "$tables" --models "$models" --out "$work/sharded" --merge "$@" > "$work/merge.log"
report "$n shards + merge" "$(calc "$(now) - $start")"
same_as_one sharded

if [[ -x $build/apps/brdffit-mpi ]] && command -v mpirun > /dev/null; then
  for ranks in "$n" "$((n + 1))"; do
    start=$(now)
    # --bind-to none: by default mpirun binds each of up to two ranks to one core, so a worker
    # would fit on one core however many it could use.
    mpirun --oversubscribe --allow-run-as-root --bind-to none -n "$ranks" "$brdffit" batch "$tables" --models "$models" \
      --out "$work/mpi-$ranks" "$@" > "$work/mpi-$ranks.log"
    report "mpirun -n $ranks ($((ranks - 1)) fitting)" "$(calc "$(now) - $start")"
    same_as_one "mpi-$ranks"
  done
else
  echo "  mpirun: skipped (brdffit-mpi not built or mpirun missing)"
fi

per_material=$(calc "$one * $cores / $materials")
printf '  per material: %.1f core-seconds; 10,000 materials on 100 such %d-core nodes: %.1f h\n' \
  "$per_material" "$cores" "$(calc "$per_material * 10000 / (100 * $cores) / 3600")"
