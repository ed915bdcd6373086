#!/bin/bash
# Frame times on a GPU machine without our Debian packages: run from the
# repository root with a bundle made by scripts/portable-bundle.py, e.g.
#   scripts/portable-bundle.py .gpu build/bin/aal-render build/bin/bench_render
#   (copy the repository and .gpu to the GPU machine)
#   bench/gpu-frame-times.sh .gpu OUT_DIR
# Needs the GPU's Vulkan driver (NVIDIA: its ICD manifest; the ICD lives in
# libGLX_nvidia and needs glvnd's libGLX/libEGL installed). Prints per-pass
# GPU times of aal-render on jacksboro at 1280x720 and runs bench_render
# (every frame benchmark; BENCH_FILTER narrows, BENCH_REPS repeats); the
# JSON results land in OUT_DIR/bench.json.
set -u
bundle=$(cd "${1:?bundle folder}" && pwd)
out=${2:?output folder}
mkdir -p "$out"
export LD_LIBRARY_PATH=$bundle/lib
export PROJ_DATA=$bundle/share/proj GDAL_DATA=$bundle/share/gdal
if [ -z "${VK_DRIVER_FILES:-}" ]; then
  for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
    /etc/vulkan/icd.d/nvidia_icd.json; do
    [ -f "$f" ] && { export VK_DRIVER_FILES=$f; break; }
  done
fi
echo "Vulkan driver manifest: ${VK_DRIVER_FILES:-loader default}"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null
dem=heightmaps/jacksboro_fault_dem.tif
export AAL_BENCH_DEM=$dem
for mode in approx exact baseline-lambert; do
  echo "== aal-render --mode $mode"
  timeout 300 "$bundle/aal-render" "$dem" -o "$out/jacksboro-$mode.png" --mode "$mode" --stats \
    --size 1280x720 2>&1 | grep "gpu\|device\|triangles"
done
echo "== bench_render"
timeout "${BENCH_TIMEOUT:-900}" "$bundle/bench_render" --benchmark_filter="${BENCH_FILTER:-.}" \
  --benchmark_repetitions="${BENCH_REPS:-3}" --benchmark_report_aggregates_only=true \
  --benchmark_out="$out/bench.json" --benchmark_out_format=json
