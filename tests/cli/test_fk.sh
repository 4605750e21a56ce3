#!/usr/bin/env bash
# cli.fk: `redpost fk` driven as a user drives it.
#
#   test_fk.sh <path-to-redpost> <source-dir>
#
# Checks the KR15/2 home pose, the input syntax (commas, spaces, '#' comments, blank lines), the
# Jacobian layout, the printed precision, and the exit codes and messages on bad input.
. "$(dirname "$0")/harness.sh" cli.fk "$@"
KR15="$SRC/definitions/cells/kr15_2.xml"
ANDRES="$SRC/definitions/cells/andres2011_kr15_track_table.xml"
[[ -f "$KR15" ]] || { echo "cli.fk: FAIL: no cell file '$KR15'" >&2; exit 1; }


expect_lines() {  # number of lines on stdout
  local n
  n=$(awk 'END { print NR }' "$TMP/out")
  [[ "$n" -eq "$1" ]] || fail "expected $1 line(s) on stdout, got $n"
}

expect_err_contains() {
  [[ "$ERR" == *"$1"* ]] || fail "stderr does not contain '$1'"
}

# Every field on every line of stdout is a number.
expect_numeric() {
  awk '{ for (i = 1; i <= NF; i++)
           if ($i !~ /^-?([0-9]+\.?[0-9]*|\.[0-9]+)(e[-+]?[0-9]+)?$/) { print i ": " $i; exit 1 } }' \
    "$TMP/out" >"$TMP/bad_field" || fail "a field is not a number: $(cat "$TMP/bad_field")"
}

# shellcheck disable=SC2016  # an awk program, expanded by awk
HOME_POSE_CHECK='
  function abs(x) { return x < 0 ? -x : x }
  NR == 1 {
    if (NF != 12) { print "expected 12 fields, got " NF; bad = 1; exit }
    if (abs($1 - 1040) > 1e-9) { print "x = " $1 ", expected 1040"; bad = 1 }
    if (abs($2) > 1e-9)        { print "y = " $2 ", expected 0"; bad = 1 }
    if (abs($3 - 1480) > 1e-9) { print "z = " $3 ", expected 1480"; bad = 1 }
    n = split("0 0 1 0 1 0 -1 0 0", R, " ")
    for (i = 1; i <= 9; i++)
      if (abs($(3 + i) - R[i]) > 1e-12) {
        print "r" int((i - 1) / 3) + 1 (i - 1) % 3 + 1 " = " $(3 + i) ", expected " R[i]; bad = 1
      }
  }
  END { exit bad }'

# --- (a) the KR15/2 home pose in controller units ------------------------------------------------
begin "(a) home pose, --axes"
run_with_stdin $'0 -90 90 0 0 0\n' fk --cell "$KR15" --axes
expect_rc 0
expect_lines 1
expect_numeric
awk "$HOME_POSE_CHECK" "$TMP/out" >"$TMP/why" || fail "$(cat "$TMP/why")"
[[ -z "$ERR" ]] || fail "unexpected output on stderr"
AXES_HOME=$OUT
passed

# --- (b) DH units, and the input syntax ---------------------------------------------------------
# The same posture in DH units: theta_3 = A3 - 90 deg, theta_4 = A4 + 180 deg.
begin "(b) DH units, plain line"
run_with_stdin $'0 -1.5707963267948966 0 3.141592653589793 0 0\n' fk --cell "$KR15"
expect_rc 0
expect_lines 1
awk "$HOME_POSE_CHECK" "$TMP/out" >"$TMP/why" || fail "$(cat "$TMP/why")"
PLAIN=$OUT
[[ "$PLAIN" == "$AXES_HOME" ]] || fail "DH-unit output differs from the --axes output: '$AXES_HOME'"
passed

begin "(b) DH units with commas, spaces, tabs, comments and blank lines"
run_with_stdin $'# KR15/2 home in DH units\n\n   \n  0 ,  -1.5707963267948966,0,\t3.141592653589793 , +0,0   # trailing comment\n# done\n' \
  fk --cell "$KR15"
expect_rc 0
expect_lines 1
[[ "$OUT" == "$PLAIN" ]] || fail "output differs from that of the plain line: '$PLAIN'"
passed

begin "(b) one output line per input vector, in order"
run_with_stdin $'0 -90 90 0 0 0\n# between\n30 -60 100 20 -45 -10\n\n0 -90 90 0 0 0' fk --cell "$KR15" --axes
expect_rc 0
expect_lines 3
[[ "$(sed -n 1p "$TMP/out")" == "$AXES_HOME" ]] || fail "line 1 is not the home pose"
[[ "$(sed -n 3p "$TMP/out")" == "$AXES_HOME" ]] || fail "line 3 (last input, no newline) is not the home pose"
[[ "$(sed -n 2p "$TMP/out")" != "$AXES_HOME" ]] || fail "line 2 equals the home pose"
passed

# --- (c) the Jacobian: 6 * n numbers per line ---------------------------------------------------
begin "(c) --jacobian, kr15_2 (n = 6)"
run_with_stdin $'0 -90 90 0 0 0\n30 -60 100 20 -45 -10\n' fk --cell "$KR15" --axes --jacobian
expect_rc 0
expect_lines 2
expect_numeric
awk 'NF != 36 { print "line " NR ": " NF " numbers"; bad = 1 } END { exit bad }' "$TMP/out" \
  >"$TMP/why" || fail "expected 36 numbers per line: $(cat "$TMP/why")"
passed

begin "(c) --jacobian, andres2011 (n = 9)"
run_with_stdin $'0 500 0 -90 90 0 90 0 0\n' fk --cell "$ANDRES" --axes --jacobian
expect_rc 0
expect_lines 1
expect_numeric
awk 'NF != 54 { print "line " NR ": " NF " numbers"; bad = 1 } END { exit bad }' "$TMP/out" \
  >"$TMP/why" || fail "expected 54 numbers per line: $(cat "$TMP/why")"
passed

# --- (d) 12 significant digits ------------------------------------------------------------------
begin "(d) 12 significant digits"
run_with_stdin $'30 -60 100 20 -45 -10\n' fk --cell "$KR15" --axes
expect_rc 0
expect_lines 1
expect_numeric
X=$(awk '{ print $1 }' "$TMP/out")
[[ "$X" == "1159.98608733" ]] || fail "x printed as '$X', expected '1159.98608733'"
# No field carries more than 12 significant digits.
awk '{ for (i = 1; i <= NF; i++) {
         m = $i; sub(/^-/, "", m); sub(/e.*$/, "", m); sub(/\./, "", m); sub(/^0+/, "", m)
         if (length(m) > 12) { print "field " i " = " $i; bad = 1 } } }
     END { exit bad }' "$TMP/out" >"$TMP/why" || fail "more than 12 digits: $(cat "$TMP/why")"
passed

# --- (e) bad input lines: exit 2, '<stdin>:LINE:' on stderr, the good lines still printed -------
begin "(e) a non-number on line 3"
run_with_stdin $'0 -90 90 0 0 0\n30 -60 100 20 -45 -10\n0 -90 abc 0 0 0\n0 -90 90 0 0 0\n' \
  fk --cell "$KR15" --axes
expect_rc 2
expect_lines 2
expect_err_contains "<stdin>:3:"
expect_err_contains "'abc' is not a number"
[[ "$(sed -n 1p "$TMP/out")" == "$AXES_HOME" ]] || fail "the first good line is not on stdout"
passed

begin "(e) a number with trailing garbage"
run_with_stdin $'0 -90 90 0 0 0\n0 -90 12a 0 0 0\n' fk --cell "$KR15" --axes
expect_rc 2
expect_lines 1
expect_err_contains "<stdin>:2:"
expect_err_contains "'12a' is not a number"
passed

begin "(e) a wrong count on line 3"
run_with_stdin $'0 -90 90 0 0 0\n0 -90 90 0 0 0\n0 -90 90 0 0\n' fk --cell "$KR15" --axes
expect_rc 2
expect_lines 2
expect_err_contains "<stdin>:3:"
expect_err_contains "expected 6 values"
expect_err_contains "got 5"
passed

begin "(e) too many values"
run_with_stdin $'0 -90 90 0 0 0 0\n' fk --cell "$KR15"
expect_rc 2
expect_lines 0
expect_err_contains "<stdin>:1:"
expect_err_contains "got 7"
passed

begin "(e) nan on line 3"
run_with_stdin $'0 -90 90 0 0 0\n0 -90 90 0 0 0\nnan -90 90 0 0 0\n' fk --cell "$KR15" --axes
expect_rc 2
expect_lines 2
expect_err_contains "<stdin>:3:"
expect_err_contains "'nan' is not a finite number"
passed

begin "(e) inf"
run_with_stdin $'0 -90 90 0 0 -inf\n' fk --cell "$KR15" --axes
expect_rc 2
expect_lines 0
expect_err_contains "<stdin>:1:"
expect_err_contains "'-inf' is not a finite number"
passed

begin "(e) blank and comment lines count in the line number"
run_with_stdin $'# header\n\n0 -90 90 0 0 0\n   \n0 -90 x 0 0 0\n' fk --cell "$KR15" --axes
expect_rc 2
expect_lines 1
expect_err_contains "<stdin>:5:"
passed

# --- (f) a missing cell file --------------------------------------------------------------------
begin "(f) missing cell file"
MISSING="$TMP/no_such_cell.xml"
run_with_stdin $'0 0 0 0 0 0\n' fk --cell "$MISSING"
expect_rc 2
expect_lines 0
expect_err_contains "$MISSING"
expect_err_contains "no such file"
passed

# --- (g) a missing --cell option ----------------------------------------------------------------
begin "(g) missing --cell"
run_with_stdin $'0 0 0 0 0 0\n' fk --axes
[[ "$RC" -ne 0 ]] || fail "expected a non-zero exit code"
expect_rc 2
expect_lines 0
expect_err_contains "--cell"
passed

# --- (e, last) a doubled sign -------------------------------------------------------------------
# Kept last so that every check above has run if this one fails.
begin "(e) a doubled sign '+-5' is not a number"
run_with_stdin $'0 -90 90 0 0 0\n+-5 -90 90 0 0 0\n' fk --cell "$KR15" --axes
expect_rc 2
expect_lines 1
expect_err_contains "<stdin>:2:"
expect_err_contains "'+-5' is not a number"
passed

echo "cli.fk: all $checks checks passed"
