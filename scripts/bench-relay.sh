#!/usr/bin/env bash
# The horizon mode's re-lays under a moving sun in aal-view (docs/rendering.md,
# "Where the horizons lie"; docs/performance.md): an fBm DEM of
# AAL_BENCH_RELAY_SIZE^2 texels (default 4096, made with aal-synth and baked
# with AAL_BENCH_RELAY_DIRECTIONS horizon directions, default 16 as aal-bake
# and the viewer's own bake keep them, on first use into build/bench-data/,
# never committed) drawn in the horizon mode at 1280x720 under Xvfb while the
# sun turns 1 degree of azimuth per frame over 90 degrees (91 frames, 12
# degrees up, so four or five of 16 stored directions are passed). aal-view
# --stats prints each run's median and longest frame; a re-lay done in one
# frame shows as max/median far above 1.
#
#   scripts/bench-relay.sh [ROUNDS]        (default 3)
#
# AAL_BEFORE_BIN=DIR also runs DIR/aal-view (another build, e.g. of the
# commit before the change) alternated round by round with this build's, so
# that load from other processes hits both alike, and prints both.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rounds=${1:-3}
size=${AAL_BENCH_RELAY_SIZE:-4096}
directions=${AAL_BENCH_RELAY_DIRECTIONS:-16}
build=${AAL_BUILD_DIR:-$root/build}
bin=$build/bin
data=$build/bench-data
mkdir -p "$data"
for tool in aal-view aal-synth aal-bake; do
  [ -x "$bin/$tool" ] || { echo "bench-relay: $bin/$tool missing (build it)" >&2; exit 1; }
done

dem=$data/fbm-$size.tif
if [ ! -f "$dem" ]; then
  echo "bench-relay: making a ${size}^2 fBm DEM (once)" >&2
  "$bin/aal-synth" -o "$dem" --size "$size" >/dev/null
fi
if [ ! -f "$data/fbm-$size-relay-h$directions.bin" ]; then
  echo "bench-relay: baking its aperture map and $directions horizon directions (once)" >&2
  "$bin/aal-bake" "$dem" -o "$data/fbm-$size-relay-a$directions.exr" --azimuths "$directions" \
    --horizons "$data/fbm-$size-relay-h$directions.bin.tmp" --horizon-directions "$directions" \
    --horizon-bits 8 -q
  mv "$data/fbm-$size-relay-h$directions.bin.tmp" "$data/fbm-$size-relay-h$directions.bin"
fi

# relayRun AAL_VIEW: aal-view --stats's output of one sweep.
relayRun() {
  xvfb-run -a -s "-screen 0 1280x720x24" "$1" "$dem" \
    --aperture "$data/fbm-$size-relay-a$directions.exr" \
    --horizons "$data/fbm-$size-relay-h$directions.bin" --mode horizon --size 1280x720 \
    --sun-azimuth 200 --sun-elevation 12 --sun-sweep 1 --frames 91 --no-vsync \
    --no-obscurance --target-fps 0 --stats 2>/dev/null
}

cases=("$bin/aal-view")
names=("this build")
if [ -n "${AAL_BEFORE_BIN:-}" ]; then
  cases=("$AAL_BEFORE_BIN/aal-view" "${cases[@]}")
  names=("before (${AAL_BEFORE_BIN})" "${names[@]}")
fi
results=$(mktemp)
trap 'rm -f "$results"' EXIT
for round in $(seq "$rounds"); do
  for i in "${!cases[@]}"; do
    out=$(relayRun "${cases[$i]}")
    line=$(awk '/^frames ms/{print $4, $6}' <<<"$out" | tr -d ',')
    relays=$(awk '/^horizons/{print $3}' <<<"$out")
    [ -n "$line" ] || { echo "bench-relay: aal-view failed for ${names[$i]}" >&2; exit 1; }
    echo "$i $line $relays" >>"$results"
    read -r median max <<<"$line"
    printf 'round %d  %-40s median %7.1f ms  max %7.1f ms  max/median %5.2f  re-lays %s\n' \
      "$round" "${names[$i]}" "$median" "$max" "$(awk -v a="$max" -v b="$median" \
      'BEGIN{print a / b}')" "$relays" >&2
  done
done

median() { sort -g | awk '{v[NR]=$1} END{print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}'; }
echo
echo "aal-view, horizon mode, ${size}^2 fBm ($directions directions), 1280x720," \
  "sun 12 degrees up turning 1 degree a frame" \
  "over 90 degrees (90 frames counted), $rounds rounds (medians over rounds)"
printf '%-40s %10s %10s %11s\n' case "median ms" "max ms" "max/median"
for i in "${!cases[@]}"; do
  med=$(awk -v i="$i" '$1 == i {print $2}' "$results" | median)
  max=$(awk -v i="$i" '$1 == i {print $3}' "$results" | median)
  ratio=$(awk -v i="$i" '$1 == i {print $3 / $2}' "$results" | median)
  printf '%-40s %10.1f %10.1f %11.2f\n' "${names[$i]}" "$med" "$max" "$ratio"
done
