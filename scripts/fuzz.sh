#!/usr/bin/env bash
# Builds the libFuzzer targets at the GDAL boundary (clang, ASan + UBSan) in
# build-fuzz/ and runs each for a bounded time. Fails if any finds a crash,
# a sanitizer report, a leak, a timeout or an unexpected exception.
#   scripts/fuzz.sh [SECONDS]     seconds per target (default 20)
# The corpus grows in build-fuzz/corpus/<target>/ across runs; seeds are
# written fresh by fuzz_seeds into build-fuzz/seeds/; crashing inputs land in
# build-fuzz/artifacts/<target>/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-20}
build_dir=${AAL_FUZZ_BUILD_DIR:-$root/build-fuzz}
targets=(load_dem raster)

"$root/scripts/install-deps.sh"
if ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz: clang++ not found (install clang and libclang-rt-dev)" >&2
  exit 1
fi
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DAAL_FUZZ=ON \
  -DAAL_WERROR="${AAL_WERROR:-OFF}" -DAAL_BUILD_TESTS=OFF -DAAL_BUILD_BENCH=OFF >/dev/null
cmake --build "$build_dir" --target fuzz_seeds "${targets[@]/#/fuzz_}"

rm -rf "$build_dir/seeds"
"$build_dir/bin/fuzz_seeds" "$build_dir/seeds"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
for target in "${targets[@]}"; do
  corpus=$build_dir/corpus/$target
  artifacts=$build_dir/artifacts/$target
  mkdir -p "$corpus" "$artifacts"
  log=$build_dir/fuzz_$target.log
  echo "== fuzz_$target for ${seconds}s (log: $log)"
  if ! "$build_dir/bin/fuzz_$target" -max_total_time="$seconds" -timeout=20 \
    -rss_limit_mb=2560 -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts/" \
    "$corpus" "$build_dir/seeds/$target" >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    echo "fuzz: fuzz_$target failed; the input is in $artifacts/" >&2
    exit 1
  fi
  grep -E "^stat::(number_of_executed_units|new_units_added|peak_rss_mb)" "$log" | tr '\n' ' '
  echo
done
echo "fuzz: all targets ran ${seconds}s without findings"
