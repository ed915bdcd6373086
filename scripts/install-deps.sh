#!/usr/bin/env bash
# Installs every Debian 12 package needed to build, test and run aperture.
# Idempotent and non-interactive: packages already present are skipped, so a
# configured machine runs this in well under a second.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config clang-format
  # Vulkan: headers/loader, GLSL compiler, CPU driver (lavapipe), validation
  libvulkan-dev glslang-tools glslang-dev spirv-tools
  mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  # windowing and UI
  libglfw3-dev libimgui-dev libstb-dev xvfb xauth
  # fonts for text in plots (OpenImageIO render_text)
  fonts-dejavu-core
  # math, images, geodesy, geodata (GDAL reads every DEM; gdal-bin for
  # scripts/bench-io.sh's comparison with gdalinfo)
  libglm-dev libopenimageio-dev openimageio-tools libgeographiclib-dev
  libgdal-dev gdal-bin
  # aperture maps (EXR) without OpenImageIO
  libopenexr-dev libimath-dev
  # the aperture maps' pixel checksum (XXH64)
  libxxhash-dev
  # parallelism, command line, tests, benchmarks
  libtbb-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
  # aal-bake-mpi, the tiled bake across MPI ranks (-DAAL_MPI=ON, which
  # scripts/build.sh turns on)
  libopenmpi-dev openmpi-bin
  # the Python module (python/) and its tests
  python3-dev python3-numpy pybind11-dev python3-pytest python3-rasterio
  # the QGIS Processing plugin (python/qgis/) and its headless test
  python3-qgis qgis-providers
  # the .deb (cpack -G DEB: Depends from dpkg-shlibdeps) and its check;
  # the tools' manual pages (help2man)
  dpkg-dev lintian help2man
  # fuzzing the DEM parsers (scripts/fuzz.sh): clang with libFuzzer
  clang libclang-rt-14-dev
  # SAGA's Topographic Openness and GRASS's r.horizon, which
  # AalBakeOpenness.AgreesWithSaga and SkyViewFactorAgreesWithGrassRHorizon
  # compare aal-bake's outputs with (skipped without saga_cmd or grass)
  saga grass-core
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo="sudo"
  else
    echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
