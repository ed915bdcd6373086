#!/usr/bin/env bash
# `cpack -G DEB` makes a package that lintian passes without errors, whose
# Depends come from dpkg-shlibdeps, which holds the tools, the image plugin,
# the libraries with their headers and package configs, and whose tools run
# from its unpacked tree.
#   debian_package_test.sh BUILD_DIR [FILE...]
# FILEs: more paths the package must hold (what this build makes: the Python
# module, the manual pages), as ./usr/...
set -euo pipefail
build=$(cd "$1" && pwd)
shift
expected=("$@")
work=$(mktemp -d /tmp/aperture-deb.XXXXXX)
trap 'rm -rf "$work"' EXIT

(cd "$build" && cpack -G DEB -B "$work" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; exit 1; }
deb=$(ls "$work"/aperture_*.deb)
echo "package: $(basename "$deb")"

depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for library in libc6 libvulkan1 libgdal32 libtbb12; do
  case "$depends" in *"$library"*) ;; *) echo "Depends lacks $library" >&2; exit 1 ;; esac
done

dpkg-deb -c "$deb" | awk '{print $6}' >"$work/files"
for file in ./usr/bin/aal-bake ./usr/bin/aal-render ./usr/bin/aal-view ./usr/bin/aal-relief \
            ./usr/lib/aperture/aal_oiio_images.so ./usr/lib/libaperture_terrain.a \
            ./usr/lib/libaperture_engine.a ./usr/include/aperture/engine/vk/buffer.h \
            ./usr/lib/cmake/aperture/apertureConfig.cmake ./usr/lib/pkgconfig/aperture.pc \
            ./usr/share/doc/aperture/copyright ./usr/share/doc/aperture/changelog.gz \
            "${expected[@]}"; do
  grep -qxF "$file" "$work/files" || { echo "the package lacks $file" >&2; exit 1; }
done

lintian --fail-on error --no-tag-display-limit "$deb" | tee "$work/lintian.log"
echo "lintian: $(grep -c '^E:' "$work/lintian.log" || true) errors," \
  "$(grep -c '^W:' "$work/lintian.log" || true) warnings"

dpkg-deb -x "$deb" "$work/root"
env -u AAL_IMAGE_PLUGIN "$work/root/usr/bin/aal-bake" --version
echo "debian_package_test: package built, lintian clean of errors, tools run"
