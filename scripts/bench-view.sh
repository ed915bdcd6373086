#!/usr/bin/env bash
# The viewer's frame rate against a yardstick, in one run: vkcube
# and aal-view at 1280x720 under the same Xvfb screen on this machine's
# Vulkan driver (lavapipe here), alternated round by round so that load from
# other processes hits every case alike. Prints per case the median frame
# time, frames per second and the ratio to vkcube's frame time measured in
# the same round (median over rounds), with the targets (docs/viewer.md):
# without obscurances at most 4x vkcube's frame, with them at most 8x.
#
#   scripts/bench-view.sh [ROUNDS]          (default 3)
#
# Cases: the shipped DEM (jacksboro, 403 x 344) and an fBm DEM of
# AAL_BENCH_FBM_SIZE^2 texels (default 8192, made with aal-synth and baked at
# 4 azimuths on first use into build/bench-data/; the map's content does not
# change the frame time), each framed (the start view) and in a low flight
# (a camera path ~1 km above the ground looking ahead and down), with and
# without the obscurance passes, at full resolution (--target-fps 0); the
# flights once more with the dynamic resolution at 30 fps. Frame times are
# aal-view --stats's mean wall time per frame over BENCH_FRAMES frames
# (default 40; the first one's set-up excluded): drawing, presenting, the
# panel. vkcube's is (T(360 frames) - T(60 frames)) / 300 from two runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rounds=${1:-3}
frames=${BENCH_FRAMES:-40}
fbmSize=${AAL_BENCH_FBM_SIZE:-8192}
build=${AAL_BUILD_DIR:-$root/build}
export AAL_BUILD_DIR=$build

"$root/scripts/build.sh" --target aal-view aal-synth aal-bake >/dev/null
command -v vkcube >/dev/null || { echo "bench-view: vkcube missing (vulkan-tools)" >&2; exit 1; }
bin=$build/bin
data=$build/bench-data
mkdir -p "$data"

jacksboro=$root/heightmaps/jacksboro_fault_dem.tif
fbm=$data/fbm-$fbmSize.tif
if [ ! -f "$data/jacksboro-aperture.exr" ]; then
  "$bin/aal-bake" "$jacksboro" -o "$data/jacksboro-aperture.exr" -q
fi
if [ ! -f "$fbm" ]; then
  echo "bench-view: making a ${fbmSize}^2 fBm DEM and its aperture map (once)" >&2
  "$bin/aal-synth" -o "$fbm" --size "$fbmSize" >/dev/null
fi
if [ ! -f "$data/fbm-$fbmSize-aperture.exr" ]; then
  "$bin/aal-bake" "$fbm" -o "$data/fbm-$fbmSize-aperture.exr" --azimuths 4 -q
fi
# Flights ~1 km above the ground looking ahead and down (docs/performance.md).
printf '0 -12000 -12000 1800 -9000 -9000 1200\n1 8000 8000 1800 11000 11000 1200\n' \
  >"$data/flight-jacksboro.txt"
# Over the fBm DEM (30 m cells), from 24 km inside its south-west corner
# diagonally to 56 km short of the north-east one (8192^2: -98.9 -> 66.9 km).
from=$((24000 - fbmSize * 15))
to=$((fbmSize * 15 - 56000))
printf '0 %d %d 1500 %d %d 900\n1 %d %d 1500 %d %d 900\n' "$from" "$from" $((from + 3000)) \
  $((from + 3000)) "$to" "$to" $((to + 3000)) $((to + 3000)) >"$data/flight-fbm.txt"

screen="-screen 0 1280x720x24"
now() { date +%s.%N; }

vkcubeMs() {
  local t0 t1 t2
  t0=$(now)
  xvfb-run -a -s "$screen" vkcube --width 1280 --height 720 --c 60 --present_mode 1 >/dev/null 2>&1
  t1=$(now)
  xvfb-run -a -s "$screen" vkcube --width 1280 --height 720 --c 360 --present_mode 1 >/dev/null 2>&1
  t2=$(now)
  awk -v a="$t0" -v b="$t1" -v c="$t2" 'BEGIN {print ((c - b) - (b - a)) * 1000 / 300}'
}

# viewMs DEM APERTURE [aal-view options...]: mean ms per frame.
viewMs() {
  local dem=$1 aperture=$2
  shift 2
  xvfb-run -a -s "$screen" "$bin/aal-view" "$dem" --aperture "$aperture" --size 1280x720 \
    --frames "$frames" --no-vsync --stats "$@" 2>/dev/null | awk '/^frame /{print $2}'
}

names=(
  "jacksboro framed, no obscurance" "jacksboro flight, no obscurance"
  "fbm framed, no obscurance" "fbm flight, no obscurance"
  "jacksboro framed, obscurance" "jacksboro flight, obscurance"
  "fbm framed, obscurance" "fbm flight, obscurance"
  "jacksboro flight, no obscurance, dynamic 30 fps" "fbm flight, no obscurance, dynamic 30 fps"
)
runCase() {
  case $1 in
  0) viewMs "$jacksboro" "$data/jacksboro-aperture.exr" --no-obscurance --target-fps 0 ;;
  1) viewMs "$jacksboro" "$data/jacksboro-aperture.exr" --no-obscurance --target-fps 0 \
       --camera-path "$data/flight-jacksboro.txt" ;;
  2) viewMs "$fbm" "$data/fbm-$fbmSize-aperture.exr" --no-obscurance --target-fps 0 ;;
  3) viewMs "$fbm" "$data/fbm-$fbmSize-aperture.exr" --no-obscurance --target-fps 0 \
       --camera-path "$data/flight-fbm.txt" ;;
  4) viewMs "$jacksboro" "$data/jacksboro-aperture.exr" --target-fps 0 ;;
  5) viewMs "$jacksboro" "$data/jacksboro-aperture.exr" --target-fps 0 \
       --camera-path "$data/flight-jacksboro.txt" ;;
  6) viewMs "$fbm" "$data/fbm-$fbmSize-aperture.exr" --target-fps 0 ;;
  7) viewMs "$fbm" "$data/fbm-$fbmSize-aperture.exr" --target-fps 0 \
       --camera-path "$data/flight-fbm.txt" ;;
  8) viewMs "$jacksboro" "$data/jacksboro-aperture.exr" --no-obscurance --target-fps 30 \
       --camera-path "$data/flight-jacksboro.txt" ;;
  9) viewMs "$fbm" "$data/fbm-$fbmSize-aperture.exr" --no-obscurance --target-fps 30 \
       --camera-path "$data/flight-fbm.txt" ;;
  esac
}

results=$(mktemp)
trap 'rm -f "$results"' EXIT
for round in $(seq "$rounds"); do
  cube=$(vkcubeMs)
  echo "round $round: vkcube $(printf '%.1f' "$cube") ms" >&2
  for i in "${!names[@]}"; do
    ms=$(runCase "$i")
    [ -n "$ms" ] || { echo "bench-view: aal-view failed for ${names[$i]}" >&2; exit 1; }
    echo "$i $ms $cube" >>"$results"
    printf '  %-48s %7.1f ms\n' "${names[$i]}" "$ms" >&2
  done
done

median() { sort -g | awk '{v[NR]=$1} END{print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}'; }
cubeMedian=$(awk '{print $3}' "$results" | sort -u | median)
echo
echo "aal-view at 1280x720 on $(vulkaninfo 2>/dev/null | awk -F'= ' '/deviceName/{print $2; exit}'), $rounds rounds"
printf 'vkcube: %.1f ms per frame (median)\n\n' "$cubeMedian"
printf '%-48s %9s %7s %9s %7s\n' case "ms" fps "x vkcube" target
for i in "${!names[@]}"; do
  ms=$(awk -v i="$i" '$1 == i {print $2}' "$results" | median)
  ratio=$(awk -v i="$i" '$1 == i {print $2 / $3}' "$results" | median)
  target=4
  case ${names[$i]} in *", obscurance"*) target=8 ;; esac
  printf '%-48s %9.1f %7.1f %9.2f %7s\n' "${names[$i]}" "$ms" \
    "$(awk -v ms="$ms" 'BEGIN {print 1000 / ms}')" "$ratio" "<= $target"
done
