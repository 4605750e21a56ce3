#!/usr/bin/env bash
# The whole-path plan's threads change nothing but the time (issue 32): every example and every
# real CAM file of ../shared/evaldata (when present) converted with one thread and with two (the
# pipeline: reading here, planning on the session's thread, tracking and writing on one of its
# own) gives the same program, byte for byte, and a raster with three too (the lattice's nodes
# shared as well) and under --plan local; a failure on the tracking thread is told as one thread
# tells it, also before a broken line the reader meets later (docs/redundancy.md, "Threads").
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

begin "--plan local: one thread and two (the file read on its own thread), the same program"
for threads in 1 2; do
  mkdir -p "$TMP/local$threads"
  run convert "$TMP/raster.apt" --cell "$cell" -o "$TMP/local$threads" --name P -q --plan local \
    --threads "$threads"
  expect_rc 0
done
diff -r "$TMP/local1" "$TMP/local2" >"$TMP/diff" ||
  fail "--plan local: the program differs with 2 threads: $(head -5 "$TMP/diff")"
passed

# Converts INPUT with one thread and two: exit code 2, nothing left in the output folders, the
# same message both ways, and that message names WHERE (file:line).
same_failure() {
  local input=$1 where=$2 tag
  tag=$(basename "$input" .apt)
  for threads in 1 2; do
    mkdir -p "$TMP/$tag$threads"
    run convert "$input" --cell "$cell" -o "$TMP/$tag$threads" --name P -q --threads "$threads"
    expect_rc 2
    cp "$TMP/err" "$TMP/$tag$threads.err"
    [[ -z "$(ls -A "$TMP/$tag$threads")" ]] ||
      fail "$tag, $threads threads: files left: $(ls "$TMP/$tag$threads")"
  done
  grep -q "$where" "$TMP/${tag}1.err" || fail "the message does not name $where: $(cat "$TMP/${tag}1.err")"
  cmp -s "$TMP/${tag}1.err" "$TMP/${tag}2.err" ||
    fail "the messages differ: $(cat "$TMP/${tag}1.err") / $(cat "$TMP/${tag}2.err")"
}

begin "a pose out of reach: the same message with one thread and two, nothing written"
# A point 5 m out, in the middle of the raster: found while the plan's windows run ahead.
awk 'NR == 3000 { print "GOTO/5000.000,0.000,60.000,0.000000,0.000000,1.000000" } { print }' \
  "$TMP/raster.apt" >"$TMP/far.apt"
same_failure "$TMP/far.apt" "far.apt:3000: "
passed

begin "a pose out of reach, then a broken line: the pose is the error with one thread and two"
# With two threads the file is read on its own thread (rp_options.pipeline) and runs ahead of the
# session: the broken line 1800 lines on is read before the pose is tracked, and must not be
# told first (rp_sync).
awk 'NR == 4800 { print "GOTO/1.0,2.0" } { print }' "$TMP/far.apt" >"$TMP/far_broken.apt"
same_failure "$TMP/far_broken.apt" "far_broken.apt:3000: "
# The broken line alone: the reader's message, the same both ways.
awk 'NR == 4800 { print "GOTO/1.0,2.0" } { print }' "$TMP/raster.apt" >"$TMP/broken.apt"
same_failure "$TMP/broken.apt" "broken.apt:4800"
passed

begin "--threads out of range"
run convert "$SRC/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$TMP/bad" --name P --threads -1
expect_rc 2
[[ ! -e $TMP/bad/P.src ]] || fail "a program was written"
passed

echo "cli.threads: $checks checks passed"
