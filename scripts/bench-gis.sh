#!/usr/bin/env bash
# Runs the same DEM through aal-bake, SAGA GIS's Sky View Factor
# (ta_lighting 3: 32 sectors, its default 10 km radius, multi-scale and
# cell-size methods) and GRASS r.horizon (32 directions), and prints the
# times and ratios. Installs saga, grass-core and gdal-bin when missing.
#   scripts/bench-gis.sh [SIZE]      default 1024 (a synthetic fBm DEM, 30 m cells)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
size=${1:-1024}
work=${WORK:-/tmp/aal-bench-gis}
rm -rf "$work" && mkdir -p "$work"

need=()
for p in saga grass-core gdal-bin time bc; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get install -y -qq --no-install-recommends "${need[@]}"
fi
"$root/scripts/build.sh" --target aal-bake aal-synth >/dev/null
bin=${AAL_BUILD_DIR:-$root/build}/bin

dem="$work/dem.tif"
"$bin/aal-synth" -o "$dem" --size "$size" --cell-size 30 --seed 1 >/dev/null

seconds() { /usr/bin/time -f %e "$@" 2>&1 >/dev/null | tail -1; }

# The same outputs as SAGA's: the sky-view factor and the visible sky, no aperture map.
t_aal=$(seconds "$bin/aal-bake" "$dem" --svf "$work/svf.tif" --visible "$work/vis.tif" \
  --azimuths 32 -q)
# And within SAGA's radius, as a user matching its settings would.
t_aal_10k=$(seconds "$bin/aal-bake" "$dem" --svf "$work/svf_10k.tif" --visible "$work/vis_10k.tif" \
  --azimuths 32 --max-distance 10000 -q)
# And within RVT's default radius of 10 cells.
t_aal_rvt=$(seconds "$bin/aal-bake" "$dem" --svf "$work/svf_rvt.tif" --visible "$work/vis_rvt.tif" \
  --azimuths 32 --max-distance 300 -q)
t_saga_ms=$(seconds saga_cmd ta_lighting 3 -DEM "$dem" -SVF "$work/svf_ms.sdat" \
  -VISIBLE "$work/vis_ms.sdat" -NDIRS 32 -METHOD 1)
t_saga_cs=$(seconds saga_cmd ta_lighting 3 -DEM "$dem" -SVF "$work/svf_cs.sdat" \
  -VISIBLE "$work/vis_cs.sdat" -NDIRS 32 -METHOD 0)
# r.horizon needs a projected location; aal-synth writes a local metric CRS
# that GRASS cannot translate, so the grid goes into a UTM location as is (-o).
grass -c EPSG:32616 "$work/grassdb/bench" -e
t_grass=$(seconds grass "$work/grassdb/bench/PERMANENT" --exec bash -c \
  "r.in.gdal -o --quiet input='$dem' output=dem && g.region raster=dem &&
   r.horizon --quiet elevation=dem step=11.25 output=hor")

printf "%dx%d DEM, 32 directions\n" "$size" "$size"
printf "  %-34s %8s s\n" "aal-bake --svf --visible (whole DEM)" "$t_aal"
printf "  %-34s %8s s\n" "aal-bake --max-distance 10000" "$t_aal_10k"
printf "  %-34s %8s s\n" "aal-bake --max-distance 300 (10 px)" "$t_aal_rvt"
printf "  %-34s %8s s  (%.0fx aal-bake, %.0fx within 10 km)\n" "SAGA SVF multi-scale (10 km)" \
  "$t_saga_ms" "$(echo "$t_saga_ms / $t_aal" | bc -l)" "$(echo "$t_saga_ms / $t_aal_10k" | bc -l)"
printf "  %-34s %8s s  (%.0fx aal-bake)\n" "SAGA SVF cell size (10 km)" "$t_saga_cs" \
  "$(echo "$t_saga_cs / $t_aal" | bc -l)"
printf "  %-34s %8s s  (%.0fx aal-bake)\n" "GRASS r.horizon" "$t_grass" \
  "$(echo "$t_grass / $t_aal" | bc -l)"
