#!/usr/bin/env bash
# Installs what is missing, builds brdffit and fits every model to the bundled RGL material.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
mkdir -p build
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > build/configure.log 2>&1 || { cat build/configure.log; exit 1; }
cmake --build build -j "$(nproc)" --target brdffit_cli
./build/apps/brdffit info data/cc_ibiza_sunset_rgb.bsdf
./build/apps/brdffit fit data/cc_ibiza_sunset_rgb.bsdf --models all --out build/cc_ibiza_sunset.fit.json
./build/apps/brdffit report build/cc_ibiza_sunset.fit.json --out build/cc_ibiza_sunset.report.html
echo "result document: build/cc_ibiza_sunset.fit.json; pictures of every fit: build/cc_ibiza_sunset.report.html"
