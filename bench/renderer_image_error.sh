#!/usr/bin/env bash
# The renderer-vs-brdffit image error of every glTF export (issue 23): each shared MERL proxy is
# fitted with gltf, gltf-specular, gltf+clearcoat, gltf+sheen, gltf+clearcoat+sheen and gltf+anisotropy (its
# isotropic form, gltf, on these isotropic tables); each fit is exported as .gltf,
# drawn by three.js in headless Chromium (tests/tools/render_gltf_three.js: one directional light,
# no environment, no tone mapping, linear floats) and by `brdffit render` (.exr) on the same
# sphere under the same light; prints the mean relative difference per channel over the lit
# pixels inside the outline (n·l ≥ 0.05, within 3 pixels of the silhouette excluded, as
# tests/test_gltf_renderer.cc does). What three.js departs from the glTF BRDF by is written
# down in that test, which checks the departures on synthetic materials.
#
#   bench/renderer_image_error.sh [BUILD_DIR] [WORK_DIR]   (defaults: build, /tmp/brdffit-image-error)
# Needs chromium, node and the npm package three (scripts/install-deps.sh with BRDFFIT_WITH_CHROMIUM=1),
# oiiotool (openimageio-tools) to read the .exr, and Debian's python3 with NumPy.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
work=${2:-/tmp/brdffit-image-error}
brdffit=$build/apps/brdffit
models=(gltf gltf-specular gltf+clearcoat gltf+sheen gltf+clearcoat+sheen gltf+anisotropy)
size=256
light=0.3,0.4,0.866
chromium=$(command -v chromium || command -v chromium-browser) || { echo "chromium not found" >&2; exit 1; }
mkdir -p "$work"

echo "| material | model | lit pixels | three.js vs brdffit render |"
echo "| --- | --- | ---: | ---: |"
for xz in "$here"/../shared/data/merl-proxy/*.binary.xz; do
  [[ -e $xz ]] || continue
  name=$(basename "${xz%.binary.xz}")
  table=$work/$name.binary
  [[ -s $table ]] || xz -dkc "$xz" > "$table"
  fit=$work/$name.json
  [[ -s $fit ]] || "$brdffit" fit "$table" --models "$(IFS=,; echo "${models[*]}")" --out "$fit" -q > /dev/null
  for model in "${models[@]}"; do
    out=$work/$name-$model
    "$brdffit" export "$fit" -m "$model" -o "$out.gltf" --force > /dev/null  # poor fits too: what is drawn is the question
    "$brdffit" render "$fit" -m "$model" --size "$size" --light "$light" -o "$out.exr" -q > /dev/null
    NODE_PATH=$here/.deps/npm/node_modules node "$here/tests/tools/render_gltf_three.js" "$chromium" "$out.gltf" \
      "$size" "$light" "$out.three.json" > /dev/null
    oiiotool --info --dumpdata "$out.exr" > "$out.exr.txt"
    /usr/bin/python3 - "$name" "$model" "$size" "$light" "$out.three.json" "$out.exr.txt" << 'EOF'
import json, re, sys
import numpy as np
name, model, size, light, three_file, exr_text = sys.argv[1:]
size = int(size)
three = json.load(open(three_file))
drawn = np.array(three["rgb"], dtype=float).reshape(three["height"], three["width"], 3)
rendered = np.zeros((size, size, 3))
for line in open(exr_text):  # "Pixel (x, y): r g b"
    m = re.match(r"\s*Pixel \((\d+), (\d+)\):\s*(\S+)\s+(\S+)\s+(\S+)", line)
    if m:
        rendered[int(m[2]), int(m[1])] = [float(m[3]), float(m[4]), float(m[5])]
l = np.array([float(x) for x in light.split(",")]); l /= np.linalg.norm(l)
middle, radius = (size - 1) / 2, size / 2 - 1
y, x = np.mgrid[0:size, 0:size]
nx, ny = (x - middle) / radius, -(y - middle) / radius
r2 = nx * nx + ny * ny
nz = np.sqrt(np.clip(1 - r2, 0, None))
lit = (np.sqrt(r2) < 1 - 3 / radius) & (nx * l[0] + ny * l[1] + nz * l[2] >= 0.05) & (rendered.min(axis=2) > 0)
relative = np.abs(drawn[lit] - rendered[lit]) / rendered[lit]
print(f"| {name} | {model} | {lit.sum()} | {relative.mean():.4f} |")
EOF
  done
done
