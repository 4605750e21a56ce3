#!/bin/sh
# CTest driver: writes the sample report and checks it in the browser (render_check.sh).
# Usage: run_render_check.sh MAKE_SAMPLE_REPORT OUTDIR. Exit 77 (skip) without chromium.
set -u
maker=$1
out=$2
here=$(cd "$(dirname "$0")" && pwd)
# The sample report has 3 convert + 4 calibrate + 5 place plots (make_sample_report.cpp).
expected=12
mkdir -p "$out" || exit 1
n=$("$maker" "$out/sample_report.html") || { echo "FAIL: $maker failed" >&2; exit 1; }
[ "$n" = "$expected" ] || { echo "FAIL: the writer reports $n plots, expected $expected" >&2; exit 1; }
# A page tall enough to show every plot: the screenshot is then worth looking at.
exec "$here/render_check.sh" "$out/sample_report.html" "$expected" "$out/sample_report.png" 4200
