#!/bin/sh
# `redpost convert --report` in a real browser (issue 9): converts the pocket example with a
# report and checks that report with render_check.sh (headless Chromium: no console messages,
# self-contained, the expected number of plots, not blank), then its 3D view with scene_check.py
# (WebGL through chromedriver: the link count, the page's own kinematics, the arm moving).
# Usage: test_convert_report.sh REDPOST SOURCE_DIR OUTDIR. Exit 77 (skip) without chromium.
set -u
redpost=$1
src=$2
out=$3
here=$(cd "$(dirname "$0")" && pwd)
# Joints, axis speed fractions, path speed, motion duration against the interpolation cycle,
# 1/kappa_F, external axes, the plan against the written joints (E1, E2, the spin), iterations,
# feed, the closest approach of the bodies per motion (the cell's own, issue 46) and the XY, XZ,
# YZ toolpath projections.
expected=15
rm -rf "$out" && mkdir -p "$out" || exit 1
"$redpost" convert "$src/examples/cl/pocket_arcs.apt" \
  --cell "$src/definitions/cells/andres2011_kr15_track_table.xml" -o "$out" --name POCKET -q \
  --report "$out/convert_report.html" || { echo "FAIL: convert --report failed" >&2; exit 1; }
# The header counts the warnings the page shows (the run's and the report's own checks): the
# surface example has two of the run and one joint near its limit.
html=$out/convert_report.html
"$redpost" convert "$src/examples/cl/surface_5axis.cls" \
  --cell "$src/definitions/cells/andres2011_kr15_track_table.xml" -o "$out" --name SURF -q \
  --report "$out/surface_report.html" 2>/dev/null || { echo "FAIL: convert --report failed" >&2; exit 1; }
for page in "$html" "$out/surface_report.html"; do
  count=$(sed -n 's|.*warnings</th><td>\([0-9]*\).*|\1|p' "$page")
  shown=$(grep -o 'class="warn"' "$page" | wc -l)
  if [ -z "$count" ] || [ "$count" -ne "$shown" ]; then
    echo "FAIL: $page: the header counts '$count' warnings, the page shows $shown" >&2
    exit 1
  fi
done
# A page tall enough to show every plot: the screenshot is then worth looking at.
"$here/render_check.sh" "$out/convert_report.html" "$expected" "$out/convert_report.png" 3800 ||
  exit $?
# The 3D view (issue 21): the scene holds one link solid per joint of the cell file (counted
# here from the file itself), the page's kinematics meets the TCP of every motion, and the arm
# moves on the screen between the first and the last motion.
# Under the sanitizers the page is the same bytes and the browser is not what is checked: skipped
# there (scripts/reliability.sh sets REDPOST_SANITIZER), to keep the CI run short.
if [ -n "${REDPOST_SANITIZER:-}" ]; then
  echo "note: the 3D view's browser check runs in the plain build only"
  exit 0
fi
links=$(grep -c '<joint ' "$src/definitions/cells/andres2011_kr15_track_table.xml")
# The collision check's bodies (issue 46): the cell's, counted from its file, and the pocket's
# tool (its CUTTER/ diameter: one cutter).
bodies=$(($(grep -c '<body ' "$src/definitions/cells/andres2011_kr15_track_table.xml") + 1))
exec python3 "$here/scene_check.py" "$out/convert_report.html" --links "$links" \
  --bodies "$bodies" --out-dir "$out"
