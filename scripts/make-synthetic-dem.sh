#!/usr/bin/env bash
# Writes a synthetic DEM (float32 GeoTIFF, local projected metres) of any size
# on demand, so that large test DEMs are never committed. Builds aal-synth
# first (into build/, or $AAL_BUILD_DIR).
#   scripts/make-synthetic-dem.sh OUT.tif SIZE [aal-synth options]
#   e.g. scripts/make-synthetic-dem.sh out/ridges-8k.tif 8192 --seed 7 --ridged --cell-size 10
# Same size, seed and options give the same heights on every machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -lt 2 ]; then
  echo "usage: $0 OUT.tif SIZE [--seed S] [--cell-size M] [--ridged] [--amplitude M]" \
    "[--feature-size TEXELS] [--octaves N]" >&2
  exit 2
fi
out=$1
size=$2
shift 2
"$root/scripts/build.sh" --target aal-synth >/dev/null
mkdir -p "$(dirname "$out")"
"${AAL_BUILD_DIR:-$root/build}/bin/aal-synth" -o "$out" --size "$size" "$@"
