#!/usr/bin/env bash
# Whether aal-bake's sky-view factor agrees with SAGA's and GRASS's on the same
# DEMs, directions and radius (docs/baking.md, "Sky-view factor against SAGA
# and GRASS"): 256² of jacksboro on a square 90 m grid (16 directions, 1800 m)
# and a 1024² fBm of 30 m cells (32 directions, 3000 m). Per tool: the mean,
# 95th percentile and largest |difference|, the signed mean (ours - theirs)
# and the correlation, over the texels at least the radius from every edge.
#   scripts/bench-svf-agreement.sh [WORK]     default /tmp/aal-svf-agreement
# Installs saga and grass-core when missing; needs python3-rasterio.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${AAL_BUILD_DIR:-$root/build}/bin
work=${1:-/tmp/aal-svf-agreement}
[ -x "$bin/aal-bake" ] || { echo "bench-svf-agreement: no $bin/aal-bake (build first)" >&2; exit 2; }
for p in saga grass-core; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
    sudo apt-get install -y -qq "$p"
done
mkdir -p "$work"
cd "$work"

# The DEMs: jacksboro's crop as the suite's SAGA tests place it, the fBm as aal-synth makes it.
/usr/bin/python3 - "$root/heightmaps/jacksboro_fault_dem.tif" <<'PY'
import sys, rasterio
from rasterio.transform import from_origin
z = rasterio.open(sys.argv[1]).read(1).astype("float32")[:256, :256]
with rasterio.open("jacksboro.tif", "w", driver="GTiff", width=256, height=256, count=1,
                   dtype="float32", crs="EPSG:32614",
                   transform=from_origin(500000, 4000000, 90, 90)) as out:
    out.write(z, 1)
PY
[ -f fbm.tif ] || "$bin/aal-synth" -o fbm.tif --size 1024 --cell-size 30 --seed 1 >/dev/null
gdal_edit.py -a_srs EPSG:32614 fbm.tif 2>/dev/null || true  # GRASS needs a CRS it knows

echo "| DEM | directions, radius | against | mean \|Δ\| | p95 | max | signed mean | correlation |"
echo "|---|---|---|---|---|---|---|---|"
for case in "jacksboro 16 1800 20" "fbm 32 3000 100"; do
  read -r dem n radius margin <<<"$case"
  step=$(awk -v n="$n" 'BEGIN { print 360 / n }')  # 22.5, 11.25: GRASS names its maps by it
  "$bin/aal-bake" "$dem.tif" -o "$dem.exr" --azimuths "$n" --max-distance "$radius" \
    --svf "$dem-aal.tif" -q
  saga_cmd ta_lighting 3 -DEM "$dem.tif" -VISIBLE "$dem-saga-visible.tif" \
    -SVF "$dem-saga-svf.tif" -RADIUS "$radius" -NDIRS "$n" -METHOD 0 >/dev/null 2>&1
  rm -rf "grass-$dem"
  grass -c "$dem.tif" "$work/grass-$dem" -e >/dev/null 2>&1
  # GRASS: r.horizon's angles (degrees, counter-clockwise from east) to
  # 1 - mean sin(max(h, 0)), the same definition.
  grass "$work/grass-$dem/PERMANENT" --exec bash -c "
    r.in.gdal input=$dem.tif output=dem --q && g.region raster=dem &&
    r.horizon -d elevation=dem step=$step maxdistance=$radius output=hor --q &&
    terms=\$(g.list raster pattern='hor_*' separator=' ' | sed 's/\([^ ]*\)/sin(max(\1,0))/g; s/ /+/g') &&
    r.mapcalc expression=\"svf = 1.0 - (\$terms) / $n\" --q &&
    r.out.gdal input=svf output=$work/$dem-grass.tif type=Float64 -c --q" >/dev/null 2>&1
  /usr/bin/python3 - "$dem" "$n" "$radius" "$margin" <<'PY'
import sys, numpy as np, rasterio
dem, n, radius, m = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
ours = rasterio.open(f"{dem}-aal.tif").read(1).astype(float)[m:-m, m:-m]
for name, path, scale in (("SAGA Visible Sky / 100", f"{dem}-saga-visible.tif", 0.01),
                          ("SAGA Sky View Factor", f"{dem}-saga-svf.tif", 1.0),
                          ("GRASS r.horizon", f"{dem}-grass.tif", 1.0)):
    theirs = rasterio.open(path).read(1).astype(float)[m:-m, m:-m] * scale
    ok = np.isfinite(ours) & np.isfinite(theirs)
    d = ours[ok] - theirs[ok]
    a = np.abs(d)
    print(f"| {dem} | {n}, {radius} m | {name} | {a.mean():.4f} | {np.percentile(a, 95):.4f} | "
          f"{a.max():.4f} | {d.mean():+.4f} | {np.corrcoef(ours[ok], theirs[ok])[0, 1]:.4f} |")
PY
done
