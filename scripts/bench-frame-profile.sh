#!/usr/bin/env bash
# Where a frame's time goes on this machine's Vulkan driver (lavapipe here),
# at 1280x720 on the shipped DEM (docs/performance.md, "Where a frame's time
# goes"), with and without the obscurance passes:
#  1. per pass: aal-render --pass-profile (each pass submitted on its own and
#     waited for: wall-clock and the process's CPU time, medians), from the
#     middle of bench-view.sh's jacksboro flight;
#  2. the viewer's main thread along that flight: aal-view --stats (where
#     each frame's wall time went: waiting, acquiring, recording,
#     presenting, the rest of the loop);
#  3. with perf (Debian's linux-perf) where the kernel lets it sample: the
#     CPU time of the viewer's threads (the driver's workers apart from the
#     main thread) and how busy the cores were.
#
#   scripts/bench-frame-profile.sh [FRAMES]   (default 7 profiled frames)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
frames=${1:-7}
build=${AAL_BUILD_DIR:-$root/build}
export AAL_BUILD_DIR=$build
"$root/scripts/build.sh" --target aal-render aal-view aal-bake >/dev/null
bin=$build/bin
data=$build/bench-data
mkdir -p "$data"
dem=$root/heightmaps/jacksboro_fault_dem.tif
aperture=$data/jacksboro-aperture.exr
[ -f "$aperture" ] || "$bin/aal-bake" "$dem" -o "$aperture" -q
# bench-view.sh's flight over jacksboro, and its middle as one camera.
path=$data/flight-jacksboro.txt
printf '0 -12000 -12000 1800 -9000 -9000 1200\n1 8000 8000 1800 11000 11000 1200\n' >"$path"
camera=(--camera -2000,-2000,1800 --look-at 1000,1000,1200)

for obscurance in "" --no-obscurance; do
  echo "== aal-render --pass-profile $frames, 1280x720, ${obscurance:-obscurance on}"
  "$bin/aal-render" "$dem" --aperture "$aperture" --size 1280x720 -o "$data/profile.png" -q \
    "${camera[@]}" --pass-profile "$frames" $obscurance | sed -n '/^step/,$p'
done

view() {
  xvfb-run -a -s "-screen 0 1280x720x24" "$bin/aal-view" "$dem" --aperture "$aperture" \
    --size 1280x720 --frames 30 --no-vsync --stats --target-fps 0 --camera-path "$path" "$@" 2>/dev/null
}
for obscurance in "" --no-obscurance; do
  echo "== aal-view --stats, the flight, 30 frames, ${obscurance:-obscurance on}"
  view $obscurance | grep -E '^frames ms|^main thread' | sed 's/, /\n    /g'
done

if command -v perf >/dev/null && perf record -q -o /dev/null true 2>/dev/null; then
  echo "== perf: the viewer's threads over 60 frames of the flight with obscurance"
  data_file=$(mktemp)
  trap 'rm -f "$data_file"' EXIT
  xvfb-run -a -s "-screen 0 1280x720x24" perf record -q -F 999 -o "$data_file" -- \
    "$bin/aal-view" "$dem" --aperture "$aperture" --size 1280x720 --frames 60 --no-vsync \
    --target-fps 0 --camera-path "$path" >/dev/null 2>&1
  perf script -i "$data_file" -F comm,time 2>/dev/null | awk '
    { t = $2 + 0; n[$1]++; if (first == "" || t < first) first = t; if (t > last) last = t }
    END {
      wall = last - first
      for (c in n) { s = n[c] / 999; total += s; printf "  %-12s %6.2f s of CPU\n", c, s }
      printf "  wall %.2f s: the 2 cores %.0f %% busy with the viewer\n", wall, 100 * total / (2 * wall)
    }'
else
  echo "== perf: not available here (linux-perf, or perf_event_paranoid)"
fi
