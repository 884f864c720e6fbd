#!/usr/bin/env bash
# Installs the Debian packages brdffit builds, tests and runs with. Safe to run twice: when every
# package is already there it only checks (no apt-get update, no network).
set -euo pipefail
packages=(
  cmake g++ make ninja-build pkg-config xz-utils clang-format
  libceres-dev libeigen3-dev libopenimageio-dev
  # Only the OpenCV modules brdffit uses (cmake/brdffitOpenCV.cmake finds them without OpenCV's
  # CMake package): libopencv-dev would add every other module with VTK, Qt, ...
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-videoio-dev libopencv-photo-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libgtest-dev libssl-dev liblzma-dev zlib1g-dev
  openimageio-tools  # OpenImageIO's CMake package refers to its tools (iconvert, ...)
  libxml2-utils      # xmllint checks exported MaterialX and Mitsuba files in the tests
  libopenmpi-dev openmpi-bin  # brdffit-mpi: one batch over the ranks of an MPI job (mpirun)
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib  # the Python module, its tests, examples/
)
# node and npm run the Khronos glTF-Validator (below), which checks exported glTF files in the
# tests. Debian's packages unless both commands are there already (another node distribution,
# such as NodeSource's, bundles npm and conflicts with Debian's npm package).
if ! command -v node > /dev/null || ! command -v npm > /dev/null; then packages+=(nodejs npm); fi
[[ "${BRDFFIT_WITH_CHROMIUM:-0}" == 1 ]] && packages+=(chromium)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# npm packages, pinned, into .deps/npm of this checkout: the Khronos glTF-Validator
# (tests/tools/validate_gltf.js) and three.js, the renderer that draws exported glTF in headless
# Chromium (tests/tools/render_gltf_three.js; its shading departures from the glTF BRDF are
# written down in tests/test_gltf_renderer.cc, so a new version is a reviewed change); and
# @needle-tools/materialx, MaterialX 1.39.4 built for the web, whose bundled standard library
# (bin/JsMaterialXGenShader.data.txt) holds the ND_open_pbr_surface_surfaceshader nodedef the
# exported .mtlx files are checked against (tests/test_export.cc). Three.js comes first: it is
# that package's peer dependency.
npm_prefix="$(cd "$(dirname "$0")/.." && pwd)/.deps/npm"
for package in gltf-validator@2.0.0-dev.3.10 three@0.187.0 @needle-tools/materialx@1.4.6; do
  name="${package%@*}" version="${package##*@}"
  if ! grep -q "\"version\": \"$version\"" "$npm_prefix/node_modules/$name/package.json" 2>/dev/null; then
    echo "install-deps: installing $package (npm) into $npm_prefix"
    npm install --prefix "$npm_prefix" --no-audit --no-fund --loglevel=error "$package"
  fi
done
