#!/usr/bin/env bash
# The cost of the deflection model (docs/performance.md, issue 20): the 5-axis raster of
# convert_bench.sh (100 000 poses) and the shipped examples converted on the 9-joint cell plain,
# with --predict-deflection and with --compensate; wall time (best of 3), peak RSS, and the ratio
# to the plain convert. The target: --compensate at most 3 x a plain convert.
#
# Usage: tests/bench/deflection_bench.sh [BUILD_DIR]   (default: build)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
redpost=$build/plugin/redpost
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
python3 "$top/tests/bench/make_raster_apt.py" 100000 "$work/raster.apt"

# best of 3: "seconds peak_kib"
best() {
  local input=$1 out=$2
  shift 2
  local best_s="" best_k=0
  for _ in 1 2 3; do
    rm -rf "$out" && mkdir -p "$out"
    /usr/bin/time -f "%e %M" -o "$work/t" "$redpost" convert "$input" --cell "$cell" -o "$out" \
      --name P -q "$@" 2>/dev/null
    read -r s k <"$work/t"
    if [[ -z "$best_s" ]] || awk -v a="$s" -v b="$best_s" 'BEGIN { exit !(a < b) }'; then
      best_s=$s
      best_k=$k
    fi
  done
  echo "$best_s $best_k"
}

for input in "$work/raster.apt" "$top/examples/cl/long_pass.apt" "$top/examples/cl/surface_5axis.cls"; do
  name=$(basename "$input")
  read -r s0 k0 < <(best "$input" "$work/plain")
  read -r s1 k1 < <(best "$input" "$work/predict" --predict-deflection)
  read -r s2 k2 < <(best "$input" "$work/comp" --compensate)
  poses=$(cat "$work"/comp/P*.src | grep -c '^LIN\|^PTP' || true)
  awk -v n="$name" -v s0="$s0" -v s1="$s1" -v s2="$s2" -v k0="$k0" -v k2="$k2" -v p="$poses" 'BEGIN {
    printf "%-18s plain %6.2f s | predict %6.2f s (%.2f x) | compensate %6.2f s (%.2f x) | peak RSS %.1f -> %.1f MB | %d motions\n",
           n, s0, s1, s1 / s0, s2, s2 / s0, k0 / 1024, k2 / 1024, p }'
done
