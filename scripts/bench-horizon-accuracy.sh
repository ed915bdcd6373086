#!/usr/bin/env bash
# The horizon mode's accuracy table (docs/comparison.md, "Directional horizons for
# the sun"): `aal-render --compare` against the CPU ray tracer on the rugged
# fBm (aal-synth --size 256 --amplitude 2500 --feature-size 64) and jacksboro,
# with horizons of 8 directions of 8 bits, 16 of 8 bits and 16 of 4 bits,
# for every sun azimuth in AZ and elevation in EL. Prints one Markdown row per
# scene and sun: relative RMSE of every mode and the ratios the targets
# (docs/comparison.md) are stated in. About 4 s a sun on two cores.
#
#   scripts/bench-horizon-accuracy.sh [WORK]      default /tmp/aal-horizon-accuracy
#
# Environment: AZ (default "20 22.5 135 247.5 250 292.5 300"), EL ("3 5 8
# 12"), SCENES ("fbm jacksboro"), SUBPIXELS (4), SKY_RAYS (128),
# AAL_BUILD_DIR (build). Bakes and comparisons already in WORK are reused.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${AAL_BUILD_DIR:-$root/build}/bin
work=${1:-/tmp/aal-horizon-accuracy}
[ -x "$bin/aal-render" ] || { echo "bench-horizon-accuracy: no $bin/aal-render (build first)" >&2; exit 2; }
mkdir -p "$work"
cd "$work"

[ -f fbm.tif ] || "$bin/aal-synth" -o fbm.tif --size 256 --amplitude 2500 --feature-size 64 >/dev/null
[ -f jacksboro.tif ] || cp "$root/heightmaps/jacksboro_fault_dem.tif" jacksboro.tif
for s in ${SCENES:-fbm jacksboro}; do
  [ -f "$s-16x4.hz" ] && continue
  echo "bench-horizon-accuracy: baking $s" >&2
  "$bin/aal-bake" "$s.tif" -o "$s.exr" --horizons "$s-8x8.hz" --horizon-directions 8 \
    --horizon-bits 8 -q
  "$bin/aal-bake" "$s.tif" -o "$s-16.exr" --horizons "$s-16x8.hz" --horizon-directions 16 \
    --horizon-bits 8 -q
  "$bin/aal-bake" "$s.tif" -o "$s-16.exr" --horizons "$s-16x4.hz" --horizon-directions 16 \
    --horizon-bits 4 -q
done

echo "| scene | sun az/el | approx | exact | approx without W | baseline-lambert | baseline-ao |" \
  "horizon 8 × 8 bits | 16 × 8 bits | 16 × 4 bits | 16 × 4 / approx | 16 × 4 / lambert | 16 × 8 / approx |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for s in ${SCENES:-fbm jacksboro}; do
  for az in ${AZ:-20 22.5 135 247.5 250 292.5 300}; do
    for el in ${EL:-3 5 8 12}; do
      out=out/$s-$az-$el
      if [ ! -f "$out/errors.csv" ]; then
        "$bin/aal-render" "$s.tif" --aperture "$s.exr" --compare "$out" --size 320x180 \
          --sun-azimuth "$az" --sun-elevation "$el" --reference-sky-rays "${SKY_RAYS:-128}" \
          --reference-subpixels "${SUBPIXELS:-4}" --horizons "$s-8x8.hz" --horizons "$s-16x8.hz" \
          --horizons "$s-16x4.hz" -q >/dev/null
      fi
      # errors.csv: mode,relative_rmse,mean_relative_error; the horizon
      # modes are named horizon-STEM after their files.
      awk -F, -v scene="$s" -v sun="$az°/$el°" '
        NR > 1 { m = $1; sub(/^horizon-[^-]*-/, "h", m); e[m] = 100 * $2 }
        END {
          printf "| %s | %s | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.2f | %.2f | %.2f |\n",
            scene, sun, e["approx"], e["exact"], e["approx-without-w"], e["baseline-lambert"],
            e["baseline-ao"], e["h8x8"], e["h16x8"], e["h16x4"], e["h16x4"] / e["approx"],
            e["h16x4"] / e["baseline-lambert"], e["h16x8"] / e["approx"]
        }' "$out/errors.csv"
    done
  done
done
