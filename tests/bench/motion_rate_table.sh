#!/usr/bin/env bash
# The controller's clock on real and generated toolpaths (docs/timing.md, "The interpolation
# cycle"; issue 30): every file converted with each feed set to 10 000 mm/min, and per file the
# motions written, how many last less than one 12 ms cycle at their $VEL.CP (convert's count and
# `redpost check`'s, from the written text), and the cutting time the cycle-aware model gives
# against the CL feeds' time.
#
# Usage: tests/bench/motion_rate_table.sh [BUILD_DIR]   (prints a Markdown table)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
redpost=$build/plugin/redpost
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"

python3 "$top/tests/bench/make_raster_apt.py" 20000 "$work/raster_20k.apt"
# The evaldata job whose tool 20 has no TOOL_DATA of its own needs a tool table.
{
  echo '<tool-table>'
  for t in 1 2 6 15 16 18 20; do
    echo "  <tool number=\"$t\" data=\"$((t % 16 + 1))\" length=\"100\"/>"
  done
  echo '</tool-table>'
} >"$work/tools.xml"
# options_of NAME: what a file needs to convert (its MCS turned, a tool table).
options_of() {
  case $1 in
    swcam_cutcom_multi_op.apt) echo "--tools $work/tools.xml" ;;
    nx_variable_contour_5axis.cls) echo "--msys apply" ;;
  esac
}
inputs=("$work/raster_20k.apt" "$top"/examples/cl/*)
evaldata=$top/../shared/evaldata
[[ -d $evaldata ]] && inputs+=("$evaldata"/apt/*.apt "$evaldata"/clsf/*)

echo
echo "| file | motions | below 12 ms (convert) | below 12 ms (check) | cutting time / CL feeds' time |"
echo "|---|---|---|---|---|"
for f in "${inputs[@]}"; do
  name=$(basename "$f")
  fast=$work/fast_$name
  sed -E 's#FEDRAT/MMPM,[ ]*[0-9.]+#FEDRAT/MMPM,10000#; s#FEDRAT/[ ]*[0-9.]+,[ ]*MMPM#FEDRAT/10000,MMPM#; s#^(CYCLE/.*MMPM,)[ ]*[0-9.]+#\110000#' \
    "$f" >"$fast"
  out=$work/out_$name
  mkdir -p "$out"
  # shellcheck disable=SC2046 # the options are words
  if ! "$redpost" convert "$fast" --cell "$cell" -o "$out" --name P $(options_of "$name") \
    >"$work/log" 2>&1; then
    echo "| $name | refused: $(grep -m1 '^redpost:' "$work/log" | sed "s#$work/##" | cut -c10-120)... | | | |"
    continue
  fi
  motions=$(sed -n 's/^poses [0-9]* (motions written \([0-9]*\)).*/\1/p' "$work/log")
  below=$(sed -n 's/^interpolation cycle 12 ms: \([0-9]*\) of \([0-9]*\) .*(\([0-9]*\) %.*/\1 of \2 (\3 %)/p' "$work/log")
  ratio=$(sed -n 's/.*(cutting .*, \([-+0-9.]*\) % on the CL feeds.*/\1/p' "$work/log")
  ratio=$(awk -v p="${ratio:-0}" 'BEGIN { printf "%.2fx", 1 + p / 100 }')
  checked=$("$redpost" check "$out/P.src" | sed -n 's/.*: motion rate: \([0-9]*\) of \([0-9]*\) .*/\1 of \2/p' | head -1)
  echo "| $name $(options_of "$name" | sed "s#$work/##") | $motions | $below | ${checked:-0} | $ratio |"
done
