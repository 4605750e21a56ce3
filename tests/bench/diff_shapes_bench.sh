#!/usr/bin/env bash
# `redpost diff` and `redpost check` on the shapes that once had a cliff (issue 48,
# docs/krl-diff.md "Bounded work", docs/performance.md "diff and check on any shape"): for each
# shape of tests/bench/make_shape_krl.py, N motions split as redpost splits a program (parts of
# 20 000), `check` on it, `diff` against itself and `diff` against a copy moved by up to 0.01 mm
# in each coordinate (every point over the 0.001 mm tolerance: the path search cannot stop at
# a partner on the path). Prints wall time and peak RSS (GNU time) and each figure's ratio to
# the plain raster's (target: at most 2x in time and memory).
#
# Usage: tests/bench/diff_shapes_bench.sh [BUILD_DIR] [MOTIONS]   (default: build, 1000000)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
n=${2:-1000000}
redpost=${REDPOST:-$build/plugin/redpost}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC'); $n motions"
printf '%-10s %-18s %9s %9s %8s %8s  %s\n' shape run seconds MiB "x time" "x mem" note
declare -A base_s base_m
for shape in raster point backforth line finish; do
  python3 "$top/tests/bench/make_shape_krl.py" "$shape" "$n" "$work/a" --part 20000
  python3 "$top/tests/bench/make_shape_krl.py" "$shape" "$n" "$work/b" --part 20000 --jitter 0.01
  for run in check diff_itself diff_moved; do
    case $run in
      check) cmd=("$redpost" check "$work/a/SHAPE.src") ;;
      diff_itself) cmd=("$redpost" diff "$work/a/SHAPE.src" "$work/a/SHAPE.src") ;;
      diff_moved) cmd=("$redpost" diff "$work/a/SHAPE.src" "$work/b/SHAPE.src") ;;
    esac
    rc=0
    /usr/bin/time -f "%e %M" -o "$work/time" "${cmd[@]}" >"$work/out" 2>&1 || rc=$?
    # check: 0 clean; diff: 0 equal, 1 different. Anything else is a failure of the run.
    if ((rc > 1)); then
      echo "$shape $run: exit $rc: $(tail -3 "$work/out")"
      exit 1
    fi
    read -r s kib < <(tail -1 "$work/time")
    mib=$(awk -v k="$kib" 'BEGIN { printf "%.1f", k / 1024 }')
    if [[ $shape == raster ]]; then
      base_s[$run]=$s
      base_m[$run]=$mib
    fi
    note=$(grep -o '[0-9]* points\? in a crowd' "$work/out" || true)
    awk -v sh="$shape" -v r="$run" -v s="$s" -v m="$mib" -v bs="${base_s[$run]}" \
      -v bm="${base_m[$run]}" -v note="$note" \
      'BEGIN { printf "%-10s %-18s %9.2f %9.1f %8.2f %8.2f  %s\n", sh, r, s, m, s / bs, m / bm, note }'
  done
  rm -rf "$work/a" "$work/b"
done
