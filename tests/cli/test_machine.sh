#!/usr/bin/env bash
# Programs a real cell can run (issue 16), judged from the written files as a controller would:
# the shipped template sets by name, the byte budget on a 100 000-pose program (and `redpost
# check` of every file), a program above the old 16 MiB reading limit read by check and diff,
# and, where ../shared/evaldata is present, every real CAM file with the default options: the
# statements a controller accepts (tests/cli/machine_check.py), a $TOOL per CL tool and the
# coupled base on the drill job, and every PTP interpolated in joint space through `redpost fk`.
#
# Usage: test_machine.sh REDPOST SOURCE_DIR
. "$(dirname "$0")/harness.sh" cli.machine "$@"
cell=$SRC/definitions/cells/andres2011_kr15_track_table.xml
check_py=$SRC/tests/cli/machine_check.py
py=python3

begin "a shipped template set by its name, in convert and in nx_replay"
mkdir -p "$TMP/named" "$TMP/replay"
run convert "$SRC/examples/cl/pocket_arcs.apt" --cell "$cell" --krl krc4_spline -o "$TMP/named" \
  --name NAMED -q
expect_rc 0
grep -q '^SPLINE' "$TMP/named/NAMED.src" || fail "krc4_spline by name gave no SPLINE block"
"${TCLSH:-tclsh}" "$SRC/tcl/nx_replay.tcl" --lib "$(dirname "$BIN")" --cell "$cell" --krl krc4_spline \
  -o "$TMP/replay" --name NAMED -q "$SRC/examples/cl/pocket_arcs.apt" >"$TMP/out" 2>"$TMP/err" ||
  fail "nx_replay --krl krc4_spline: $(cat "$TMP/err")"
cmp -s "$TMP/named/NAMED.src" "$TMP/replay/NAMED.src" || fail "nx_replay and convert differ"
passed

begin "100 000 poses: parts within 512 KiB that end out of the material, and check passes them"
# A raster that lifts 20 mm at the end of every line: each part must end where a lift ended
# (its last motion at the lifted z), never in the cut.
$py "$SRC/tests/bench/make_raster_apt.py" 100000 "$TMP/raster.apt" --lift
mkdir -p "$TMP/raster"
# One motion per CL point (--fit-tol 0, no point reduction): the sizes of the largest program.
run convert "$TMP/raster.apt" --cell "$cell" -o "$TMP/raster" --name RASTER --fit-tol 0
expect_rc 0
files=0 total=0
for f in "$TMP/raster"/*.src "$TMP/raster"/*.dat; do
  size=$(stat -c %s "$f")
  [[ "$size" -le 524288 ]] || fail "$(basename "$f") has $size bytes, more than 512 KiB"
  files=$((files + 1)) total=$((total + size))
done
[[ "$files" -ge 20 ]] || fail "expected a main program and at least nine parts, got $files files"
parts=("$TMP/raster"/RASTER_P*.src)
for f in "${parts[@]:0:${#parts[@]}-1}"; do  # the last part ends where the CL file does
  last=$(grep -E '^(LIN|PTP) ' "$f" | tail -1)
  [[ "$last" == *"Z 80.000"* ]] || fail "$(basename "$f") ends in the cut: $last"
done
grep -q "part boundaries fall where the tool may be in the material" "$TMP/err" &&
  fail "a boundary in the cut was reported: $(cat "$TMP/err")"
# The program is larger than the set's program memory: said, with its size, which check
# recounts from the files.
grep -q "the program's files take $total bytes, more than the 3000000 bytes of program memory" \
  "$TMP/err" || fail "no program memory warning with $total bytes: $(cat "$TMP/err")"
run check "$TMP/raster" --max-bytes 524288
expect_rc 0
run check "$TMP/raster" --max-bytes 524288 --program-memory 3000000
expect_rc 1
grep -q "RASTER.src:1: the program's $files files take $total bytes" "$TMP/out" ||
  fail "check counts otherwise: $(cat "$TMP/out")"
$py "$check_py" statements "$TMP/raster" >"$TMP/out" 2>&1 || fail "statements: $(cat "$TMP/out")"
rm -rf "$TMP/raster"
# Without the lifts there is no place out of the material: the boundaries fall in the cut, and
# the warning names the CL lines.
$py "$SRC/tests/bench/make_raster_apt.py" 60000 "$TMP/zigzag.apt"
mkdir -p "$TMP/zigzag"
run convert "$TMP/zigzag.apt" --cell "$cell" -o "$TMP/zigzag" --name ZIGZAG --fit-tol 0
expect_rc 0
grep -qE "zigzag.apt: [0-9]+ of the [0-9]+ part boundaries fall where the tool may be in the material \(after CL line [0-9]+.*continues the cut without a stop" \
  "$TMP/err" || fail "no warning of boundaries in the cut: $(cat "$TMP/err")"
# The part after such a boundary continues the cut: its first motion is a LIN (no exact-stop
# PTP), after no INI fold; the part before ends on a blended LIN. check reads it all, in order.
zparts=("$TMP/zigzag"/ZIGZAG_P*.src)
[[ ${#zparts[@]} -ge 2 ]] || fail "the zigzag was not split"
for ((k = 1; k < ${#zparts[@]}; ++k)); do
  first=$(grep -m1 -E '^(LIN|PTP) ' "${zparts[k]}")
  [[ "$first" == LIN* ]] || fail "$(basename "${zparts[k]}") starts with $first"
  if grep -q "INITMOV" "${zparts[k]}"; then fail "$(basename "${zparts[k]}") has an INI fold"; fi
  last=$(grep -E '^(LIN|PTP) ' "${zparts[k - 1]}" | tail -1)
  [[ "$last" == *" C_DIS"* ]] || fail "$(basename "${zparts[k - 1]}") ends on $last"
done
run check "$TMP/zigzag"
expect_rc 0
$py "$check_py" statements "$TMP/zigzag" >"$TMP/out" 2>&1 || fail "statements: $(cat "$TMP/out")"
rm -rf "$TMP/zigzag"
# --split N: the boundaries fall every N motions, and the warning says that, not the budget.
mkdir -p "$TMP/every"
run convert "$SRC/examples/cl/long_pass.apt" --cell "$cell" -o "$TMP/every" --split 150 --fit-tol 0
expect_rc 0
grep -q "2 of the 2 part boundaries fall where the tool may be in the material (after CL line [0-9]*, [0-9]*): --split 150 ends a part after every 150 motions, so the part after each continues the cut without a stop" \
  "$TMP/err" || fail "no --split warning: $(cat "$TMP/err")"
rm -rf "$TMP/every"
passed

begin "a program above the old 16 MiB limit is read by check (too large: a finding) and diff"
mkdir -p "$TMP/big" "$TMP/big2"
$py "$SRC/tests/bench/make_raster_apt.py" 170000 "$TMP/big.apt"
run convert "$TMP/big.apt" --cell "$cell" -o "$TMP/big" --name BIG --max-bytes 40000000 --fit-tol 0 -q
expect_rc 0
size=$(stat -c %s "$TMP/big/BIG.src")
[[ "$size" -gt 16777216 ]] || fail "BIG.src has only $size bytes"
run check "$TMP/big/BIG.src"
expect_rc 1
expect_out "more than the limit of 5000000"
cp "$TMP/big/"* "$TMP/big2/"
run diff "$TMP/big/BIG.src" "$TMP/big2/BIG.src"
expect_rc 0
rm -rf "$TMP/big" "$TMP/big2" "$TMP/big.apt"
passed

eval_dir=$SRC/../shared/evaldata
if [[ ! -d "$eval_dir" ]]; then
  echo "cli.machine: note: ../shared/evaldata not present, the real CAM files are skipped"
  echo "cli.machine: $checks checks passed"
  exit 0
fi

begin "every real CAM file converts with the default options into statements a KRC accepts"
for f in "$eval_dir"/apt/*.apt "$eval_dir"/clsf/*; do
  name=$(basename "$f")
  out=$TMP/eval_$name
  mkdir -p "$out"
  run convert "$f" --cell "$cell" -o "$out" --name EVAL --joints-csv "$TMP/joints_$name.csv" -q
  case $name in
    swcam_cutcom_multi_op.apt)
      # Tool 20 has no TOOL_DATA without a tool table; with one, the cycle left on at a tool
      # change is refused with advice that does not drag the drill across the part.
      expect_rc 2
      expect_err "tool 20"
      printf '<tool-table>\n' >"$TMP/tools.xml"
      for t in 2 15 18 20; do
        printf '  <tool number="%s" data="%s" length="100"/>\n' "$t" $((t % 16 + 1)) >>"$TMP/tools.xml"
      done
      printf '</tool-table>\n' >>"$TMP/tools.xml"
      run convert "$f" --cell "$cell" -o "$out" --name EVAL --tools "$TMP/tools.xml" -q
      expect_rc 2
      expect_err "swcam_cutcom_multi_op.apt:479"
      expect_err "Do not only insert CYCLE/OFF before the tool change"
      [[ -z "$(ls -A "$out")" ]] || fail "$name: files left after the refusal: $(ls -A "$out")"
      continue ;;
    nx_variable_contour_5axis.cls)
      # Its MCS is z-down: with the MCS as the workpiece frame the tool would point down.
      expect_rc 2
      expect_err "--msys apply"
      expect_err "--placement"
      run convert "$f" --cell "$cell" -o "$out" --name EVAL --msys apply \
        --joints-csv "$TMP/joints_$name.csv" -q
      ;;
  esac
  expect_rc 0
  run check "$out"
  expect_rc 0
  $py "$check_py" statements "$out" >"$TMP/out" 2>&1 || fail "$name: $(cat "$TMP/out")"
  echo "cli.machine: $name: converted, $(grep -cE '^(PTP|LIN|SLIN|CIRC) ' "$out/EVAL.src") motions"
done
passed

begin "the drill job: a \$TOOL per CL tool, the coupled base, no free text as code"
src=$TMP/eval_swcam_drill_cycles.apt/EVAL.src
grep -q '^\$TOOL = TOOL_DATA\[15\]' "$src" || fail "no \$TOOL = TOOL_DATA[15]"
grep -q '^\$TOOL = TOOL_DATA\[16\]' "$src" || fail "no \$TOOL = TOOL_DATA[16]"
grep -q '^\$BASE = EK(MACHINE_DEF\[2\].ROOT, MACHINE_DEF\[2\].MECH_TYPE, BASE_DATA\[1\])' "$src" ||
  fail "no coupled base"
grep -q '^; \[HOLDER=C40-32ERP412\] 14MM X 60DEG HSS CENTERDRILL' "$src" ||
  fail "the INSERT text is not a comment"
passed

begin "no PTP leaves a hole's axis below the part's top (joint interpolation through FK)"
for name in swcam_drill_cycles.apt swcam_gasket_circles.apt; do
  $py "$check_py" ptps "$TMP/eval_$name/EVAL.src" "$TMP/joints_$name.csv" "$eval_dir/apt/$name" \
    "$BIN" "$cell" 119.7 >"$TMP/out" 2>&1 || fail "$name: $(cat "$TMP/out")"
  echo "cli.machine: $name: $(cat "$TMP/out")"
done
passed

begin "compensated against the arm's deflection (issue 20): the PTPs still keep to the holes' axes"
name=swcam_gasket_circles.apt
mkdir -p "$TMP/comp_$name"
run convert "$eval_dir/apt/$name" --cell "$cell" -o "$TMP/comp_$name" --name EVAL --compensate \
  --joints-csv "$TMP/comp_joints.csv" -q
expect_rc 0
$py "$check_py" ptps "$TMP/comp_$name/EVAL.src" "$TMP/comp_joints.csv" "$eval_dir/apt/$name" \
  "$BIN" "$cell" 119.7 >"$TMP/out" 2>&1 || fail "compensated $name: $(cat "$TMP/out")"
echo "cli.machine: compensated $name: $(cat "$TMP/out")"
$py "$check_py" statements "$TMP/comp_$name" >"$TMP/out" 2>&1 || fail "compensated $name: $(cat "$TMP/out")"
passed

echo "cli.machine: $checks checks passed"
