#!/usr/bin/env bash
# The review tools at the converter's scale (issue 31, docs/performance.md "check and diff"):
# a 1 000 000-pose raster converted with one motion per CL point (--fit-tol 0, 1M motions in
# parts), then `redpost check` on that program and `redpost diff` against the same raster
# converted with --plan local. Prints wall time and peak RSS of each (GNU time), and check's and
# diff's time over the convert that wrote the program (targets: check <= 1.0x, diff <= 2.0x,
# each <= 64 MB); and check's clearance from the text, with the cell's bodies and with a fixture
# scene (issue 46).
#
# Usage: tests/bench/review_bench.sh [BUILD_DIR] [POSES]   (default: build, 1000000)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
n=${2:-1000000}
redpost=${REDPOST:-$build/plugin/redpost}
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"
python3 "$top/tests/bench/make_raster_apt.py" "$n" "$work/raster.apt"

# timed NAME COMMAND...: runs it, prints "NAME: s, MB" and leaves the seconds in $seconds.
timed() {
  local name=$1
  shift
  local rc=0
  /usr/bin/time -f "%e %M" -o "$work/time" "$@" >"$work/log" 2>&1 || rc=$?
  read -r seconds kib < <(tail -1 "$work/time")
  awk -v n="$name" -v s="$seconds" -v k="$kib" -v rc="$rc" \
    'BEGIN { printf "%-34s %7.2f s, peak RSS %7.1f MB (exit %d)\n", n, s, k / 1024, rc }'
}

mkdir -p "$work/a" "$work/b"
timed "convert (global plan)" "$redpost" convert "$work/raster.apt" --cell "$cell" -o "$work/a" \
  --name RASTER --fit-tol 0 -q
convert_s=$seconds
echo "  program: $(ls "$work/a"/*.src | wc -l) .src files, $(du -sk "$work/a" | cut -f1) KB"
timed "convert (--plan local)" "$redpost" convert "$work/raster.apt" --cell "$cell" -o "$work/b" \
  --name RASTER --fit-tol 0 --plan local -q
timed "check" "$redpost" check "$work/a/RASTER.src" --cell "$cell"
check_s=$seconds
echo "  $(tail -1 "$work/log" | cut -c1-120)"
# The clearance recomputed from the text (issue 46): the cell's and the tool's bodies, then the
# fixture scene of collision_bench.sh (two clamps beside the raster, the part under it).
timed "check --clearance" "$redpost" check "$work/a/RASTER.src" --cell "$cell" --clearance
clearance_s=$seconds
echo "  $(grep -m1 'closest' "$work/log" | cut -c1-120)"
python3 "$top/tests/bench/write_fixture_scene.py" "$work"
timed "check with the fixture scene" "$redpost" check "$work/a/RASTER.src" --cell "$cell" \
  --fixture "$work/clamp_left.stl" --fixture "$work/clamp_right.stl" --part "$work/part.stl"
scene_s=$seconds
echo "  $(grep -m1 'closest' "$work/log" | cut -c1-120)"
timed "diff (global against local plan)" "$redpost" diff "$work/a/RASTER.src" "$work/b/RASTER.src"
diff_s=$seconds
echo "  $(grep -m1 '^different\|^equal' "$work/log" | cut -c1-120)"
awk -v c="$convert_s" -v k="$check_s" -v d="$diff_s" -v l="$clearance_s" -v f="$scene_s" \
  'BEGIN { printf "check %.2fx and diff %.2fx the convert that wrote the program\n", k / c, d / c
           printf "check --clearance %.2fx, with the fixture scene %.2fx\n", l / c, f / c }'
