#!/usr/bin/env bash
# The adversarial shapes of issue 48 in the reliability suite: every motion at one point, a path
# back and forth over itself, all motions on one line, a fine finishing raster, and the plain
# raster, each 20 000 motions split into parts as redpost splits a program
# (tests/bench/make_shape_krl.py). `check` passes each; `diff` of each against itself is equal,
# and against a copy moved by up to 0.01 mm is different. The work is read from the diff's own
# count, not timed: the path search examines at most 256 segments per point (PathWindow::
# kMaxExamined), about one per point against itself (before issue 48: every pass through a place,
# up to the 20 000 of the window), and only the shapes with no two points alike in one place may
# reach the bound.
#
# Usage: test_diff_shapes.sh REDPOST SOURCE_DIR WORK_DIR
set -uo pipefail
redpost=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
n=20000
fail=0
# json FILE KEY: the value of "path": {KEY: ...} in a diff's JSON report.
json() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['path'][sys.argv[2]])" "$1" "$2"; }
for shape in raster point backforth line finish; do
  python3 "$src/tests/bench/make_shape_krl.py" "$shape" "$n" "$work/$shape" --part 5000
  python3 "$src/tests/bench/make_shape_krl.py" "$shape" "$n" "$work/${shape}_moved" --part 5000 \
    --jitter 0.01
  a=$work/$shape/SHAPE.src b=$work/${shape}_moved/SHAPE.src
  "$redpost" check "$a" >"$work/$shape.check" 2>&1
  rc=$?
  ((rc == 0)) || { echo "FAIL $shape: check exit $rc: $(tail -2 "$work/$shape.check")"; fail=1; }
  "$redpost" diff --json "$a" "$a" >"$work/$shape.self.json" 2>"$work/$shape.self.err"
  rc=$?
  if ((rc != 0)); then
    echo "FAIL $shape: diff against itself exit $rc: $(head -c 300 "$work/$shape.self.err")"
    fail=1
    continue
  fi
  self=$(json "$work/$shape.self.json" examined)
  "$redpost" diff --json "$a" "$b" >"$work/$shape.moved.json" 2>"$work/$shape.moved.err"
  rc=$?
  if ((rc != 1)); then
    echo "FAIL $shape: diff against the moved copy exit $rc (expected 1: different)"
    fail=1
    continue
  fi
  moved=$(json "$work/$shape.moved.json" examined)
  capped=$(json "$work/$shape.moved.json" capped)
  # Both ways: each point of A against B's path and each of B against A's.
  points=$((2 * n))
  echo "diff shapes: $shape: examined per point $(awk -v e="$self" -v p="$points" 'BEGIN{printf "%.2f", e/p}') against itself, $(awk -v e="$moved" -v p="$points" 'BEGIN{printf "%.2f", e/p}') against the moved copy, $capped capped"
  if ((self > 2 * points)); then
    echo "FAIL $shape: against itself the search examined $self segments for $points points"
    fail=1
  fi
  if ((moved > 256 * points)); then
    echo "FAIL $shape: the search examined $moved segments for $points points (bound 256 each)"
    fail=1
  fi
  case $shape in
    point | backforth) ;;  # the moved copy is a cloud / a jittered retrace: the bound may apply
    *) if ((capped != 0)); then echo "FAIL $shape: $capped points capped"; fail=1; fi ;;
  esac
done
((fail == 0)) && echo "diff shapes: all bounded"
exit "$fail"
