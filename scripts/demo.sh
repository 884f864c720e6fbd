#!/usr/bin/env bash
# Installs what is missing, builds what the README's first sections use (brdffit, brdffit-imaging
# for render and report, brdffit-mpi when OpenMPI is there, the Python module) and fits every
# model to the bundled RGL material, then writes its report.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
mkdir -p build
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > build/configure.log 2>&1 || { cat build/configure.log; exit 1; }
# brdffit_cli depends on brdffit-imaging (and brdffit-mpi), to which it hands commands over.
targets=(brdffit_cli)
python_module=0
if grep -q "Python module: on" build/configure.log; then
  targets+=(brdffit_python)
  python_module=1
else
  grep "Python module" build/configure.log || true
fi
cmake --build build -j "$(nproc)" --target "${targets[@]}"
if ((python_module)); then
  PYTHONPATH=build/python python3 -c 'import brdffit; print("Python module:", brdffit.__file__)'
fi
./build/apps/brdffit info data/cc_ibiza_sunset_rgb.bsdf
./build/apps/brdffit fit data/cc_ibiza_sunset_rgb.bsdf --models all --out build/cc_ibiza_sunset.fit.json
./build/apps/brdffit report build/cc_ibiza_sunset.fit.json --out build/cc_ibiza_sunset.report.html
echo "result document: build/cc_ibiza_sunset.fit.json; pictures of every fit: build/cc_ibiza_sunset.report.html"
((python_module)) && echo "Python: PYTHONPATH=build/python python3 (import brdffit; docs/library.md)"
exit 0
