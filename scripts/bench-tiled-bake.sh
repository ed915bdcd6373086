#!/usr/bin/env bash
# The tiled bake's cost per texel-azimuth against the in-memory bake's, as
# whole processes in one run (docs/performance.md, "Baking"): an fBm DEM made
# on demand, baked in memory and in tiles with the far field (no
# --max-distance), the two alternated ROUNDS times. Prints each run's CPU time
# (user + system) and peak memory, then the medians, the nanoseconds of CPU
# per texel-azimuth and the tiled/in-memory ratio.
#   scripts/bench-tiled-bake.sh [SIZE] [TILE] [ROUNDS]   default 4096 2048 3
# Environment: AZIMUTHS (32), WORK (scratch, default /tmp/aal-bench-tiled),
# AAL_BUILD_DIR (build), REFERENCE_SIZE (the in-memory bake's DEM, default
# SIZE: e.g. 1024 to set a 16384² tiled bake against a 1024² in-memory one),
# LOW_MEMORY=1 (the tiled bake reads the DEM in windows, --low-memory).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
size=${1:-4096}
tile=${2:-2048}
rounds=${3:-3}
azimuths=${AZIMUTHS:-32}
work=${WORK:-/tmp/aal-bench-tiled}
bin=${AAL_BUILD_DIR:-$root/build}/bin
[ -x "$bin/aal-bake" ] || { echo "bench-tiled-bake: no $bin/aal-bake (build first)" >&2; exit 2; }
command -v /usr/bin/time >/dev/null || sudo apt-get install -y -qq time
mkdir -p "$work"
reference=${REFERENCE_SIZE:-$size}
for n in "$size" "$reference"; do
  [ -f "$work/fbm-$n.tif" ] ||
    "$bin/aal-synth" -o "$work/fbm-$n.tif" --size "$n" --cell-size 30 --seed 1 >/dev/null
done

run() {  # KIND: prints "KIND CPU-SECONDS PEAK-KB"
  rm -rf "$work/tiles" "$work/map.exr"
  local dem="$work/fbm-$reference.tif" target=("$work/map.exr")
  if [ "$1" = tiled ]; then
    dem="$work/fbm-$size.tif"
    target=("$work/tiles" --tile-size "$tile")
    [ "${LOW_MEMORY:-0}" = 1 ] && target+=(--low-memory)
  fi
  /usr/bin/time -f "$1 %U %S %M" -o "$work/time.txt" \
    "$bin/aal-bake" "$dem" -o "${target[@]}" --azimuths "$azimuths" -q
  awk '{printf "%s %.2f %d\n", $1, $2 + $3, $4}' "$work/time.txt"
}

echo "DEM ${size}² in tiles of $tile against ${reference}² in memory, $azimuths azimuths, $rounds rounds"
results=()
for ((r = 1; r <= rounds; r++)); do
  for kind in in-memory tiled; do
    line=$(run "$kind")
    echo "round $r: $line (CPU s, peak kB)"
    results+=("$line")
  done
done
printf '%s\n' "${results[@]}" | awk -v n="$size" -v r="$reference" -v a="$azimuths" '
  { cpu[$1] = cpu[$1] " " $2 }
  END {
    for (k in cpu) {
      m = split(substr(cpu[k], 2), v, " ")
      for (i = 1; i <= m; ++i) for (j = i + 1; j <= m; ++j) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
      med[k] = v[int((m + 1) / 2)]
      side[k] = (k == "tiled") ? n : r
      ns[k] = med[k] * 1e9 / (side[k] * side[k] * a)
      printf "%-9s median CPU %.2f s, %.1f ns per texel-azimuth\n", k, med[k], ns[k]
    }
    printf "tiled / in-memory, per texel-azimuth: %.2f\n", ns["tiled"] / ns["in-memory"]
  }'
