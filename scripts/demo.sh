#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine: installs what is missing,
# builds, and writes the results to out/ (or the folder given as $1).
# For now: the spherical-cap error table and plot (exact vs Oat's approximation).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/out}
mkdir -p "$out"

"$root/scripts/build.sh" --target aal-caps
bin=${AAL_BUILD_DIR:-$root/build}/bin

echo "== Spherical-cap intersection: exact vs Oat's approximation"
"$bin/aal-caps" --table "$out/cap-error.csv" --plot "$out/cap-error.png"
echo
echo "Results in $out:"
echo "  $out/cap-error.csv  error table over (r0, r1, d)"
echo "  $out/cap-error.png  error plot"
