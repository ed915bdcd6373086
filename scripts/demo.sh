#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine: installs what is missing,
# builds, bakes the shipped DEM (heightmaps/jacksboro_fault_dem.tif) and
# renders it lit by the sun and the sky through a summer day, plus a
# shaded-relief GeoTIFF, a framed block on a solid base, a day's time-lapse
# and a fly-through (image sequences, MP4s when ffmpeg is installed), an
# approximate-vs-exact pair, every mode against the ray-traced reference and
# the cap error table. Results go to out/ (or the folder given as $1).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/out}
dem=${DEM:-$root/heightmaps/jacksboro_fault_dem.tif}
size=${SIZE:-1280x720}
mkdir -p "$out"

"$root/scripts/build.sh" --target aal-bake aal-render aal-caps aal-info aal-relief
bin=${AAL_BUILD_DIR:-$root/build}/bin

echo "== DEM"
"$bin/aal-info" "$dem"

echo
echo "== Baking the aperture map"
"$bin/aal-bake" "$dem" -o "$out/aperture.exr" --svf "$out/sky-view-factor.tif"

echo
echo "== Shaded-relief map (a GeoTIFF placed like the DEM, and a PNG preview)"
"$bin/aal-relief" "$dem" --aperture "$out/aperture.exr" --palette hypsometric \
  -o "$out/relief.tif"
gdal_translate -q -of PNG "$out/relief.tif" "$out/relief.png"
echo "  $out/relief.tif, $out/relief.png"

echo
echo "== Rendering a summer day (UTC times; the DEM is at 84 W, local noon ~17:40 UTC)"
day=${DAY:-2024-06-21}
for time in 10:45 12:00 14:00 17:40 21:30 23:00 01:15; do
  date=$day
  [ "$time" = 01:15 ] && date=$(date -u -d "$day + 1 day" +%F)
  name="day-${date}T${time/:/}Z.png"
  "$bin/aal-render" "$dem" --aperture "$out/aperture.exr" -o "$out/$name" --size "$size" \
    --time "${date}T${time}:00Z" -q
  echo "  $out/$name"
done

echo
echo "== A framed block: the DEM on a solid base, transparent around it"
"$bin/aal-render" "$dem" --aperture "$out/aperture.exr" -o "$out/block.png" --size "$size" \
  --time "${day}T15:00:00Z" --base 400 --background transparent -q
echo "  $out/block.png"

echo
echo "== A day as a time-lapse and a fly-through (image sequences; MP4s when ffmpeg is installed)"
mkdir -p "$out/timelapse" "$out/flight"
"$bin/aal-render" "$dem" --aperture "$out/aperture.exr" -o "$out/timelapse/day.png" \
  --size 640x360 --time-range "${day}T10:30Z" "$(date -u -d "$day + 1 day" +%F)T01:00Z" \
  --frames 30 -q
"$bin/aal-render" "$dem" --aperture "$out/aperture.exr" -o "$out/flight/flight.png" \
  --size 640x360 --time "${day}T15:00:00Z" --camera-path "$root/heightmaps/jacksboro_flight.txt" \
  --frames 60 -q
echo "  $out/timelapse/, $out/flight/"

echo
echo "== Approximate (Oat's smoothstep) vs exact cap intersection, low sun"
for mode in approx exact; do
  "$bin/aal-render" "$dem" --aperture "$out/aperture.exr" -o "$out/sun-low-$mode.png" \
    --size "$size" --sun-azimuth 250 --sun-elevation 10 --mode "$mode" -q
  echo "  $out/sun-low-$mode.png"
done

echo
echo "== Every shading mode against the CPU ray-traced reference, low sun (320x180)"
"$bin/aal-render" "$dem" --aperture "$out/aperture.exr" --compare "$out/compare" \
  --size 320x180 --sun-azimuth 250 --sun-elevation 10 -q
echo "  $out/compare/ (images, error maps, errors.csv)"

echo
echo "== Spherical-cap intersection error"
"$bin/aal-caps" --table "$out/cap-error.csv" --plot "$out/cap-error.png"

echo
echo "Results in $out"
