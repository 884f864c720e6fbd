#!/usr/bin/env bash
# The renderer-materials figures (issue 13): on the three shared MERL proxies and the six shared
# RGL tables, the cosine and log error and the seconds of the gltf, gltf-specular, openpbr and
# principled fits beside ggx (each fitted minimising the cosine metric, all samples); then the
# published glTF fits of hephil/gltfit (results/materials.json, a glTF "materials" array; pass its
# path) scored on the MERL proxies with `brdffit score -m gltf`, beside our gltf fit.
#
#   bench/renderer_materials.sh [BUILD_DIR] [WORK_DIR] [GLTFIT_MATERIALS_JSON]
#   (defaults: build, /tmp/brdffit-renderer, no published comparison)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
work=${2:-/tmp/brdffit-renderer}
published=${3:-}
brdffit=$build/apps/brdffit
models=ggx,gltf,gltf-specular,openpbr,principled
mkdir -p "$work/tables" "$work/fits"

tables=()
for xz in "$here"/../shared/data/merl-proxy/*.binary.xz; do
  [[ -e $xz ]] || continue
  out=$work/tables/$(basename "${xz%.xz}")
  [[ -s $out ]] || xz -dkc "$xz" > "$out"
  tables+=("$out")
done
for bsdf in "$here"/../shared/data/rgl/*.bsdf; do [[ -e $bsdf ]] && tables+=("$bsdf"); done
((${#tables[@]})) || { echo "no shared tables under $here/../shared/data" >&2; exit 1; }

echo "| material | model | verdict | cosine | log | seconds |"
echo "| --- | --- | --- | ---: | ---: | ---: |"
for table in "${tables[@]}"; do
  name=$(basename "$table"); name=${name%.*}
  csv=$work/fits/$name.csv
  [[ -s $csv ]] || "$brdffit" fit "$table" --models "$models" --out "$work/fits/$name.json" --csv "$csv" > /dev/null
  # Columns by their header names (fit --csv: model, status, verdict, cosine, log, ..., seconds, parameters).
  awk -F, -v name="$name" 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    { printf "| %s | %s | %s | %.4f | %.4f | %.1f |\n", name, $col["model"], $col["verdict"], $col["cosine"], $col["log"], $col["seconds"] }' \
    "$csv" | sort -t'|' -k3,3
done

[[ -n $published ]] || exit 0
# hephil/gltfit's file is a glTF materials array: read as a .gltf, each material by its name.
cp "$published" "$work/gltfit.gltf"
echo
echo "| MERL material | gltfit cosine | ours (gltf fit) cosine | gltfit log | ours log |"
echo "| --- | ---: | ---: | ---: | ---: |"
for table in "${tables[@]}"; do
  [[ $table == *.binary ]] || continue
  name=$(basename "$table" .binary)
  theirs=$("$brdffit" score "$table" --material "$work/gltfit.gltf" --name "$name" -m gltf --json 2> /dev/null)
  python3 - "$theirs" "$work/fits/$name.csv" "$name" <<'PY'
import csv, json, sys
theirs = json.loads(sys.argv[1])["metrics"]
ours = next(row for row in csv.DictReader(open(sys.argv[2])) if row["model"] == "gltf")
print(f"| {sys.argv[3]} | {theirs['cosine']:.4f} | {float(ours['cosine']):.4f} | {theirs['log']:.4f} | {float(ours['log']):.4f} |")
PY
done
