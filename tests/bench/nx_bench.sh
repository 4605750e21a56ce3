#!/usr/bin/env bash
# The NX path against convert (issue 29, docs/performance.md): a 5-axis APT raster converted by
# `redpost convert` and replayed through the NX handlers by tcl/nx_replay.tcl (which reads the
# file itself and plays it as NX's MOM events), taken in turn RUNS times; prints the median wall
# and CPU time and the peak RSS of each, their ratio, and checks that the programs are the same.
# Target: the NX path at most 1.5 x convert's wall time on 100 000 poses.
#
# Usage: tests/bench/nx_bench.sh [BUILD_DIR] [POSES] [RUNS]   (default: build 100000 5)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
n=${2:-100000}
runs=${3:-5}
redpost=$build/plugin/redpost
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"
python3 "$top/tests/bench/make_raster_apt.py" "$n" "$work/raster.apt"
mkdir -p "$work/convert" "$work/nx"
for ((k = 0; k < runs; ++k)); do
  /usr/bin/time -a -f "%e %U %S %M" -o "$work/convert.times" "$redpost" convert \
    "$work/raster.apt" --cell "$cell" -o "$work/convert" --name RASTER -q 2>/dev/null
  /usr/bin/time -a -f "%e %U %S %M" -o "$work/nx.times" tclsh "$top/tcl/nx_replay.tcl" \
    --lib "$build/plugin" --cell "$cell" -o "$work/nx" --name RASTER -q "$work/raster.apt" \
    2>/dev/null
done
diff -r "$work/convert" "$work/nx" >/dev/null || { echo "the programs differ"; exit 1; }
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
report() {
  local wall cpu rss
  wall=$(awk '{ print $1 }' "$work/$1.times" | median)
  cpu=$(awk '{ print $2 + $3 }' "$work/$1.times" | median)
  rss=$(awk '{ print $4 }' "$work/$1.times" | median)
  printf "%-10s %d poses: wall %.2f s, CPU %.2f s, peak RSS %.1f MB (median of %d)\n" "$1" "$n" \
    "$wall" "$cpu" "$(awk -v k="$rss" 'BEGIN { print k / 1024 }')" "$runs"
  echo "$wall" >"$work/$1.wall"
}
report convert
report nx
awk -v a="$(cat "$work/convert.wall")" -v b="$(cat "$work/nx.wall")" \
  'BEGIN { printf "NX path / convert: %.2f x wall time (target <= 1.5); programs identical\n", b / a }'
