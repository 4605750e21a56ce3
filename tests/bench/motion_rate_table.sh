#!/usr/bin/env bash
# The controller's clock on real and generated toolpaths (docs/timing.md, "The interpolation
# cycle" and "Point reduction"; issue 30): every file converted with each feed set to
# 10 000 mm/min four ways: 0.7's program (krc4_lin, --fit-tol 0), the point reduction with LINs
# (krc4_lin), with arcs (krc4_circ), and with arcs and the fast plan preset; and krc4_spline with
# the reduction (SPL knots), also with the fast preset. Per file the motions
# written, how many last less than one 12 ms cycle at their $VEL.CP (convert's count; `redpost
# check` counts the same from the written text), the cutting time the cycle-aware model gives
# against the CL feeds' time, and how far each reduced program's path strays from the CL points
# (tests/cli/fit_check.py, against the 0.7 program printed with 6 decimals, whose positions are
# the CL points). Last, the
# floor: the least time the controller's path limits allow the CL path with arms that never
# limit it (tests/bench/time_floor.py), against the same CL feeds' time.
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
# The floor (tests/bench/time_floor.py) needs the rapids' positions (krc4_circ with Cartesian PTPs)
# and every feed move written at its feed (the cell without axis speeds, planned pose by pose).
sed '/<speed velocity=/d' "$cell" >"$work/free_cell.xml"
sed 's#<statement name="rapid">PTP {E6AXIS:[^<]*<#<statement name="rapid">PTP {E6POS: X {x}, Y {y}, Z {z}, A {a}, B {b}, C {c}{ext}}<#' \
  "$top/definitions/krl/krc4_circ.xml" >"$work/circ_cartesian.xml"
sed 's#<numbers [^>]*>#<numbers position="6" angle="6" external="6" velocity="6" rpm="0"/>#' \
  "$top/definitions/krl/krc4_circ.xml" >"$work/krc4_circ_exact.xml"
inputs=("$work/raster_20k.apt" "$top"/examples/cl/*)
evaldata=$top/../shared/evaldata
[[ -d $evaldata ]] && inputs+=("$evaldata"/apt/*.apt "$evaldata"/clsf/*)

# convert_at FILE NAME OUT [options...]: converts; prints "motions|below|ratio" or "refused: why".
convert_at() {
  local f=$1 name=$2 out=$3
  shift 3
  mkdir -p "$out"
  # shellcheck disable=SC2046 # the options are words
  if ! "$redpost" convert "$f" --cell "$cell" -o "$out" --name P $(options_of "$name") "$@" \
    >"$work/log" 2>&1; then
    echo "refused: $(grep -m1 '^redpost:' "$work/log" | sed "s#$work/##" | cut -c10-100)..."
    return
  fi
  local motions below ratio
  motions=$(sed -n 's/^poses [0-9]* (motions written \([0-9]*\)).*/\1/p' "$work/log")
  below=$(sed -n 's/^interpolation cycle 12 ms: \([0-9]*\) of \([0-9]*\) .*(\([0-9]*\) %.*/\1 (\3 %)/p' "$work/log")
  ratio=$(sed -n 's/.*(cutting .*, \([-+0-9.]*\) % on the CL feeds.*/\1/p' "$work/log")
  ratio=$(awk -v p="${ratio:-0}" 'BEGIN { printf "%.2fx", 1 + p / 100 }')
  echo "$motions|${below:-0}|$ratio"
}

# fit_of REDUCED REFERENCE: "mm, deg" of the largest deviation of a CL point from the path. The
# reference is krc4_circ with --fit-tol 0, printed with 6 decimals (krc4_circ_exact below): its CL points are exact to 1e-6, and the
# reduced program's own decimals must stay within the tolerance.
fit_of() {
  (python3 "$top/tests/cli/fit_check.py" "$1" "$2" --slack-mm 1e-6 --slack-deg 1e-5 || true) |
    sed -n 's/.*largest deviation \([0-9.]*\) mm and \([0-9.]*\) deg.*; \([0-9]*\) outside.*/\1, \2 (\3 outside)/p'
}

echo
echo "Each cell: 0.7 (krc4_lin, --fit-tol 0) → reduction, krc4_lin → reduction, krc4_circ; the"
echo "time also → krc4_circ with --preset fast; the deviation for krc4_lin and krc4_circ. Then"
echo "krc4_spline with the reduction (SPL where the path is smooth): motions and those below 12 ms,"
echo "the time (→ with --preset fast), the deviation. Last, the floor: the least time over the CL"
echo "feeds' time that \$ACC.CP, \$VEL.ORI1 and the blend allow the path (tests/bench/time_floor.py)."
echo
echo "| file | motions | below 12 ms | cutting time / CL feeds' time | largest deviation (mm, deg) | spline: motions, below 12 ms | spline: time | spline: deviation | floor |"
echo "|---|---|---|---|---|---|---|---|---|"
for f in "${inputs[@]}"; do
  name=$(basename "$f")
  fast=$work/fast_$name
  sed -E 's#FEDRAT/MMPM,[ ]*[0-9.]+#FEDRAT/MMPM,10000#; s#FEDRAT/[ ]*[0-9.]+,[ ]*MMPM#FEDRAT/10000,MMPM#; s#^(CYCLE/.*MMPM,)[ ]*[0-9.]+#\110000#' \
    "$f" >"$fast"
  before=$(convert_at "$fast" "$name" "$work/before_$name" --fit-tol 0)
  label="$name $(options_of "$name" | sed "s#$work/##")"
  if [[ $before == refused* ]]; then
    echo "| $label | $before | | | |"
    continue
  fi
  convert_at "$fast" "$name" "$work/exact_$name" --fit-tol 0 --krl "$work/krc4_circ_exact.xml" >/dev/null
  lin=$(convert_at "$fast" "$name" "$work/lin_$name")
  circ=$(convert_at "$fast" "$name" "$work/circ_$name" --krl krc4_circ)
  quick=$(convert_at "$fast" "$name" "$work/quick_$name" --krl krc4_circ --preset fast)
  cell=$work/free_cell.xml convert_at "$fast" "$name" "$work/floor_$name" \
    --krl "$work/circ_cartesian.xml" --fit-tol 0 --plan local >/dev/null
  floor=$( (python3 "$top/tests/bench/time_floor.py" "$work/floor_$name/P.src" --feed 10000 || true) |
    sed -n 's/.*floor .* s (\([0-9.]*x\)).*/\1/p')
  spl=$(convert_at "$fast" "$name" "$work/spl_$name" --krl krc4_spline)
  splquick=$(convert_at "$fast" "$name" "$work/splquick_$name" --krl krc4_spline --preset fast)
  IFS='|' read -r m0 b0 r0 <<<"$before"
  IFS='|' read -r m1 b1 r1 <<<"$lin"
  IFS='|' read -r m2 b2 r2 <<<"$circ"
  IFS='|' read -r _ _ r3 <<<"$quick"
  IFS='|' read -r m4 b4 r4 <<<"$spl"
  IFS='|' read -r _ _ r5 <<<"$splquick"
  fit_lin=$(fit_of "$work/lin_$name/P.src" "$work/exact_$name/P.src")
  fit_circ=$(fit_of "$work/circ_$name/P.src" "$work/exact_$name/P.src")
  fit_spl=$(fit_of "$work/spl_$name/P.src" "$work/exact_$name/P.src")
  echo "| $label | $m0 → $m1 → $m2 | $b0 → $b1 → $b2 | $r0 → $r1 → $r2 → $r3 | ${fit_lin:-fit check failed}; ${fit_circ:-fit check failed} | $m4, $b4 | $r4 → $r5 | ${fit_spl:-fit check failed} | ${floor:-?} |"
done
