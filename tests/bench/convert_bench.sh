#!/usr/bin/env bash
# The end-to-end convert benchmark (docs/performance.md): generates 5-axis APT rasters of 100 000
# and 1 000 000 poses, converts them on the 9-joint cell with the point reduction and without it
# (--fit-tol 0), and prints wall time, poses/s and peak RSS of each run (GNU time). Memory must
# not grow with the path length.
#
# Usage: tests/bench/convert_bench.sh [BUILD_DIR]   (default: build)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
redpost=$build/plugin/redpost
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"
for n in 100000 1000000; do
  python3 "$top/tests/bench/make_raster_apt.py" "$n" "$work/raster_$n.apt"
  # With the point reduction (the default, issue 30) and without it (--fit-tol 0: one motion per
  # CL point).
  for fit in 0.01 0; do
    rm -rf "$work/out_$n" && mkdir -p "$work/out_$n"
    /usr/bin/time -f "%e %M" -o "$work/time_$n" "$redpost" convert "$work/raster_$n.apt" \
      --cell "$top/definitions/cells/andres2011_kr15_track_table.xml" -o "$work/out_$n" \
      --name RASTER --split 50000 --fit-tol "$fit" -q
    read -r seconds kib <"$work/time_$n"
    size=$(du -sk "$work/out_$n" | cut -f1)
    awk -v n="$n" -v s="$seconds" -v k="$kib" -v o="$size" -v f="$fit" 'BEGIN {
      printf "%8d poses, --fit-tol %-4s: %6.2f s, %8.0f poses/s, peak RSS %6.1f MB, output %6.1f MB\n",
             n, f, s, n / s, k / 1024, o / 1024 }'
  done
  rm -rf "$work/out_$n" "$work/raster_$n.apt"
done
