#!/usr/bin/env bash
# Installs what is missing, builds brdffit and runs the main job on the bundled data.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
mkdir -p build
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBRDFFIT_BUILD_TESTS=OFF -DBRDFFIT_BUILD_BENCH=OFF > build/configure.log 2>&1 \
  || { cat build/configure.log; exit 1; }
cmake --build build -j "$(nproc)" --target brdffit_cli
./build/apps/brdffit models
./build/apps/brdffit eval ggx --param albedo=0.6,0.3,0.2 --param roughness=0.3 --light 1,0,1 --view -1,0,1.2
