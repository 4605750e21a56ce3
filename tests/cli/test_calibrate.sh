#!/usr/bin/env bash
# cli.calibrate: `redpost calibrate plan -> simulate -> calibrate --json` driven as a user drives
# it, on the Andres cell with a "true" cell whose link 1 d is off by +0.4 mm.
#
#   test_calibrate.sh <path-to-redpost> <source-dir>
. "$(dirname "$0")/harness.sh" cli.calibrate "$@"
ANDRES="$SRC/definitions/cells/andres2011_kr15_track_table.xml"
[[ -f "$ANDRES" ]] || { echo "cli.calibrate: FAIL: no cell file '$ANDRES'" >&2; exit 1; }

# |value(json key) - expected| <= tol
close() {
  local json=$1 key=$2 want=$3 tol=$4
  python3 - "$json" "$key" "$want" "$tol" <<'PY' || fail "$key not within $4 of $3"
import json, sys
j = json.load(open(sys.argv[1]))
v = j["parameters"][sys.argv[2]]
want, tol = float(sys.argv[3]), float(sys.argv[4])
print(f"{sys.argv[2]} = {v} (true {want})")
sys.exit(0 if abs(v - want) <= tol else 1)
PY
}

# The "true" cell: link 1's d from -305 to -304.6 mm, nothing else changed.
sed 's|<dh alpha="90" a="803" theta="0" d="-305"/>|<dh alpha="90" a="803" theta="0" d="-304.6"/>|' \
  "$ANDRES" >"$TMP/true.xml"
[[ $(diff "$ANDRES" "$TMP/true.xml" | grep -c '^[<>]') -eq 2 ]] ||
  { echo "cli.calibrate: FAIL: could not perturb link 1 d in $ANDRES" >&2; exit 1; }

begin "plan writes the KRL program and the readings template with the same numbers"
run calibrate plan --cell "$ANDRES" -o "$TMP/plan"
expect_rc 0
T="$TMP/plan/readings_template.csv"
[[ -f "$T" ]] || fail "no $T"
grep -qx 'point,plane,distance,x,y,z,a,b,c,q1,q2' "$T" || fail "no header row in $T"
[[ $(grep -c '^[0-9]*,[xyz],,' "$T") -eq 108 ]] || fail "expected 108 rows with a blank distance"
grep -qx '1,x,,0,-200,150,0,-90,0,0,700' "$T" || fail "first point of plane x not as planned"
grep -qx '108,z,,.*' "$T" || fail "the last row is not point 108"
P="$TMP/plan/calib_plan.src"
[[ -f "$P" && -f "$TMP/plan/calib_plan.dat" ]] || fail "no calib_plan.src/.dat"
[[ $(grep -c '^; point [0-9]* of 108' "$P") -eq 108 ]] || fail "expected 108 numbered points"
[[ $(grep -c '^WAIT SEC 2.00' "$P") -eq 108 ]] || fail "expected a dwell at every point"
[[ $(grep -c '^PTP {E6AXIS' "$P") -eq 120 ]] || fail "expected 108 points + 6 approaches + 6 retracts"
grep -q "KRL program: .*calib_plan.src" "$TMP/out" || fail "program not reported"
# The program passes the static checks and stays within the cell's axis limits.
run check "$P" --cell "$ANDRES"
expect_rc 0
passed

begin "plan --dwell 0 writes HALT, --validation writes the validation program"
run calibrate plan --cell "$ANDRES" --dwell 0 --validation 12 -o "$TMP/val"
expect_rc 0
[[ $(grep -c '^HALT' "$TMP/val/calib_validate.src") -eq 12 ]] || fail "expected 12 HALTs"
[[ $(grep -c '^[0-9]*,z,,' "$TMP/val/validation_template.csv") -eq 12 ]] ||
  fail "expected 12 table-plane rows"
passed

begin "plan with a 4x4 grid and other configurations"
run calibrate plan --cell "$ANDRES" --grid 4 --configs "0,650;45,300" -o "$TMP/plan4"
expect_rc 0
[[ $(grep -c '^[0-9]*,[xyz],,' "$TMP/plan4/readings_template.csv") -eq 48 ]] || fail "expected 48 rows"
grep -q ',0.7853981633974483,300$' "$TMP/plan4/readings_template.csv" || fail "no 45 deg row"
passed

begin "plan refuses a bad --configs"
run calibrate plan --cell "$ANDRES" --configs "0,700;45" -o "$TMP/bad"
expect_rc 2
grep -q -- "--configs" "$TMP/err" || fail "message does not name --configs"
passed

begin "the unfilled template is refused with its line"
run calibrate --cell "$ANDRES" --readings "$T"
expect_rc 2
grep -q "readings_template.csv:3: column 'distance' is empty" "$TMP/err" || fail "message"
passed

begin "simulate, noise-free"
run calibrate simulate --cell "$ANDRES" --true "$TMP/true.xml" --noise-mm 0 -o "$TMP/exact.csv"
expect_rc 0
[[ $(grep -c '^[0-9]*,[xyz],' "$TMP/exact.csv") -eq 108 ]] || fail "expected 108 readings"
passed

begin "calibrate noise-free readings recovers the truth"
run calibrate --cell "$ANDRES" --readings "$TMP/exact.csv" --json "$TMP/exact.json"
expect_rc 0
grep -q "link1.d" "$TMP/out" || fail "no parameter table"
grep -q "iterations:" "$TMP/out" || fail "no iterations"
grep -q "singular values" "$TMP/out" || fail "no singular values"
close "$TMP/exact.json" link1.d -304.6 1e-6
close "$TMP/exact.json" link1.a 803 1e-6
close "$TMP/exact.json" link1.alpha 1.5707963267948966 1e-9
close "$TMP/exact.json" link2.d 0 1e-6
python3 - "$TMP/exact.json" <<'PY' || fail "JSON fields"
import json, sys
j = json.load(open(sys.argv[1]))
assert set(j["parameters"]) == {"link1.alpha", "link1.a", "link1.theta", "link1.d",
                                "link2.theta", "link2.d"}
assert 1 <= j["iterations"] <= 10
assert j["rms_before_mm"] > 0.1 and j["rms_after_mm"] < 1e-6
assert len(j["singular_values"]) == 6 and min(j["singular_values"]) > 0
PY
passed

begin "calibrate noisy readings (sigma 0.035 mm) recovers link1.d within 0.15 mm"
run calibrate simulate --cell "$ANDRES" --true "$TMP/true.xml" --seed 3 -o "$TMP/noisy.csv"
expect_rc 0
run calibrate --cell "$ANDRES" --readings "$TMP/noisy.csv" --json "$TMP/noisy.json"
expect_rc 0
close "$TMP/noisy.json" link1.d -304.6 0.15
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if j["rms_after_mm"] < 0.06 else 1)' \
  "$TMP/noisy.json" || fail "rms_after_mm"
passed

begin "calibrate -o writes the cell with only the identified values changed"
run calibrate --cell "$ANDRES" --readings "$TMP/exact.csv" -o "$TMP/calibrated.xml"
expect_rc 0
diff "$ANDRES" "$TMP/calibrated.xml" >"$TMP/diff" || true
[[ $(grep -c '^>' "$TMP/diff") -eq 3 && $(grep -c '^<' "$TMP/diff") -eq 2 ]] ||
  fail "expected a comment and two changed <dh> lines: $(cat "$TMP/diff")"
grep -q '^> <!-- calibrated by redpost calibrate on 20[0-9][0-9]-.*RMS' "$TMP/diff" ||
  fail "no comment with the date and RMS"
python3 - "$TMP/calibrated.xml" <<'PY' || fail "link 1 is not alpha 90, a 803, d -304.6 (within 1e-9)"
import re, sys
dh = re.findall(r'<dh alpha="([^"]*)" a="([^"]*)" theta="[^"]*" d="([^"]*)"', open(sys.argv[1]).read())
alpha, a, d = (float(v) for v in dh[0])
sys.exit(0 if abs(alpha - 90) < 1e-9 and abs(a - 803) < 1e-9 and abs(d + 304.6) < 1e-9 else 1)
PY
# The calibrated cell explains the readings taken at logged joints: RMS before (from it) is zero.
# (Not with the commanded-pose form: its arm joints are solved on the --cell model, as the
# controller solved them on the nominal one, so the calibrated cell as --cell changes them.)
run calibrate simulate --cell "$ANDRES" --true "$TMP/true.xml" --noise-mm 0 --form joints \
  -o "$TMP/joints0.csv"
expect_rc 0
run calibrate --cell "$TMP/calibrated.xml" --readings "$TMP/joints0.csv" --json "$TMP/again.json"
expect_rc 0
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if j["rms_before_mm"] < 1e-6 else 1)' \
  "$TMP/again.json" || fail "the calibrated cell does not explain the readings"
passed

begin "simulate in the joints form, calibrate from it"
run calibrate simulate --cell "$ANDRES" --true "$TMP/true.xml" --noise-mm 0 --form joints \
  -o "$TMP/joints.csv"
expect_rc 0
grep -qx 'point,plane,distance,q1,q2,q3,q4,q5,q6,q7,q8,q9' "$TMP/joints.csv" || fail "header"
run calibrate --cell "$ANDRES" --readings "$TMP/joints.csv" --json "$TMP/joints.json"
expect_rc 0
close "$TMP/joints.json" link1.d -304.6 1e-6
passed

begin "rank deficiency is refused with exit 2, --allow-partial calibrates"
run calibrate --cell "$ANDRES" --readings "$TMP/exact.csv" --params link1.d,link2.d,link3.d
expect_rc 2
grep -q "cannot be separated" "$TMP/err" || fail "no diagnosis"
run calibrate --cell "$ANDRES" --readings "$TMP/exact.csv" --params link1.d,link2.d,link3.d \
  --allow-partial --json "$TMP/partial.json"
expect_rc 0
grep -q "not identified" "$TMP/out" || fail "no partial note"
passed

begin "a bad row is reported with its line"
{ echo "plane,distance,x,y,z,a,b,c,q1,q2"; echo "z,0.2,-200,-200,0,0,0,0,0,700";
  echo "q,0.2,-200,-200,0,0,0,0,0,700"; } >"$TMP/badrow.csv"
run calibrate --cell "$ANDRES" --readings "$TMP/badrow.csv"
expect_rc 2
grep -q "badrow.csv:3: column 'plane': 'q' is not x, y or z" "$TMP/err" || fail "message"
passed

begin "missing --readings"
run calibrate --cell "$ANDRES"
expect_rc 2
passed


begin "validation before and after, robust loss, and a path converted with the calibrated cell"
run calibrate simulate --cell "$ANDRES" --true "$TMP/true.xml" --validation 24 --seed 5 \
  -o "$TMP/val.csv"
expect_rc 0
# Two gross outliers in the calibration readings: rows 10 and 50 off by 3 mm.
python3 - "$TMP/noisy.csv" "$TMP/dirty.csv" <<'PY'
import sys
rows = open(sys.argv[1]).read().splitlines()
out = []
for line in rows:
    f = line.split(",")
    if f[0] in ("10", "50"):
        f[2] = repr(float(f[2]) + 3.0)
    out.append(",".join(f))
open(sys.argv[2], "w").write("\n".join(out) + "\n")
PY
run calibrate --cell "$ANDRES" --readings "$TMP/dirty.csv" --validate "$TMP/val.csv" \
  --loss huber --json "$TMP/robust.json" -o "$TMP/robust.xml" --report "$TMP/robust.html"
expect_rc 0
# The report: six parameters per iteration, RMS, singular values, residuals, validation.
[[ $(grep -o '<svg class="plot"' "$TMP/robust.html" | wc -l) -eq 10 ]] || fail "expected 10 plots"
grep -q 'weighted below 0.5' "$TMP/robust.html" || fail "the outliers are not in the report"
grep -q "huber loss: 2 reading(s) weighted below 0.5: rows 10, 50" "$TMP/out" ||
  fail "outliers not reported"
grep -q "^validation before (24 readings)" "$TMP/out" || fail "no validation line"
close "$TMP/robust.json" link1.d -304.6 0.15
python3 - "$TMP/robust.json" <<'PY' || fail "JSON validation/history"
import json, sys
j = json.load(open(sys.argv[1]))
v = j["validation"]
assert v["before"]["count"] == 24 and v["after"]["count"] == 24
assert v["before"]["rms_mm"] > 0.2, v
assert v["after"]["rms_mm"] < 0.07, v
assert j["loss"] == "huber" and j["outliers"] == [10, 50]
h = j["history"]
assert len(h) == j["iterations"] + 1 and h[0]["iteration"] == 0
assert abs(h[0]["rms_mm"] - j["rms_before_mm"]) < 1e-12
assert abs(h[-1]["rms_mm"] - j["rms_after_mm"]) < 1e-12
PY
# The calibrated cell loads and converts the bundled example; its joints differ from the
# nominal cell's where link 1 moved (E1/E2 and the arm).
mkdir -p "$TMP/conv_nominal" "$TMP/conv_cal"
run convert "$SRC/examples/cl/pocket_arcs.apt" --cell "$ANDRES" -o "$TMP/conv_nominal"
expect_rc 0
run convert "$SRC/examples/cl/pocket_arcs.apt" --cell "$TMP/robust.xml" -o "$TMP/conv_cal"
expect_rc 0
src_nominal=$(ls "$TMP"/conv_nominal/*.src | head -1)
src_cal=$(ls "$TMP"/conv_cal/*.src | head -1)
run diff "$src_nominal" "$src_cal" --axis-tol 0.001
[[ $RC -eq 1 ]] || fail "the calibrated cell gives the same joints as the nominal one"
passed

echo "cli.calibrate: all $checks checks passed"
