#!/usr/bin/env bash
# The placement benchmark (docs/placement.md): runs the example job of Caro 2014 chapter 5 end to
# end with `redpost place` and prints the wall time, the CPU time, the peak RSS, the evaluations,
# the time per inner evaluation and the four cases of Table 5.1.
#
# Usage: tests/bench/placement_bench.sh [BUILD_DIR]   (default: build)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
redpost=$build/plugin/redpost
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; load $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M UTC')"
/usr/bin/time -f "%e %U %S %M" -o "$work/time" "$redpost" place \
  "$top/examples/placement/caro2014_job.xml" -o "$work/out" --json "$work/out.json" >"$work/log"
read -r wall user sys kib <"$work/time"
python3 - "$work/out.json" "$wall" "$user" "$sys" "$kib" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
wall, user, sys_, kib = map(float, sys.argv[2:6])
n = j["convergence"]["best"]["evaluations"] + j["convergence"]["worst"]["evaluations"]
print(f"wall {wall:.1f} s, CPU {user + sys_:.1f} s, peak RSS {kib / 1024:.1f} MB")
print(f"{n} placements evaluated in {j['seconds']:.1f} s: {1000 * j['seconds'] / n:.1f} ms wall "
      f"per inner evaluation (both cores)")
p = j["placement"]
print(f"best placement: O_W = ({p['x_mm']:.1f}, {p['y_mm']:.1f}, {p['z_mm']:.1f}) mm, Q4 = {p['q4']:.4f}")
c = j["cases"]
for k, v in c.items():
    print(f"  {k:<28} f_MQC {v['f_mqc_mm']:.4f} mm, max c {v['max_c_mm']:.4f} mm")
print(f"  case 4 / case 1 = {j['ratio_case4_case1']:.2f}  (Caro Table 5.1: 1.2 / 0.083 = 14.5)")
PY
