#!/usr/bin/env bash
# The size and cost of `redpost convert --report` with its 3D view (docs/reports.md, issue 21):
# the 5-axis raster of convert_bench.sh (100 000 poses, and 1 000 000 with --long) converted on
# the 9-joint cell without and with --report; wall time (best of 3), peak RSS, the report's size,
# the 3D view's share of it (its data and the inlined scripts) and what the view kept (frames,
# toolpath points). The target: the report of a 100 000-pose program under 10 MB.
#
# Usage: tests/bench/report_bench.sh [BUILD_DIR] [--long]   (default: build)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
# $redpost, $cell (the Andres cell), a $work folder removed at exit, the machine line, and
# best_of_3 INPUT OUT [options]: "seconds peak_kib" of the fastest of three runs.
source "$top/tests/bench/convert_timing.sh"
sizes=(100000)
[[ "${2:-}" == "--long" ]] && sizes+=(1000000)

printf '%-9s %10s %10s %10s %10s %10s %10s %9s %8s %8s\n' poses "plain [s]" "report [s]" \
  "RSS [MiB]" "RSS rep." "page [MB]" "3D data" "3D js" frames points
for n in "${sizes[@]}"; do
  python3 "$top/tests/bench/make_raster_apt.py" "$n" "$work/raster.apt"
  read -r s0 k0 < <(best_of_3 "$work/raster.apt" "$work/plain")
  read -r s1 k1 < <(best_of_3 "$work/raster.apt" "$work/rep" --report "$work/rep/report.html")
  page=$work/rep/report.html
  # The view's data is the JSON <script> of scene-1; its scripts are three.js, OrbitControls
  # and the view's own (everything from the error collector to the report's own script).
  read -r total data js frames points < <(python3 - "$page" <<'PY'
import re, sys
src = open(sys.argv[1], encoding="utf-8").read()
data = re.search(r'<script type="application/json" id="scene-1-data">(.*?)</script>', src, re.S)
start = src.find("<script>\nwindow.__redpostErrors")
end = src.rfind("<script>")
note = re.search(r"slider steps through (\d+)", src)
pts = re.search(r"drawn with (\d+) points", src)
print(f"{len(src.encode()) / 1e6:.2f} {len(data.group(1).encode()) / 1e6:.2f}",
      f"{len(src[start:end].encode()) / 1e6:.2f}", note.group(1) if note else "all",
      pts.group(1) if pts else "all")
PY
)
  printf '%-9s %10s %10s %10s %10s %10s %10s %9s %8s %8s\n' "$n" "$s0" "$s1" \
    "$(awk -v k="$k0" 'BEGIN { printf "%.1f", k / 1024 }')" \
    "$(awk -v k="$k1" 'BEGIN { printf "%.1f", k / 1024 }')" "$total" "$data" "$js" "$frames" \
    "$points"
done
