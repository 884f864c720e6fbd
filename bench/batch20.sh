#!/usr/bin/env bash
# The batch figure: 20 full-size MERL-format tables (the three shared proxies, when present, and
# tables baked from varied model parameters) fitted with every model by `brdffit batch`; prints
# the wall time and peak memory of the whole batch. TABLES: another number of tables (issue 24's
# goal is stated for ten: `bench/batch20.sh build /tmp/batch10 10`).
#
#   bench/batch20.sh [BUILD_DIR] [WORK_DIR] [TABLES]   (defaults: build, /tmp/brdffit-batch20, 20)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
work=${2:-/tmp/brdffit-batch20}
wanted=${3:-20}
brdffit=$build/apps/brdffit
tables=$work/tables
mkdir -p "$tables"

# The shared proxies (never committed: decompressed here).
for xz in "$here"/../shared/data/merl-proxy/*.binary.xz; do
  [[ -e $xz ]] || continue
  (($(find "$tables" -name '*.binary' | wc -l) < wanted)) || break
  out=$tables/$(basename "${xz%.xz}")
  [[ -s $out ]] || xz -dkc "$xz" > "$out"
done

# Baked tables, each a different model and look, until there are 20.
bakes=(
  "ggx albedo=0.5,0.3,0.1 roughness=0.2 f0=0.04"
  "ggx albedo=0.02 roughness=0.45 f0=0.9,0.6,0.3"
  "ggx albedo=0.3,0.3,0.35 roughness=0.08 f0=0.05"
  "beckmann albedo=0.6,0.5,0.4 specular=0.3 m=0.3"
  "cook-torrance albedo=0.2,0.4,0.1 specular=0.5 f0=0.2 m=0.15"
  "cook-torrance albedo=0.05 specular=0.9 f0=0.8 m=0.35"
  "ward albedo=0.4,0.1,0.1 specular=0.06 alpha=0.12"
  "ward albedo=0.1,0.2,0.5 specular=0.15 alpha=0.3"
  "ashikhmin-shirley albedo=0.5,0.45,0.3 specular=0.5 f0=0.1 n=200"
  "ashikhmin-shirley albedo=0.1 specular=0.8 f0=0.6 n=20"
  "lafortune albedo=0.3,0.2,0.1 specular=0.4 cxy=-0.6 cz=0.55 n=30"
  "blinn-phong albedo=0.2,0.3,0.2 specular=0.3 gloss=80"
  "phong albedo=0.5,0.2,0.2 specular=0.2 shininess=40"
  "oren-nayar albedo=0.6,0.5,0.3 roughness=0.5"
  "lambert albedo=0.7,0.7,0.6"
  "gaussian albedo=0.3,0.3,0.3 specular=0.3 m=0.4"
  "ggx albedo=0.6,0.1,0.1 roughness=0.6 f0=0.04"
  "ward albedo=0.05,0.05,0.05 specular=0.3 alpha=0.05"
  "cook-torrance albedo=0.5,0.5,0.5 specular=0.2 f0=0.05 m=0.5"
  "blinn-phong albedo=0.1,0.1,0.3 specular=0.6 gloss=300"
)
count=$(find "$tables" -name '*.binary' | wc -l)
for i in "${!bakes[@]}"; do
  ((count < wanted)) || break
  read -r model params <<< "${bakes[$i]}"
  out=$tables/baked-$(printf %02d "$i")-$model.binary
  args=()
  for p in $params; do args+=(--param "$p"); done
  [[ -s $out ]] || "$brdffit" bake -m "$model" "${args[@]}" -o "$out" > /dev/null
  count=$((count + 1))
done
echo "batch20: $(find "$tables" -name '*.binary' | wc -l) tables in $tables"

rm -rf "$work/results"
/usr/bin/time -f "batch20: %e s wall, %M KB peak resident memory" \
  "$brdffit" batch "$tables" --models all --jobs 2 --out "$work/results" | tail -3
