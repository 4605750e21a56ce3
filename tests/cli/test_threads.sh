#!/usr/bin/env bash
# The whole-path plan's threads change nothing but the time (issue 32): every example and every
# real CAM file of ../shared/evaldata (when present) converted with one thread and with two (the
# pipeline: planning here, tracking and writing on the session's thread) gives the same program,
# byte for byte, and a raster with three too (the lattice's nodes shared as well); a failure on
# the tracking thread is told as one thread tells it (docs/redundancy.md, "Threads").
#
# Usage: test_threads.sh REDPOST SOURCE_DIR
. "$(dirname "$0")/harness.sh" cli.threads "$@"

. "$(dirname "$0")/cam_inputs.sh"
cell=$SRC/definitions/cells/andres2011_kr15_track_table.xml
# A raster of 5000 poses besides: windows whose layers have hundreds of nodes to share.
python3 "$SRC/tests/bench/make_raster_apt.py" 5000 "$TMP/raster.apt" >/dev/null
inputs+=("$TMP/raster.apt")

begin "one thread, two (and three on the raster): the same program"
for f in "${inputs[@]}"; do
  name=$(basename "$f")
  cam_options "$name" || continue
  counts=(1 2)
  [[ $name == raster.apt ]] && counts+=(3)
  for threads in "${counts[@]}"; do
    mkdir -p "$TMP/$threads/$name"
    run convert "$f" --cell "$cell" -o "$TMP/$threads/$name" --name P -q --threads "$threads" \
      "${opts[@]}"
    expect_rc 0
    [[ $threads == 1 ]] && continue
    diff -r "$TMP/1/$name" "$TMP/$threads/$name" >"$TMP/diff" ||
      fail "$name: the program differs with $threads threads: $(head -5 "$TMP/diff")"
  done
  echo "cli.threads: $name: $(cat "$TMP/1/$name"/*.src | wc -l) lines, identical (${counts[*]})"
done
passed

begin "a pose out of reach: the same message with one thread and two, nothing written"
# A point 5 m out, in the middle of the raster: found while the plan's windows run ahead.
awk 'NR == 3000 { print "GOTO/5000.000,0.000,60.000,0.000000,0.000000,1.000000" } { print }' \
  "$TMP/raster.apt" >"$TMP/far.apt"
for threads in 1 2; do
  mkdir -p "$TMP/far$threads"
  run convert "$TMP/far.apt" --cell "$cell" -o "$TMP/far$threads" --name P -q --threads "$threads"
  expect_rc 2
  cp "$TMP/err" "$TMP/far$threads.err"
  [[ -z "$(ls -A "$TMP/far$threads")" ]] || fail "$threads threads: files left: $(ls "$TMP/far$threads")"
done
grep -q "far.apt:3000: " "$TMP/far1.err" || fail "the message does not name far.apt:3000: $(cat "$TMP/far1.err")"
cmp -s "$TMP/far1.err" "$TMP/far2.err" ||
  fail "the messages differ: $(cat "$TMP/far1.err") / $(cat "$TMP/far2.err")"
passed

begin "--threads out of range"
run convert "$SRC/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$TMP/bad" --name P --threads -1
expect_rc 2
[[ ! -e $TMP/bad/P.src ]] || fail "a program was written"
passed

echo "cli.threads: $checks checks passed"
