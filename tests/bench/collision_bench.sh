#!/usr/bin/env bash
# The collision check's cost (issue 46, docs/performance.md, "Collisions"): the 5-axis raster of
# make_raster_apt.py converted on the 9-joint cell three ways, each a whole process (GNU time),
# the median of RUNS runs by wall time:
#   none  --no-collision-check: no body checked (the program before issue 46);
#   cell  the default: the cell's own bodies and the tool's;
#   scene the cell's, the tool's and a set-up's: two clamps beside the raster and the part under
#         it (boxes written here in the CL frame).
# Printed: wall, CPU, peak RSS, the distances computed, and the scene's time over the others.
# Target: the scene within 1.5 x the conversion without it, under 64 MB.
#
# Usage: tests/bench/collision_bench.sh [BUILD_DIR] [POSES] [RUNS] [THREADS]
#        (default: build, 1000000, 3, 2)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
poses=${2:-1000000}
runs=${3:-3}
threads=${4:-2}
redpost=$build/plugin/redpost
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"
python3 "$top/tests/bench/make_raster_apt.py" "$poses" "$work/raster.apt"
# Clamps beside the raster and the part under it (write_fixture_scene.py).
python3 "$top/tests/bench/write_fixture_scene.py" "$work"
scene=(--fixture "$work/clamp_left.stl" --fixture "$work/clamp_right.stl" --part "$work/part.stl")
echo "raster: $poses poses, --threads $threads, median of $runs runs"
printf '%-6s %9s %9s %10s %12s %s\n' mode "wall s" "CPU s" "RSS MB" "distances" "closest"
declare -A wall
for mode in none cell scene; do
  case $mode in
    none) args=(--no-collision-check) ;;
    cell) args=() ;;
    scene) args=("${scene[@]}") ;;
  esac
  results=()
  for ((r = 0; r < runs; ++r)); do
    rm -rf "$work/out" && mkdir -p "$work/out"
    /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$redpost" convert "$work/raster.apt" \
      --cell "$cell" -o "$work/out" --name RASTER --threads "$threads" "${args[@]}" \
      >"$work/stdout" 2>/dev/null
    read -r e u s m <"$work/time"
    results+=("$e $(echo "$u + $s" | bc) $m")
  done
  median=$(printf '%s\n' "${results[@]}" | sort -n | sed -n "$(((runs + 1) / 2))p")
  read -r e c m <<<"$median"
  wall[$mode]=$e
  closest=$(sed -n 's/^collisions: .*closest //p' "$work/stdout")
  printf '%-6s %9.2f %9.2f %10.1f %12s %s\n' "$mode" "$e" "$c" "$(echo "$m / 1024" | bc -l)" \
    "-" "${closest:-not checked}"
done
printf 'scene / none: %.2f x, scene / cell: %.2f x\n' \
  "$(echo "${wall[scene]} / ${wall[none]}" | bc -l)" "$(echo "${wall[scene]} / ${wall[cell]}" | bc -l)"
