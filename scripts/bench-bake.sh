#!/usr/bin/env bash
# Times aal-bake on synthetic DEMs generated on demand (nothing is committed)
# and reports seconds, texel-azimuths per second and peak memory per texel.
#   scripts/bench-bake.sh [SIZE ...]     default: 1024 4096 16384
# Environment: AZIMUTHS (32), WORK (a scratch folder, default /tmp/aal-bench),
# MAX_DISTANCE (metres; none by default), TILE_SIZE (a tiled bake into a
# folder; needs MAX_DISTANCE). The tiled benchmark of a DEM too large for the
# in-memory bake (16 GiB of scratch for the DEM and the tiles, hours):
#   TILE_SIZE=4096 MAX_DISTANCE=1000 scripts/bench-bake.sh 32768
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(1024 4096 16384)
azimuths=${AZIMUTHS:-32}
extra=()
[ -n "${MAX_DISTANCE:-}" ] && extra+=(--max-distance "$MAX_DISTANCE")
[ -n "${TILE_SIZE:-}" ] && extra+=(--tile-size "$TILE_SIZE")
work=${WORK:-/tmp/aal-bench}
mkdir -p "$work"

"$root/scripts/build.sh" --target aal-bake aal-synth >/dev/null
bin=${AAL_BUILD_DIR:-$root/build}/bin
command -v /usr/bin/time >/dev/null || sudo apt-get install -y -qq time

[ ${#extra[@]} -gt 0 ] && echo "options: ${extra[*]}"
printf "%-7s %-9s %-10s %-22s %-14s\n" size azimuths seconds texel-azimuths/s bytes/texel
for n in "${sizes[@]}"; do
  dem="$work/fbm-$n.tif"
  [ -f "$dem" ] || "$bin/aal-synth" -o "$dem" --size "$n" --cell-size 30 --seed 1 >/dev/null
  log="$work/bake-$n.log"
  output="$work/aperture-$n.exr"
  if [ -n "${TILE_SIZE:-}" ]; then
    output="$work/aperture-$n.tiles"
    rm -rf "$output"  # a fresh bake, not a resumed one
  fi
  /usr/bin/time -v "$bin/aal-bake" "$dem" -o "$output" --azimuths "$azimuths" \
    ${extra[@]+"${extra[@]}"} 2>"$log" >/dev/null
  seconds=$(grep -oP 'in \K[0-9.]+(?= s)' "$log" | tail -1)
  rate=$(grep -oP '\(\K[0-9.e+]+(?= texel-azimuths/s)' "$log" | tail -1)
  peak_kb=$(grep -oP 'Maximum resident set size \(kbytes\): \K[0-9]+' "$log")
  bytes=$(awk -v kb="$peak_kb" -v n="$n" 'BEGIN { printf "%.1f", kb * 1024 / (n * n) }')
  printf "%-7s %-9s %-10s %-22s %-14s\n" "$n" "$azimuths" "$seconds" "$rate" "$bytes"
done
