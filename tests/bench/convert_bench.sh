#!/usr/bin/env bash
# The end-to-end convert benchmark (docs/performance.md, "redpost convert, end to end" and
# "Threads"): generates 5-axis APT rasters of 100 000 and 1 000 000 poses and converts them on
# the 9-joint cell with the whole-path plan (on every core with --threads 0, then on one thread,
# the default) and with --plan local, printing wall time, CPU time (user + system), poses/s and peak RSS of each
# whole process (GNU time). In the same run, the KDL pinv_nso tracking loop over 100 500 poses
# of the same kind of raster (tests/bench/bench_tracker.cpp), and how many times the 100 000-pose
# convert fits in it (issue 32's target: at least 20x). Memory must not grow with the path.
#
# Usage: tests/bench/convert_bench.sh [BUILD_DIR] [SIZES]   (default: build, "100000 1000000")
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
sizes=${2:-"100000 1000000"}
redpost=$build/plugin/redpost
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"

kdl_ms=""
if [[ -x $build/tests/bench/redpost_bench_tracker ]]; then
  "$build/tests/bench/redpost_bench_tracker" --benchmark_filter='^BM_kdl_pinv_nso/' \
    --benchmark_format=json >"$work/kdl.json" 2>/dev/null
  kdl_ms=$(python3 -c 'import json, sys
b = [x for x in json.load(open(sys.argv[1]))["benchmarks"] if x["name"].startswith("BM_kdl_pinv_nso/")]
print("%.1f" % b[0]["real_time"])' "$work/kdl.json")
  echo "KDL pinv_nso loop, 100 500 poses: $kdl_ms ms (Google Benchmark, one thread)"
else
  echo "KDL loop: $build/tests/bench/redpost_bench_tracker not built (-DREDPOST_BENCHMARKS=ON)"
fi

for n in $sizes; do
  python3 "$top/tests/bench/make_raster_apt.py" "$n" "$work/raster_$n.apt"
  for run in "global --threads 0" "global" "local"; do
    read -r plan threads <<<"$run"
    rm -rf "$work/out" && mkdir -p "$work/out"
    # shellcheck disable=SC2086  # $threads is "" or "--threads 0"
    /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$redpost" convert "$work/raster_$n.apt" \
      --cell "$cell" -o "$work/out" --name RASTER --plan "$plan" $threads -q 2>/dev/null
    read -r wall user sys kib <"$work/time"
    size=$(du -sk "$work/out" | cut -f1)
    awk -v n="$n" -v r="$run" -v w="$wall" -v u="$user" -v s="$sys" -v k="$kib" -v o="$size" \
      -v kdl="$kdl_ms" 'BEGIN {
        printf "%8d poses, %-18s: %6.2f s wall, %6.2f s CPU, %8.0f poses/s, peak RSS %5.1f MB, output %6.1f MB",
               n, r, w, u + s, n / w, k / 1024, o / 1024
        if (n == 100000 && kdl != "" && r == "global --threads 0")
          printf ", KDL loop / this %.1fx", kdl / 1000 / w
        printf "\n" }'
  done
  rm -f "$work/raster_$n.apt"
done
