#!/usr/bin/env bash
# The default plan is never beaten by holding the external axes still (issue 47, item 3,
# docs/redundancy.md "Costs"): every example, every real CAM file in ../shared/evaldata and
# seeded random rasters and passes, at their own feeds and at 10 000 mm/min, converted with the
# default plan and with the track and the table held at a grid of values
# (tests/cli/plan_dominance.py: the track at its first-pose value, 300 mm either side and home;
# the table at its first-pose value and every 90 deg). No held program may be faster by more than
# 2 %, travel less and keep 1/kappa_F at or above the plan's threshold 0.3, all at once.
#
# Usage: test_plan_dominance.sh REDPOST SOURCE_DIR
# With REDPOST_QUICK=1 (the suite under the sanitizers, 25 times slower): 4 held settings per
# file instead of 16, and 10 000 mm/min only.
. "$(dirname "$0")/harness.sh" cli.plan_dominance "$@"
py=${PYTHON:-python3}
quick=()
feeds=(0 10000)
if [[ ${REDPOST_QUICK:-0} == 1 ]]; then
  quick=(--small-grid)
  feeds=(10000)
fi
cell=$SRC/definitions/cells/andres2011_kr15_track_table.xml
files=("$SRC"/examples/cl/*)
eval_dir=$SRC/../shared/evaldata
if [[ -d $eval_dir ]]; then
  for f in "$eval_dir"/apt/*.apt "$eval_dir"/clsf/*; do
    case $(basename "$f") in
      # Refused by design: a drilling cycle left on over a tool change (cli.machine covers it).
      swcam_cutcom_multi_op.apt) ;;
      nx_variable_contour_5axis.cls) files+=("$f::--msys apply") ;;
      *) files+=("$f") ;;
    esac
  done
else
  echo "cli.plan_dominance: note: ../shared/evaldata not present, the real CAM files are skipped"
fi
# Seeded random paths the plan was not tuned on: rasters of other widths, spacings, tilts and
# directions, and passes along and across the track.
$py - "$SRC/tests/cli/make_path_apt.py" "$TMP" >"$TMP/generated" <<'PY'
import random, subprocess, sys
gen, tmp = sys.argv[1], sys.argv[2]
rng = random.Random(47)
for k in range(4):
    spec = ["raster", "--width", "%.0f" % rng.uniform(150, 400), "--spacing", "%.1f" % rng.uniform(2, 10),
            "--step", "%.1f" % rng.uniform(0.5, 3), "--tilt", "%.0f" % rng.uniform(0, 25),
            "--angle", "%.0f" % rng.uniform(0, 90)]
    out = "%s/random_raster%d.apt" % (tmp, k)
    subprocess.run([sys.executable, gen] + spec + [out], check=True)
    print(out)
for k in range(2):
    spec = ["pass", "--length", "%.0f" % rng.uniform(300, 1500), "--step", "%.1f" % rng.uniform(1, 5),
            "--tilt", "%.0f" % rng.uniform(-20, 20), "--angle", "%.0f" % rng.uniform(-30, 30)]
    out = "%s/random_pass%d.apt" % (tmp, k)
    subprocess.run([sys.executable, gen] + spec + [out], check=True)
    print(out)
PY
mapfile -t generated <"$TMP/generated"
# cli.speeds' two rasters at 45 deg to the track, judged at 2 % with the shipped files: the
# first was 2.6 % slower than the axes held 300 mm further along (step 3), until a fresh window
# could hold them where its approach puts them (docs/redundancy.md, "Where to hold").
$py "$SRC/tests/cli/make_path_apt.py" raster --spacing 5 --tilt 15 --angle 45 "$TMP/raster45_a.apt"
$py "$SRC/tests/cli/make_path_apt.py" raster --spacing 3 --tilt 25 --angle 45 "$TMP/raster45_b.apt"
files+=("$TMP/raster45_a.apt" "$TMP/raster45_b.apt")

# judge SLACK FILES...: every file converts and no held program beats its default by SLACK.
judge() {
  local slack=$1
  shift
  if ! $py "$SRC/tests/cli/plan_dominance.py" --redpost "$BIN" --cell "$cell" --feed "$feed" \
    --slack "$slack" "${quick[@]}" "$@" >"$TMP/out" 2>"$TMP/err"; then
    fail "a default program is dominated or refused"
  fi
  cat "$TMP/out"
  [[ $(grep -c "| not dominated |" "$TMP/out") -eq $# ]] || fail "not every file judged"
}
for feed in "${feeds[@]}"; do
  begin "the examples and the real CAM files: the default plan is not dominated by held external axes (feed ${feed/#0/own})"
  judge 0.02 "${files[@]}"
  passed
  # The random paths at 2 % too since issue 47's step 4: one raster (238 mm wide at 46 deg) was
  # 2.02 % slower than one held setting until a fresh window could hold the axes where its
  # approach puts them (docs/redundancy.md, "Where to hold"); now as fast.
  begin "seeded random rasters and passes: not dominated (feed ${feed/#0/own})"
  judge 0.02 "${generated[@]}"
  passed
done
begin "the check sees a dominated plan: the stiff preset's raster at 10 000 mm/min"
# The stiff preset trades time for its compliance term; on the 20 000-pose raster at 10 m/min it
# loses 12 % to holding the axes (docs/redundancy.md), which the check must call dominated.
$py "$SRC/tests/bench/make_raster_apt.py" 20000 "$TMP/raster_20k.apt"
set +e
$py "$SRC/tests/cli/plan_dominance.py" --redpost "$BIN" --cell "$cell" --feed 10000 \
  --options "--preset stiff" "${quick[@]}" "$TMP/raster_20k.apt" >"$TMP/out" 2>"$TMP/err"
RC=$?
set -e
[[ $RC -eq 1 ]] || fail "exit $RC, expected 1 (dominated)"
grep -q "| DOMINATED by E1=" "$TMP/out" || fail "no held program named"
passed
echo "cli.plan_dominance: $checks checks passed"
