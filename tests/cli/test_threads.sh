#!/usr/bin/env bash
# The whole-path plan's threads change nothing but the time (issue 32): every example and every
# real CAM file of ../shared/evaldata (when present) converted with one thread and with three
# gives the same program, byte for byte (docs/redundancy.md, "Threads").
#
# Usage: test_threads.sh REDPOST SOURCE_DIR
. "$(dirname "$0")/harness.sh" cli.threads "$@"

. "$(dirname "$0")/cam_inputs.sh"
cell=$SRC/definitions/cells/andres2011_kr15_track_table.xml
# A raster of 5000 poses besides: windows whose layers have hundreds of nodes to share.
python3 "$SRC/tests/bench/make_raster_apt.py" 5000 "$TMP/raster.apt" >/dev/null
inputs+=("$TMP/raster.apt")

begin "one thread and three: the same program"
for f in "${inputs[@]}"; do
  name=$(basename "$f")
  cam_options "$name" || continue
  for threads in 1 3; do
    mkdir -p "$TMP/$threads/$name"
    run convert "$f" --cell "$cell" -o "$TMP/$threads/$name" --name P -q --threads "$threads" \
      "${opts[@]}"
    expect_rc 0
  done
  diff -r "$TMP/1/$name" "$TMP/3/$name" >"$TMP/diff" ||
    fail "$name: the program differs with three threads: $(head -5 "$TMP/diff")"
  echo "cli.threads: $name: $(cat "$TMP/1/$name"/*.src | wc -l) lines, identical"
done
passed

begin "--threads out of range"
run convert "$SRC/examples/cl/pocket_arcs.apt" --cell "$cell" -o "$TMP/bad" --name P --threads -1
expect_rc 2
[[ ! -e $TMP/bad/P.src ]] || fail "a program was written"
passed

echo "cli.threads: $checks checks passed"
