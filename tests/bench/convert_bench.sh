#!/usr/bin/env bash
# The end-to-end convert benchmark (docs/performance.md, "redpost convert, end to end", "Threads"
# and "The pipeline"): generates 5-axis APT rasters of 100 000 and 1 000 000 poses and converts
# them on the 9-joint cell with the whole-path plan (two threads: the pipeline; one thread, the
# default; one per core) and with --plan local. Each run is a whole process (GNU time), the
# median of RUNS runs by wall time: wall, CPU (user + system), poses/s, peak RSS, output size and
# the motions written. Memory must not grow with the path.
#
# Two yardsticks in the same run:
# - the floor: the same CL file read as convert reads it and its motions formatted and written
#   with no kinematics (tests/bench/bench_read_write.cpp), one motion per reduced move (fewer
#   than convert writes) and in the tracking's steps (more); issue 32's target: the 1M raster
#   under the default plan in at most 2.5 times the floor;
# - the KDL pinv_nso tracking loop over 100 500 poses (tests/bench/bench_tracker.cpp), with the
#   predictor and as the plain loop of Andres' Algorithm 1, against the 100 000-pose convert:
#   how many times the whole conversion fits in KDL's loop alone.
#
# Usage: tests/bench/convert_bench.sh [BUILD_DIR] [SIZES] [RUNS]   (default: build,
#        "100000 1000000", 3)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
sizes=${2:-"100000 1000000"}
runs=${3:-3}
redpost=$build/plugin/redpost
floor=$build/tests/bench/redpost_bench_read_write
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
krl=$top/definitions/krl/krc4_lin.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
[[ -x $floor ]] || { echo "$floor not built (-DREDPOST_BENCHMARKS=ON)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"

kdl_ms=""
kdl_plain_ms=""
if [[ -x $build/tests/bench/redpost_bench_tracker ]]; then
  "$build/tests/bench/redpost_bench_tracker" --benchmark_filter='^BM_kdl_pinv_nso' \
    --benchmark_format=json >"$work/kdl.json" 2>/dev/null
  read -r kdl_ms kdl_plain_ms < <(python3 -c 'import json, sys
b = {x["name"].split("/")[0]: x["real_time"] for x in json.load(open(sys.argv[1]))["benchmarks"]}
print("%.1f %.1f" % (b["BM_kdl_pinv_nso"], b["BM_kdl_pinv_nso_no_predictor"]))' "$work/kdl.json")
  echo "KDL pinv_nso loop, 100 500 poses (Google Benchmark, one thread): $kdl_ms ms with the" \
    "predictor, $kdl_plain_ms ms as the plain loop"
else
  echo "KDL loop: $build/tests/bench/redpost_bench_tracker not built (-DREDPOST_BENCHMARKS=ON)"
fi

# median RUNS NAME CMD...: runs CMD RUNS times into a fresh $work/out; prints "wall cpu kib" of
# the median run by wall time, and leaves the last run's output in $work/out.
median() {
  local n=$1 name=$2
  shift 2
  : >"$work/times"
  for ((r = 0; r < n; r++)); do
    rm -rf "$work/out" && mkdir -p "$work/out"
    /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$@" >/dev/null 2>"$work/err" ||
      { echo "$name failed: $(head -3 "$work/err")" >&2; exit 1; }
    read -r wall user sys kib <"$work/time"
    echo "$wall $(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }') $kib" >>"$work/times"
  done
  sort -n "$work/times" | sed -n "$(((n + 1) / 2))p"
}

for n in $sizes; do
  python3 "$top/tests/bench/make_raster_apt.py" "$n" "$work/raster_$n.apt" >/dev/null
  floor_moves="" floor_steps=""
  for run in "floor" "floor steps" "global --threads 2" "global --threads 1" \
    "global --threads 0" "local"; do
    read -r plan threads <<<"$run"
    if [[ $plan == floor ]]; then
      # shellcheck disable=SC2086  # $threads is "" or "steps"
      read -r wall cpu kib < <(median "$runs" "$run" "$floor" "$work/raster_$n.apt" "$cell" "$krl" \
        "$work/out" RASTER $threads)
      [[ -z $threads ]] && floor_moves=$wall || floor_steps=$wall
    else
      # shellcheck disable=SC2086  # $threads is "" or "--threads N"
      read -r wall cpu kib < <(median "$runs" "$run" "$redpost" convert "$work/raster_$n.apt" \
        --cell "$cell" -o "$work/out" --name RASTER --plan "$plan" $threads -q)
    fi
    size=$(du -sk "$work/out" | cut -f1)
    motions=$(cat "$work/out"/*.src | grep -cE '^(LIN|PTP|CIRC|SLIN|SPL|SPTP) ' || true)
    awk -v n="$n" -v r="$run" -v w="$wall" -v c="$cpu" -v k="$kib" -v o="$size" -v m="$motions" \
      -v kdl="$kdl_ms" -v plain="$kdl_plain_ms" -v fm="$floor_moves" -v fs="$floor_steps" 'BEGIN {
        printf "%8d poses, %-18s: %6.2f s wall, %6.2f s CPU, %8.0f poses/s, peak RSS %5.1f MB, output %5.1f MB, %7d motions",
               n, r, w, c, n / w, k / 1024, o / 1024, m
        if (r ~ /^global/ && fm != "")
          printf ", %.2fx the floor (%.2fx in steps)", w / fm, w / fs
        if (n == 100000 && kdl != "" && r == "global --threads 2")
          printf ", KDL loop / this %.1fx (plain loop %.1fx)", kdl / 1000 / w, plain / 1000 / w
        printf "\n" }'
  done
  rm -f "$work/raster_$n.apt"
done
