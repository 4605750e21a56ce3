#!/usr/bin/env bash
# Every shipped template set writes programs that `redpost check` accepts (issue 31): each set
# converts the examples and every real CAM file of ../shared/evaldata (when present), and check
# reads the result without a finding. The sets' fixed text is checked when they load
# (docs/krl-templates.md, "Checked when loaded"); this is the same promise seen from the output.
#
# Usage: test_sets.sh REDPOST SOURCE_DIR
. "$(dirname "$0")/harness.sh" cli.sets "$@"

. "$(dirname "$0")/cam_inputs.sh"
cell=$SRC/definitions/cells/andres2011_kr15_track_table.xml

begin "each shipped set: every input converts to a program redpost check accepts"
for set in "$SRC"/definitions/krl/*.xml; do
  krl=$(basename "$set" .xml)
  for f in "${inputs[@]}"; do
    name=$(basename "$f")
    cam_options "$name" || continue
    out=$TMP/${krl}_$name
    mkdir -p "$out"
    run convert "$f" --cell "$cell" -o "$out" --name P --krl "$set" -q "${opts[@]}"
    expect_rc 0
    run check "$out" --cell "$cell"
    [[ $RC -eq 0 ]] || fail "$krl, $name: redpost check found: $(head -5 "$TMP/out")"
    echo "cli.sets: $krl, $name: $(ls "$out"/*.src | wc -l) program file(s), check clean"
  done
done
passed

echo "cli.sets: $checks checks passed"
