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
# $redpost, $cell (the Andres cell), a $work folder removed at exit, the machine line, and
# best_of_3 INPUT OUT [options]: "seconds peak_kib" of the fastest of three runs.
source "$top/tests/bench/convert_timing.sh"
python3 "$top/tests/bench/make_raster_apt.py" 100000 "$work/raster.apt"


for input in "$work/raster.apt" "$top/examples/cl/long_pass.apt" "$top/examples/cl/surface_5axis.cls"; do
  name=$(basename "$input")
  read -r s0 k0 < <(best_of_3 "$input" "$work/plain")
  read -r s1 k1 < <(best_of_3 "$input" "$work/predict" --predict-deflection)
  read -r s2 k2 < <(best_of_3 "$input" "$work/comp" --compensate)
  poses=$(cat "$work"/comp/P*.src | grep -c '^LIN\|^PTP' || true)
  awk -v n="$name" -v s0="$s0" -v s1="$s1" -v s2="$s2" -v k0="$k0" -v k2="$k2" -v p="$poses" 'BEGIN {
    printf "%-18s plain %6.2f s | predict %6.2f s (%.2f x) | compensate %6.2f s (%.2f x) | peak RSS %.1f -> %.1f MB | %d motions\n",
           n, s0, s1, s1 / s0, s2, s2 / s0, k0 / 1024, k2 / 1024, p }'
done
