#!/usr/bin/env bash
# report.calibrate_and_place: the reports of `redpost calibrate --report`, `redpost calibrate plan
# --report` and `redpost place --report`, written by the real commands and rendered in headless
# chromium (render_check.sh): no console errors, not blank, the expected number of plots; and
# their 3D views through chromedriver (scene_check.py). Exit 77 (skip) without chromium.
#
#   test_command_reports.sh <path-to-redpost> <source-dir> <out-dir>
set -u
BIN=$1
SRC=$(cd "$2" && pwd)
OUT=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$OUT" && mkdir -p "$OUT" || exit 1
fail() { echo "report.calibrate_and_place: FAIL: $*" >&2; exit 1; }

# Calibration: readings from a "true" Andres cell whose link 1 d is off by 0.4 mm.
ANDRES="$SRC/definitions/cells/andres2011_kr15_track_table.xml"
sed 's|<dh alpha="90" a="803" theta="0" d="-305"/>|<dh alpha="90" a="803" theta="0" d="-304.6"/>|' \
  "$ANDRES" >"$OUT/true.xml"
"$BIN" calibrate simulate --cell "$ANDRES" --true "$OUT/true.xml" -o "$OUT/r.csv" >/dev/null ||
  fail "simulate"
"$BIN" calibrate simulate --cell "$ANDRES" --true "$OUT/true.xml" --validation 48 \
  -o "$OUT/v.csv" >/dev/null || fail "simulate --validation"
"$BIN" calibrate --cell "$ANDRES" --readings "$OUT/r.csv" --validate "$OUT/v.csv" \
  --report "$OUT/calibrate.html" >/dev/null || fail "calibrate --report"

# The measurement plan (issue 21): its report has no plots, a table and the 3D view.
"$BIN" calibrate plan --cell "$ANDRES" -o "$OUT/plan" --report "$OUT/plan.html" >/dev/null 2>&1 ||
  fail "calibrate plan --report"

# Placement: the example job on a coarse grid (the report's structure does not depend on it).
sed -e 's|points_per_segment="20"|points_per_segment="6"|' \
    -e 's|step="5deg" max_step="10deg" max_joint_step="20deg"|step="15deg" max_step="30deg" max_joint_step="45deg"|' \
    -e 's|global_evaluations="[0-9]*"|global_evaluations="120"|' \
    -e 's|local_evaluations="[0-9]*"|local_evaluations="40"|' \
    -e "s|file=\"../../definitions|file=\"$SRC/definitions|" \
    "$SRC/examples/placement/caro2014_job.xml" >"$OUT/job.xml"
"$BIN" place "$OUT/job.xml" -o "$OUT/place" --report "$OUT/place.html" >/dev/null ||
  fail "place --report"

rc=0
"$here/render_check.sh" "$OUT/calibrate.html" 10 "$OUT/calibrate.png" 3000 || rc=$?
[[ $rc -eq 0 ]] || exit $rc
"$here/render_check.sh" "$OUT/place.html" 7 "$OUT/place.png" 3000 || rc=$?
[[ $rc -eq 0 ]] || exit $rc
"$here/render_check.sh" "$OUT/plan.html" 0 "$OUT/plan.png" 1200 || rc=$?
[[ $rc -eq 0 ]] || exit $rc
# Under the sanitizers the pages are the same bytes and the browser is not what is checked
# (scripts/reliability.sh sets REDPOST_SANITIZER): the 3D views are checked in the plain build.
if [[ -n "${REDPOST_SANITIZER:-}" ]]; then
  echo "note: the 3D views' browser checks run in the plain build only"
  exit 0
fi
python3 "$here/scene_check.py" "$OUT/plan.html" --links "$(grep -c '<joint ' "$ANDRES")" \
  --out-dir "$OUT/plan-shots" || rc=$?
[[ $rc -eq 0 ]] || exit $rc
# The 3D view of the best placement (issue 21): one link solid per joint of the Caro cell.
links=$(grep -c '<joint ' "$SRC/definitions/cells/caro2014_kr270_table.xml")
python3 "$here/scene_check.py" "$OUT/place.html" --links "$links" --out-dir "$OUT" || rc=$?
exit $rc
