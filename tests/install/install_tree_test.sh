#!/usr/bin/env bash
# The installed package works on its own: `cmake --install` into a temporary
# prefix, then, with the build and source folders hidden (an empty tmpfs
# mounted over each in a private mount namespace, as if moved aside) and no
# AAL_* variable set, the installed aal-bake and aal-render bake and render
# the shipped DEM (aal-render writes a PNG through the installed image
# plugin), every tool answers --version, tests/consumer, built with
# find_package(aperture) against the prefix, bakes and renders a frame on
# lavapipe with no validation message, and the installed Python module
# imports and bakes (when the build has it).
#   install_tree_test.sh BUILD_DIR SOURCE_DIR [1: a sanitizer build]
# Exits 77 (skipped) when no mount namespace can be made (unshare).
set -euo pipefail
# A sanitizer build is not one to install: its static libraries need the
# sanitizer's runtime, which the package config does not pass on, and its
# diagnostics name the build folder's headers.
if [ "${3:-0}" = 1 ]; then
  echo "install_tree_test: skipped in a sanitizer build"
  exit 77
fi
build=$(cd "$1" && pwd)
source=$(cd "$2" && pwd)
work=$(mktemp -d /tmp/aperture-install.XXXXXX)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

if unshare --mount true 2>/dev/null; then
  hide=(unshare --mount)
elif unshare --map-root-user --mount true 2>/dev/null; then
  hide=(unshare --map-root-user --mount)
else
  echo "install_tree_test: cannot make a mount namespace (unshare); skipped" >&2
  exit 77
fi

cmake --install "$build" --prefix "$prefix" >"$work/install.log"
test -x "$prefix/bin/aal-bake" && test -x "$prefix/bin/aal-render"
ls "$prefix"/lib*/aperture/aal_oiio_images.so >/dev/null
ls "$prefix"/lib*/cmake/aperture/apertureConfig.cmake >/dev/null
ls "$prefix"/lib*/pkgconfig/aperture.pc >/dev/null
for f in metadata.txt __init__.py provider.py tools.py; do
  test -f "$prefix/share/aperture/qgis/aperture_processing/$f"
done
test -f "$prefix/include/aperture/engine/vk/buffer.h"
if [ -e "$prefix/include/buffer.h" ]; then
  echo "install_tree_test: a bare header include/buffer.h was installed" >&2
  exit 1
fi
# No path into the build or source tree is compiled into what is installed.
if grep -rlF "$build" "$prefix/bin" "$prefix"/lib*/aperture; then
  echo "install_tree_test: the installed files above name the build folder $build" >&2
  exit 1
fi

# The consumer is built before the folders are hidden (it needs the compiler
# and the prefix, nothing of the build tree).
cmake -S "$source/tests/consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; exit 1; }
cmake --build "$work/consumer" >>"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; exit 1; }
pkg=$(PKG_CONFIG_PATH=$(dirname "$prefix"/lib*/pkgconfig/aperture.pc) pkg-config --modversion aperture)
echo "pkg-config: aperture $pkg"

cp "$source/heightmaps/jacksboro_fault_dem.tif" "$work/dem.tif"
# The QGIS plugin finds the installed tools from where it is installed,
# when python3-qgis is there to import it.
qgis_python=""
if /usr/bin/python3 -c "import qgis.core" 2>/dev/null; then
  qgis_python=/usr/bin/python3
fi
# The Python module, when the build made it (python3 with numpy).
python=""
if ls "$prefix"/lib/python3/dist-packages/aperture/_aperture*.so >/dev/null 2>&1; then
  python=/usr/bin/python3
fi
cat >"$work/run.sh" <<SCRIPT
set -euo pipefail
mount -t tmpfs none "$build"
mount -t tmpfs none "$source"
test ! -e "$build/bin" && test ! -e "$source/heightmaps"
for tool in "$prefix"/bin/aal-*; do "\$tool" --version; done
cd "$work"
"$prefix/bin/aal-bake" dem.tif -o map.exr --azimuths 16 --svf svf.tif -q
"$prefix/bin/aal-render" dem.tif --aperture map.exr -o frame.png --size 96x64 --no-obscurance
"$work/consumer/aperture_consumer"
if [ -n "$python" ]; then
  PYTHONPATH="$prefix/lib/python3/dist-packages" "$python" -c "
import numpy, aperture
svf = aperture.sky_view_factor(numpy.zeros((32, 32), numpy.float32), 30.0, azimuths=8)
assert svf.shape == (32, 32) and (svf == 1).all(), svf
print('python: aperture', aperture.__version__, 'from', aperture.__file__)"
fi
if [ -n "$qgis_python" ]; then
  env -u APERTURE_BIN_DIR PATH=/usr/bin:/bin QT_QPA_PLATFORM=offscreen \
    PYTHONPATH="$prefix/share/aperture/qgis" "$qgis_python" -c "
from aperture_processing.tools import tool_path
found = tool_path('aal-bake')
assert found == '$prefix/bin/aal-bake', found
print('qgis plugin: finds', found)"
fi
SCRIPT
env $(env | sed -n 's/^\(AAL_[A-Z_]*\)=.*/-u \1/p') HOME="$work" "${hide[@]}" bash "$work/run.sh"
for f in map.exr svf.tif frame.png; do
  test -s "$work/$f" || { echo "install_tree_test: no $f" >&2; exit 1; }
done
echo "install_tree_test: the installed tools and library work without the build tree"
