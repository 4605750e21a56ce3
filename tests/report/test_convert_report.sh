#!/bin/sh
# `redpost convert --report` in a real browser (issue 9): converts the pocket example with a
# report and checks that report with render_check.sh (headless Chromium: no console messages,
# self-contained, the expected number of plots, not blank).
# Usage: test_convert_report.sh REDPOST SOURCE_DIR OUTDIR. Exit 77 (skip) without chromium.
set -u
redpost=$1
src=$2
out=$3
here=$(cd "$(dirname "$0")" && pwd)
# Joints, axis speed fractions, path speed, 1/kappa_F, external axes, the plan against the
# written joints (E1, E2, the spin), iterations, feed and the XY, XZ, YZ toolpath projections.
expected=13
rm -rf "$out" && mkdir -p "$out" || exit 1
"$redpost" convert "$src/examples/cl/pocket_arcs.apt" \
  --cell "$src/definitions/cells/andres2011_kr15_track_table.xml" -o "$out" --name POCKET -q \
  --report "$out/convert_report.html" || { echo "FAIL: convert --report failed" >&2; exit 1; }
# A page tall enough to show every plot: the screenshot is then worth looking at.
exec "$here/render_check.sh" "$out/convert_report.html" "$expected" "$out/convert_report.png" 3400
