#!/usr/bin/env bash
# cli.collision: the collision check as a user meets it (issue 46, docs/collision.md), with the
# project's own set-up (examples/setup/, made by make_setup.py):
# - a set-up where nothing comes near: the same program as without it;
# - a clamp tower the wrist of a plan blind to it runs through (redpost check finds it, at
#   file:line, in the program converted without it), which the plan that knows it keeps clear of,
#   under --plan global and --plan local, proven by redpost check from the KRL text alone;
# - a jaw the spindle must pass through whatever the redundancy does: refused at its CL line with
#   the two bodies, exit 2, nothing written;
# - malformed and truncated STL files refused with file:line or the byte offset, nothing written.
#
# Usage: test_collision.sh REDPOST SOURCE_DIR
. "$(dirname "$0")/harness.sh" cli.collision "$@"

cell=$SRC/definitions/cells/andres2011_kr15_track_table.xml
cl=$SRC/examples/cl/pocket_arcs.apt
setup=$SRC/examples/setup
part=(--part "$setup/pocket_block.stl")

convert_to() {  # convert_to DIR ARGS...: the pocket into DIR
  local dir=$1
  shift
  rm -rf "$dir"
  mkdir -p "$dir"
  run convert "$cl" --cell "$cell" -o "$dir" --name POCKET "$@"
}

begin "without a set-up: the cell's own bodies are checked, the closest pair said"
convert_to "$TMP/blind"
expect_rc 0
expect_out "collisions: 13 bodies"
expect_out "closest"
run check "$TMP/blind/POCKET.src" --cell "$cell" --clearance
expect_rc 0
expect_out "motions checked; closest"
run check "$TMP/blind/POCKET.src" --cell "$cell"
expect_rc 0
[[ ! -s "$TMP/out" ]] || fail "check --cell alone printed: $OUT"
passed

begin "a set-up that comes near nothing: the same program, byte for byte"
convert_to "$TMP/vise" --fixture "$setup/vise_jaw.stl" "${part[@]}"
expect_rc 0
cmp -s "$TMP/blind/POCKET.src" "$TMP/vise/POCKET.src" || fail "the vise jaw changed the program"
run check "$TMP/vise/POCKET.src" --cell "$cell" --fixture "$setup/vise_jaw.stl" "${part[@]}"
expect_rc 0
expect_out "motions checked; closest"
passed

begin "check finds the clamp tower the blind program runs through, at file:line"
run check "$TMP/blind/POCKET.src" --cell "$cell" --fixture "$setup/clamp_tower.stl" "${part[@]}"
expect_rc 1
grep -qE "^$TMP/blind/POCKET.src:[0-9]+: collision: arm_link_5 vs fixture clamp_tower.stl" \
  "$TMP/out" || fail "no collision of the wrist with the clamp tower at file:line"
line=$(grep -m1 -oE "POCKET.src:[0-9]+: collision" "$TMP/out" | grep -oE "[0-9]+")
sed -n "${line}p" "$TMP/blind/POCKET.src" | grep -qE "^(LIN|PTP|CIRC)" ||
  fail "line $line of the program is no motion: $(sed -n "${line}p" "$TMP/blind/POCKET.src")"
passed

for plan in global local; do
  begin "--plan $plan steers clear of the clamp tower, proven from the KRL text"
  convert_to "$TMP/tower_$plan" --fixture "$setup/clamp_tower.stl" "${part[@]}" --plan "$plan"
  expect_rc 0
  expect_out "clamp_tower.stl"
  run check "$TMP/tower_$plan/POCKET.src" --cell "$cell" --fixture "$setup/clamp_tower.stl" \
    "${part[@]}"
  expect_rc 0
  grep -q "collision:" "$TMP/out" && fail "check finds a collision in the avoiding program"
  closest=$(grep -oE "closest [0-9.]+ mm" "$TMP/out" | grep -oE "[0-9.]+")
  awk -v c="$closest" 'BEGIN { exit !(c >= 5.0) }' || fail "closest $closest mm, below the margin"
  # The same CL points: the redundancy moved, not the tool.
  cmp -s "$TMP/blind/POCKET.src" "$TMP/tower_$plan/POCKET.src" &&
    fail "the program did not change"
  passed
done

begin "a jaw the spindle must pass through: refused at its CL line, nothing written"
convert_to "$TMP/jaw" --fixture "$setup/jaw_too_close.stl" "${part[@]}"
expect_rc 2
# Line 11: the rapid down into the pocket brings the spindle (coaxial with the tool, r 60 mm,
# 120 mm above the tip) 50 mm from the jaw's face, below its top; routed up it still must come down.
expect_err "pocket_arcs.apt:11: collision: the spindle and the fixture jaw_too_close.stl"
expect_err "routed up along the tool axis"
expect_err "5 mm must stay between them"
expect_err "Try:"
[[ -z $(ls -A "$TMP/jaw") ]] || fail "files were left: $(ls "$TMP/jaw")"
passed

begin "only a rapid crosses the clamp strap: routed up over it, proven from the KRL text"
cat >"$TMP/strap.apt" <<'APT'
PARTNO/RAPID OVER A CLAMP STRAP
UNITS/MM
CUTTER/10.,0
LOADTL/1
SPINDL/12000,RPM,CLW
RAPID
GOTO/-170,-440,110
RAPID
GOTO/-170,-440,62
FEDRAT/200,MMPM
GOTO/-170,-440,57
FEDRAT/MMPM,900
GOTO/-150,-440,57
RAPID
GOTO/-90,-440,57
FEDRAT/MMPM,900
GOTO/-70,-440,57
RAPID
GOTO/-70,-440,110
SPINDL/OFF
FINI
APT
# The tool as the tool table gives it: check knows a tool by its TOOL_DATA entry.
cat >"$TMP/tools.xml" <<'XML'
<tool-table>
  <tool number="1" data="1" length="119.7" diameter="10" flute-length="30" holder-diameter="40"
        holder-length="40"/>
</tool-table>
XML
strap=(--fixture "$setup/clamp_strap.stl" --tools "$TMP/tools.xml")
rm -rf "$TMP/strap0" "$TMP/strap" && mkdir -p "$TMP/strap0" "$TMP/strap"
run convert "$TMP/strap.apt" --cell "$cell" -o "$TMP/strap0" --name STRAP --tools "$TMP/tools.xml"
expect_rc 0
run check "$TMP/strap0/STRAP.src" --cell "$cell" "${strap[@]}"
expect_rc 1
expect_out "collision: fixture clamp_strap.stl vs tool 1 cutter"
run convert "$TMP/strap.apt" --cell "$cell" -o "$TMP/strap" --name STRAP "${strap[@]}"
expect_rc 0
expect_err "strap.apt:15: this rapid traverse would come closer than 5 mm to a body: it is written 100 mm up"
run check "$TMP/strap/STRAP.src" --cell "$cell" "${strap[@]}"
expect_rc 0
passed

begin "check: a LIN that would take A6 a hair past its limit, going on from the motion before"
# A PTP leaves A6 at -349.99 deg; a LIN to the pose of A6 = -350.01 (the same as +9.99, which a
# solver free to pick A6's turn within the limits would take) makes the controller's A6 go on
# to -350.01 and stop at its software limit switch. A LIN to -349.995 is fine.
e6pos() {  # e6pos "E2 E1 A1 .. A6 spin" (controller units): the TCP as X, Y, Z, A, B, C
  echo "$1" | "$BIN" fk --cell "$cell" --axes | python3 -c '
import math, sys
v = [float(x) for x in sys.stdin.read().split()]
x, y, z, r = v[0], v[1], v[2], v[3:12]
a = math.degrees(math.atan2(r[3], r[0]))
b = math.degrees(math.atan2(-r[6], math.hypot(r[0], r[3])))
c = math.degrees(math.atan2(r[7], r[8]))
print(f"X {x:.3f}, Y {y:.3f}, Z {z:.3f}, A {a:.4f}, B {b:.4f}, C {c:.4f}")'
}
for end in 9.99 -349.995; do
  cat >"$TMP/limit.src" <<KRL
DEF LIMIT()
PTP {E6AXIS: A1 0, A2 -90, A3 90, A4 0, A5 45, A6 -349.99, E1 500, E2 0}
LIN {E6POS: $(e6pos "0 500 0 -90 90 0 45 $end 0"), E1 500, E2 0}
END
KRL
  run check "$TMP/limit.src" --cell "$cell" --clearance
  if [[ $end == 9.99 ]]; then
    expect_rc 1
    expect_out "limit.src:3: joint limit: A6 would pass its limit of -350 deg by 0.01 deg on this LIN"
  else
    expect_rc 0
  fi
done
passed

begin "bad STL files: file:line (ASCII) or the byte offset (binary), exit 2, nothing written"
printf 'solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0\n' >"$TMP/bad.stl"
convert_to "$TMP/bad" --fixture "$TMP/bad.stl"
expect_rc 2
expect_err "bad.stl:5:"
[[ -z $(ls -A "$TMP/bad") ]] || fail "files were left"
python3 - "$TMP/trunc.stl" <<'PY'
import struct, sys
with open(sys.argv[1], "wb") as f:
    f.write(b"binary".ljust(80, b" ") + struct.pack("<I", 10) + b"\0" * 120)
PY
convert_to "$TMP/trunc" --fixture "$TMP/trunc.stl"
expect_rc 2
expect_err "byte offset"
[[ -z $(ls -A "$TMP/trunc") ]] || fail "files were left"
convert_to "$TMP/missing" --part "$TMP/no_such.stl"
expect_rc 2
expect_err "no_such.stl"
run check "$TMP/blind/POCKET.src" --fixture "$setup/vise_jaw.stl"
expect_rc 2
expect_err "need --cell"
passed

echo "cli.collision: $checks checks passed"
