#!/usr/bin/env bash
# Threads by default (issue 47, docs/performance.md "Threads by default"): the raster of
# make_raster_apt.py converted with --threads 1 and with the default (one per core), alone and
# as two conversions side by side (as a test suite or a user with two jobs runs them). The
# configurations run in turn, RUNS times, and each one's median wall time is printed, with the
# default's over one thread's. Target: side by side, the default no slower than one thread each.
#
# Usage: tests/bench/threads_bench.sh [BUILD_DIR] [POSES] [RUNS]   (default: build, 300000, 7)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
poses=${2:-300000}
runs=${3:-7}
redpost=$build/plugin/redpost
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"
python3 "$top/tests/bench/make_raster_apt.py" "$poses" "$work/raster.apt"

one() {  # one DIR THREADS...: a conversion into DIR
  local dir=$1
  shift
  rm -rf "$dir" && mkdir -p "$dir"
  "$redpost" convert "$work/raster.apt" --cell "$cell" -o "$dir" --name R -q "$@" 2>/dev/null
}
# seconds COMMAND...: the wall time of the command (s).
seconds() {
  local start end
  start=$(date +%s.%N)
  "$@"
  end=$(date +%s.%N)
  echo "$end - $start" | bc
}
alone() { one "$work/a" "$@"; }
side_by_side() {
  one "$work/a" "$@" &
  one "$work/b" "$@"
  wait
}
declare -A times
for ((r = 0; r < runs; ++r)); do
  times[alone_1]+="$(seconds alone --threads 1) "
  times[alone_default]+="$(seconds alone) "
  times[pair_1]+="$(seconds side_by_side --threads 1) "
  times[pair_default]+="$(seconds side_by_side) "
done
median() { tr ' ' '\n' <<<"$1" | grep . | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
echo "raster: $poses poses, median of $runs runs (wall s)"
for k in alone_1 alone_default pair_1 pair_default; do
  printf '%-14s %7.3f\n' "$k" "$(median "${times[$k]}")"
done
awk -v a1="$(median "${times[alone_1]}")" -v ad="$(median "${times[alone_default]}")" \
  -v p1="$(median "${times[pair_1]}")" -v pd="$(median "${times[pair_default]}")" \
  'BEGIN { printf "default over one thread: alone %.2f x, side by side %.2f x\n", ad / a1, pd / p1 }'
