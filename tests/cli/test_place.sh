#!/usr/bin/env bash
# cli.place: `redpost place` on the example job of Caro 2014 chapter 5 (the four cases of Table
# 5.1 ordered, Case 4 / Case 1 >= 10, every output written, the KRL program passing
# `redpost check`), determinism for a given seed on a coarse copy of the job, and bad input
# (exit 2, a clear message, nothing written).
#
#   test_place.sh <path-to-redpost> <source-dir>
. "$(dirname "$0")/harness.sh" cli.place "$@"
JOB="$SRC/examples/placement/caro2014_job.xml"
CELL="$SRC/definitions/cells/caro2014_kr270_table.xml"
[[ -f "$JOB" ]] || { echo "cli.place: FAIL: no job file '$JOB'" >&2; exit 1; }

# A copy of the job with the cell path made absolute; extra sed expressions edit it further.
job_variant() {
  local out=$1
  shift
  sed -e "s|\"../../definitions/cells/|\"$SRC/definitions/cells/|" "$@" "$JOB" >"$out"
}
# The coarse grid: 4 points per segment, 15 deg spin steps, a short search.
coarse=(-e 's|points_per_segment="20"|points_per_segment="4"|'
        -e 's|step="5deg" max_step="10deg" max_joint_step="20deg"|step="15deg" max_step="30deg" max_joint_step="45deg"|'
        -e 's|global_evaluations="[0-9]*"|global_evaluations="120"|'
        -e 's|local_evaluations="[0-9]*"|local_evaluations="40"|')

begin "the example job: four cases ordered, Case 4 / Case 1 >= 10"
full="$JOB"
if [[ -n "${REDPOST_TEST_LIGHT:-}" ]]; then
  # Sanitizer builds (scripts/reliability.sh) run ~40 times slower: the same path points, 10 deg
  # spin steps and a shorter search (Case 4 / Case 1 is still 11.5).
  full="$TMP/light.xml"
  job_variant "$full" -e 's|step="5deg" max_step="10deg"|step="10deg" max_step="10deg"|' \
    -e 's|global_evaluations="[0-9]*"|global_evaluations="60"|' \
    -e 's|local_evaluations="[0-9]*"|local_evaluations="30"|'
fi
run place "$full" -o "$TMP/res" --json "$TMP/res.json" --report "$TMP/res.html"
expect_rc 0
# The report: four c_i maps, the four cases along the path, the convergence, the top view.
[[ $(grep -o '<svg class="plot"' "$TMP/res.html" | wc -l) -eq 7 ]] || fail "expected 7 plots"
grep -q 'worst_placement_worst_spin' "$TMP/res.html" || fail "no Table 5.1 in the report"
grep -Eq '(src|href)="(https?:)?//' "$TMP/res.html" && fail "the report loads something external"
expect_out "best_placement_best_spin"
for f in placement.csv plans.csv cmap_best.csv cmap_worst.csv convergence.csv \
         CARO2014_PLACEMENT.src CARO2014_PLACEMENT.dat; do
  [[ -s "$TMP/res/$f" ]] || fail "no $f"
done
ls -A "$TMP/res" | grep -q "part~$" && fail "a temporary file was left behind"
python3 - "$TMP/res.json" "$TMP/res/plans.csv" <<'PY' || fail "JSON report"
import csv, json, sys
j = json.load(open(sys.argv[1]))
p = j["placement"]
for k in ("x_mm", "y_mm", "z_mm", "q4"):
    assert isinstance(p[k], (int, float)), k
# Eqs. 5.13-5.15 of the example job, in F0.
assert -300 <= p["x_mm"] <= 300 and -2240 <= p["y_mm"] <= -1640 and -602 <= p["z_mm"] <= -214
names = ["best_placement_best_spin", "best_placement_worst_spin",
         "worst_placement_best_spin", "worst_placement_worst_spin"]
f = [j["cases"][n]["f_mqc_mm"] for n in names]
m = [j["cases"][n]["max_c_mm"] for n in names]
print("f_MQC:", " ".join(f"{v:.4f}" for v in f), f"ratio {f[3] / f[0]:.2f}")
assert f[0] < f[1] < f[2] < f[3], f
assert f[3] / f[0] >= 10.0, f[3] / f[0]
assert all(mi >= fi and mi <= 3.0 for fi, mi in zip(f, m)), m  # c_max = 3 mm
for side in ("best", "worst"):
    h = j["convergence"][side]["history"]
    assert h and h[-1]["evaluations"] == j["convergence"][side]["evaluations"]
    vals = [e["best_f_mqc_mm"] for e in h if e["best_f_mqc_mm"] is not None]
    # Monotone: the best so far never gets worse.
    assert all((b <= a) if side == "best" else (b >= a) for a, b in zip(vals, vals[1:])), vals
# plans.csv: the mean of the plan's c column is the case's f_MQC.
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 100, len(rows)
for n, fv in zip(names, f):
    mean = sum(float(r[n + "_c_mm"]) for r in rows) / len(rows)
    assert abs(mean - fv) < 1e-5, (n, mean, fv)
PY
passed

begin "the KRL program passes redpost check against the cell"
run check "$TMP/res" --cell "$CELL"
expect_rc 0
passed

begin "the same seed gives the same result, another seed runs too"
job_variant "$TMP/coarse.xml" "${coarse[@]}"
run place "$TMP/coarse.xml" -o "$TMP/c1"
expect_rc 0
run place "$TMP/coarse.xml" -o "$TMP/c2"
expect_rc 0
cmp -s "$TMP/c1/placement.csv" "$TMP/c2/placement.csv" || fail "placement.csv differs between runs"
cmp -s "$TMP/c1/plans.csv" "$TMP/c2/plans.csv" || fail "plans.csv differs between runs"
run place "$TMP/coarse.xml" -o "$TMP/c3" --seed 7
expect_rc 0
passed

begin "malformed XML: exit 2 with file:line, nothing written"
job_variant "$TMP/bad.xml" -e 's|<contour points_per_segment="20" mode="down">|<contour points_per_segment="20" mode="down"|'
run place "$TMP/bad.xml" -o "$TMP/bad_out"
expect_rc 2
grep -q "bad.xml:[0-9]*: not well-formed XML" "$TMP/err" || fail "message"
[[ ! -e "$TMP/bad_out" ]] || fail "output directory created"
passed

begin "missing cell"
job_variant "$TMP/nocell.xml" -e 's|caro2014_kr270_table.xml|no_such_cell.xml|'
run place "$TMP/nocell.xml" -o "$TMP/nocell_out"
expect_rc 2
expect_err "no_such_cell.xml' does not exist"
passed

begin "impossible bounds"
job_variant "$TMP/bounds.xml" -e 's|z_min="-0.602m" z_max="-0.214m"|z_min="-0.2m" z_max="-0.6m"|'
run place "$TMP/bounds.xml" -o "$TMP/bounds_out"
expect_rc 2
expect_err "z: min is above max"
passed

begin "no feasible placement: exit 2, the output directory left as it was"
job_variant "$TMP/far.xml" "${coarse[@]}" -e 's|y_min="-2.24m" y_max="-1.64m"|y_min="-7m" y_max="-6.5m"|'
mkdir -p "$TMP/far_out"
run place "$TMP/far.xml" -o "$TMP/far_out" --json "$TMP/far.json"
expect_rc 2
expect_err "no feasible placement found"
[[ -z "$(ls -A "$TMP/far_out")" ]] || fail "files written into the output directory"
[[ ! -e "$TMP/far.json" ]] || fail "JSON written"
passed

echo "cli.place: $checks checks passed"
