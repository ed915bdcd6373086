#!/usr/bin/env bash
# Makes docs/gis.md's QGIS screenshots: QGIS (Debian's qgis package, not
# installed by install-deps.sh: only the plugin's test needs QGIS, and it runs
# headless) with the Aperture provider, under Xvfb.
#   scripts/qgis-screenshots.sh [BUILD_DIR]   (default: build)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
command -v qgis >/dev/null || { echo "qgis-screenshots: needs Debian's qgis package" >&2; exit 2; }
shots="$(mktemp -d)"
trap 'rm -rf "$shots"' EXIT
APERTURE_SOURCE="$root" APERTURE_SHOTS="$shots" APERTURE_BIN_DIR="$build/bin" \
  QT_QPA_PLATFORM=xcb xvfb-run -a -s "-screen 0 1280x800x24" \
  qgis --nologo --noversioncheck --noplugins --profiles-path "$shots/profile" \
  --code "$root/scripts/qgis-screenshots.py" || true  # QGIS 3.22 may crash as it quits
for f in qgis-processing-dialog.png qgis-openness-layer.png; do
  [ -s "$shots/$f" ] || { echo "qgis-screenshots: $f was not made" >&2; exit 1; }
  cp "$shots/$f" "$root/docs/images/$f"
done
echo "docs/images/qgis-processing-dialog.png, docs/images/qgis-openness-layer.png"
