#!/usr/bin/env bash
# `redpost convert` driven as a user drives it: success, bad input, unreachable paths, the
# licensed sample files, the locale. Usage: test_convert.sh REDPOST SOURCE_DIR
set -uo pipefail
redpost=$1 src=$2
cell=$src/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
checks=0 failures=0
pass() { checks=$((checks + 1)); }
fail() { checks=$((checks + 1)); failures=$((failures + 1)); echo "FAIL: $*"; }

run() {  # run NAME ARGS...: stdout/stderr to $work/NAME.{out,err}, exit code in $rc
  local name=$1; shift
  "$redpost" "$@" >"$work/$name.out" 2>"$work/$name.err"
  rc=$?
}

# 1. Success: files, summary, joints CSV header.
mkdir -p "$work/ok"
run ok convert "$src/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$work/ok" --name POCKET \
  --joints-csv "$work/ok/joints.csv"
[ "$rc" -eq 0 ] && pass || fail "pocket: exit $rc: $(cat "$work/ok.err")"
[ -s "$work/ok/POCKET.src" ] && [ -s "$work/ok/POCKET.dat" ] && pass || fail "pocket: no .src/.dat"
grep -q "^poses [0-9]" "$work/ok.out" && pass || fail "pocket: no summary: $(cat "$work/ok.out")"
head -1 "$work/ok/joints.csv" | grep -q "^pose,cl_line,time_s,theta_M,d_L,theta_1" && pass ||
  fail "joints csv header: $(head -1 "$work/ok/joints.csv")"
ls -a "$work/ok" | grep -q "~" && fail "temporary files left: $(ls -a "$work/ok")" || pass

# 2. The name is derived from the input when --name is absent.
mkdir -p "$work/derived"
run derived convert "$src/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$work/derived" -q
[ "$rc" -eq 0 ] && [ -s "$work/derived/pocket_arcs.src" ] && pass ||
  fail "derived name: $(ls "$work/derived") $(cat "$work/derived.err")"

# 3. Locale: byte-identical output under a German locale (decimal comma).
if locale -a 2>/dev/null | grep -qi '^de_DE\.utf-\?8$'; then
  mkdir -p "$work/de"
  LC_ALL=de_DE.UTF-8 "$redpost" convert "$src/examples/cl/pocket_arcs.apt" --cell "$cell" \
    -o "$work/de" --name POCKET -q
  cmp -s "$work/ok/POCKET.src" "$work/de/POCKET.src" && cmp -s "$work/ok/POCKET.dat" "$work/de/POCKET.dat" &&
    pass || fail "output differs under LC_ALL=de_DE.UTF-8"
else
  echo "note: de_DE.UTF-8 not installed, locale check skipped"
fi

# 4. Bad input: exit 2, a message naming the file (and line where there is one), no output.
expect_error() {  # expect_error NAME PATTERN ARGS...
  local name=$1 pattern=$2; shift 2
  mkdir -p "$work/$name.dir"
  run "$name" convert "$@" -o "$work/$name.dir"
  if [ "$rc" -ne 2 ]; then fail "$name: exit $rc, expected 2: $(cat "$work/$name.err")"; return; fi
  if ! grep -Eq "$pattern" "$work/$name.err"; then
    fail "$name: message does not match '$pattern': $(cat "$work/$name.err")"; return
  fi
  if [ -n "$(ls -A "$work/$name.dir")" ]; then fail "$name: left files: $(ls -A "$work/$name.dir")"; return; fi
  pass
}
expect_error missing "nowhere\.apt: no such file" "$work/nowhere.apt" --cell "$cell"
expect_error directory "is a directory" "$work" --cell "$cell"
# The KR C4 sets write the numbers of the base and the tool ($ACT_BASE, $ACT_TOOL, $LOAD): an
# expression that is no BASE_DATA / TOOL_DATA entry has none, and is refused before anything is
# written; an entry is read with its blanks and case.
expect_error tool_expression "the tool is not a TOOL_DATA\[n\] entry: give --tool TOOL_DATA\[n\]" \
  "$src/examples/cl/pocket_arcs.apt" --cell "$cell" --tool 'MY_SPINDLE:TOOL_DATA[2]'
expect_error base_expression "the base is not a BASE_DATA\[n\] entry: give --base BASE_DATA\[n\]" \
  "$src/examples/cl/pocket_arcs.apt" --cell "$cell" --base 'BASE_DATA[2]:MY_SHIFT'
mkdir -p "$work/numbers"
run numbers convert "$src/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$work/numbers" \
  --name NUMBERS -q --base ' base_data[ 3 ] ' --tool 'TOOL_DATA[2]'
[ "$rc" -eq 0 ] && grep -q '^\$ACT_BASE = 3' "$work/numbers/NUMBERS.src" &&
  sed -n '/^\$TOOL = TOOL_DATA\[2\]/,/^\$ACT_TOOL/p' "$work/numbers/NUMBERS.src" | head -4 |
  tr -d '\r' | paste -sd'|' | grep -qx '\$TOOL = TOOL_DATA\[2\]|\$LOAD = LOAD_DATA\[2\]|CONTINUE|\$ACT_TOOL = 2' &&
  pass || fail "numbers: exit $rc: $(cat "$work/numbers.err") $(head -24 "$work/numbers/NUMBERS.src")"
expect_error badcell "no_cell\.xml: no such file" "$src/examples/cl/pocket_arcs.apt" --cell "$work/no_cell.xml"
printf 'UNITS/MM\nRAPID\nGOTO/-100,-450,100\nGOTO/-100,abc,100\n' >"$work/malformed.apt"
expect_error malformed "malformed\.apt:4:[0-9]+:" "$work/malformed.apt" --cell "$cell"
printf 'UNITS/MM\nRAPID\nGOTO/-100,-450,100\nFEDRAT/MMPM,1000\nGOTO/-100,-450,60\nGOTO/-100,-450,4000\n' >"$work/far.apt"
expect_error unreachable "far\.apt:6: pose [0-9]+ .*(cannot be reached|leave its limits)" "$work/far.apt" --cell "$cell" --plan local
# The global plan finds no sequence there either, and tracks that stretch pose by pose, which
# fails with the same message.
expect_error unreachable_plan "far\.apt:6: pose [0-9]+ .*(cannot be reached|leave its limits)" "$work/far.apt" --cell "$cell"
printf 'UNITS/MM\n$$ ten metres above the table\nRAPID\nGOTO/0,0,10000\n' >"$work/far2.apt"
expect_error unreachable2 "far2\.apt:4: pose 1 \(the first pose of the path\): the target cannot be reached" "$work/far2.apt" --cell "$cell" --plan local
expect_error unreachable2_plan "far2\.apt:4: pose 1 \(the first pose of the path\): the target cannot be reached.*--placement" "$work/far2.apt" --cell "$cell"
printf 'UNITS/MM\nGOTO/-100,-450,nan\n' >"$work/nan.apt"
expect_error nan "nan\.apt:2:[0-9]+:" "$work/nan.apt" --cell "$cell"
run noout convert "$src/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$work/not/there"
[ "$rc" -eq 2 ] && grep -q "not/there" "$work/noout.err" && pass ||
  fail "missing output dir: exit $rc: $(cat "$work/noout.err")"
expect_error longname "24" "$src/examples/cl/pocket_arcs.apt" --cell "$cell" --name ABCDEFGHIJKLMNOPQRSTUVWXYZ

# 5. Every licensed sample CL file converts, or stops with a precise file:line message; never a
#    crash or a hang. The SolidWorks parts are small and sit at the origin: place them on the
#    table within reach; the NX samples are far larger than this cell and may well be refused.
if [ -d "$src/../shared/evaldata" ]; then
  for f in "$src"/../shared/evaldata/apt/*.apt "$src"/../shared/evaldata/clsf/*; do
    name=$(basename "$f"); mkdir -p "$work/eval_$name"
    timeout 120 "$redpost" convert "$f" --cell "$cell" -o "$work/eval_$name" --name EVAL \
      --placement=-120,-450,40,0,0,0 -q >"$work/eval.out" 2>"$work/eval.err"
    rc=$?
    if [ "$rc" -eq 0 ]; then pass; echo "sample $name: converted"
    elif [ "$rc" -eq 2 ] && grep -Eq "$name:[0-9]+" "$work/eval.err"; then
      pass; echo "sample $name: refused: $(head -1 "$work/eval.err")"
    else fail "sample $name: exit $rc: $(head -3 "$work/eval.err")"; fi
  done
else
  echo "note: ../shared/evaldata not present, sample files skipped"
fi

# 6. --report: an HTML report beside an unchanged program; none after a failed conversion.
mkdir -p "$work/rep"
run rep convert "$src/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$work/rep" --name POCKET \
  --report "$work/rep/report.html" --joints-csv "$work/rep/joints.csv"
[ "$rc" -eq 0 ] && [ -s "$work/rep/report.html" ] && pass || fail "report: exit $rc: $(cat "$work/rep.err")"
cmp -s "$work/ok/POCKET.src" "$work/rep/POCKET.src" && cmp -s "$work/ok/POCKET.dat" "$work/rep/POCKET.dat" &&
  pass || fail "the KRL differs with --report"
# Joints, axis speed fractions, path speed, motion duration against the cycle, 1/kappa_F, external axes, the plan against the
# written joints for each of E1, E2 and the spin, iterations, feed, the clearance between the cell's
# bodies (issue 46) and three toolpath projections.
plots=$(grep -o '<svg class="plot"' "$work/rep/report.html" | wc -l)
[ "$plots" -eq 15 ] && pass || fail "report: $plots plots, expected 15"
# The inlined libraries of the 3D view (<script data-library="...">, three.js) name their
# authors' sites and XML namespaces in comments and strings: the page's own text must not.
urls=$(python3 -c 'import re, sys; sys.stdout.write(re.sub(r"<script data-library=\"[^\"]*\">.*?</script>", "", open(sys.argv[1]).read(), flags=re.S))' "$work/rep/report.html" |
  grep -Eo '(https?|ftp|file)://[^"'"'"' )]*' | grep -vx 'http://www.w3.org/2000/svg' || true)
[ -z "$urls" ] && pass || fail "report refers outside itself: $urls"
# The motion count in the report is the joints log's row count (one row per written motion).
motions=$(($(wc -l <"$work/rep/joints.csv") - 1))
grep -q "motions written</th><td>$motions</td>" "$work/rep/report.html" && pass ||
  fail "report: no 'motions written' row with $motions"
ls -a "$work/rep" | grep -q "tmp" && fail "report: temporary file left: $(ls -a "$work/rep")" || pass
mkdir -p "$work/repfail"
run repfail convert "$work/far.apt" --cell "$cell" -o "$work/repfail" --report "$work/repfail/r.html"
[ "$rc" -eq 2 ] && [ -z "$(ls -A "$work/repfail")" ] && pass ||
  fail "failed conversion with --report: exit $rc, left: $(ls -A "$work/repfail")"
mkdir -p "$work/repbad"
run repbad convert "$src/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$work/repbad" -q \
  --report "$work/repbad/no/such/dir/r.html"
[ "$rc" -eq 2 ] && grep -q "no/such/dir/r.html" "$work/repbad.err" && pass ||
  fail "unwritable report: exit $rc: $(cat "$work/repbad.err")"

echo "cli.convert: $((checks - failures)) passed, $failures failed"
[ "$failures" -eq 0 ]
