#!/usr/bin/env bash
# Set-up, build, then the main job on a bundled example: a 5-axis finishing pass (NX CLSF) on
# the Andres track-and-table cell, converted to a KUKA KRL program in out/quickstart/, with its
# HTML report (plots and the cell in 3D) beside it.
# Installs and builds only what that needs (scripts/setup.sh --main): no test suite, no browser.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --main
out=out/quickstart
mkdir -p "$out"
build/plugin/redpost convert examples/cl/surface_5axis.cls \
  --cell definitions/cells/andres2011_kr15_track_table.xml \
  -o "$out" --name SURFACE_5AXIS --joints-csv "$out/joints.csv" --report "$out/report.html"
echo "== the first motions of $out/SURFACE_5AXIS.src"
grep -m 8 -E "^(PTP|LIN|\\\$VEL)" "$out/SURFACE_5AXIS.src"
echo "== the report (open it in a browser): $out/report.html"
