#!/usr/bin/env bash
# The horizon mode's frame cost over approx (target: at most +10 %), before
# and after a change of the renderer, in one run: bench_render's
# BM_RenderFrame (jacksboro, 1280x720, sun at 25 degrees, no obscurance) for
# approx and horizon, with horizons of 8 directions of 8 bits and of 16
# directions of 4 bits, each with this tree's renderer ("new") and with
# BASE's ("old", default: main): BASE's sources built once into
# BUILD/horizon-ab-base-SHA (bench_render and its shaders) with this tree's
# bench/render_bench.cpp, so that both report the same measures (the first
# run builds it: minutes).
#
#   scripts/bench-horizon-ab.sh [ROUNDS] [BASE]      (default 4, main)
#
# Every round runs the four cases (old/new x 8x8/16x4) in random order, each
# a process that measures approx and horizon interleaved in random order
# (--benchmark_enable_random_interleaving), REPS repetitions of each (default
# 7). Prints per process the medians of the process's CPU time per frame
# (lavapipe's threads' work; less sensitive to other processes than wall
# time) and of wall time, and the ratios horizon / approx (the machine's load
# swings between processes, less within one), then per case the median CPU
# time ratio over the rounds, with the load average before and after.
# AAL_BENCH_SUN_AZIMUTH (bench/render_bench.cpp) moves the sun: 250 (default)
# puts both directions beside it in one layer of rotation 0, 285 in two (a
# renderer with the rotated layout re-lays the horizons once for it, before
# the measured frames; one without fetches two layers).
# AAL_BENCH_SUN_ELEVATION (default 25) sets the sun's elevation.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rounds=${1:-4}
base=${2:-main}
reps=${REPS:-7}
build=${AAL_BUILD_DIR:-$root/build}

[ -d "$build" ] || { echo "bench-horizon-ab: no build folder $build" >&2; exit 2; }
git -C "$root" rev-parse --verify -q "$base^{commit}" >/dev/null ||
  { echo "bench-horizon-ab: unknown revision $base" >&2; exit 2; }
ninja -C "$build" bench_render aal_shaders >/dev/null

sha=$(git -C "$root" rev-parse --short "$base")
baseBuild=$build/horizon-ab-base-$sha
# The base's build folder inside its sources, as this tree's: with ccache's
# base_dir the compiler sees the same relative paths and hits its cache.
baseBin=$baseBuild/src/build
if [ ! -x "$baseBin/bin/bench_render" ]; then
  echo "bench-horizon-ab: building $base ($sha) into $baseBuild"
  rm -rf "$baseBuild"
  mkdir -p "$baseBuild/src"
  git -C "$root" archive "$base" | tar -x -C "$baseBuild/src"
  cp "$root/bench/render_bench.cpp" "$baseBuild/src/bench/render_bench.cpp"
  launcher=()
  command -v ccache >/dev/null &&
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  cmake -S "$baseBuild/src" -B "$baseBin" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DAAL_WERROR=OFF -DAAL_SANITIZE=OFF -DAAL_MPI=ON "${launcher[@]}" >/dev/null
  ninja -C "$baseBin" bench_render aal_shaders >/dev/null
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "bench-horizon-ab: $rounds rounds, $reps repetitions; old = $base ($sha), new = this tree;" \
  "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
results=$work/results
for ((round = 1; round <= rounds; ++round)); do
  for c in "old 8 8" "old 16 4" "new 8 8" "new 16 4"; do echo "$c"; done | shuf |
    while read -r renderer directions bits; do
      bin=$build
      [ "$renderer" = old ] && bin=$baseBin
      AAL_BENCH_HORIZON_DIRECTIONS=$directions \
        AAL_BENCH_HORIZON_BITS=$bits "$bin/bin/bench_render" \
        --benchmark_filter='BM_RenderFrame/(0|10)/' \
        --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
        --benchmark_report_aggregates_only=true 2>/dev/null |
        awk -v r="$round" -v c="$renderer ${directions}x$bits" '
          /BM_RenderFrame\/0\/.*_median/ { approx = $4; approxWall = $2 }
          /BM_RenderFrame\/10\/.*_median/ { horizon = $4; horizonWall = $2 }
          END { printf "round %d  %-10s CPU approx %6.1f ms  horizon %6.1f ms  wall %6.1f, %6.1f ms  wall ratio %.3f  ratio %.3f\n",
                       r, c, approx, horizon, approxWall, horizonWall, horizonWall / approxWall,
                       horizon / approx }'
    done | tee -a "$results"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "median horizon/approx of CPU time per frame over $rounds rounds (range):"
for c in "old 8x8" "old 16x4" "new 8x8" "new 16x4"; do
  grep -F " $c " "$results" | awk '{print $NF}' | sort -n |
    awk -v c="$c" '{ v[NR] = $1 }
      END { m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
            printf "  %-9s %.3f (%+.0f %%; %.3f .. %.3f)\n", c, m, 100 * (m - 1), v[1], v[NR] }'
done
