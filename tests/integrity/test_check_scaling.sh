#!/usr/bin/env bash
# `redpost check` on a folder is linear in its files (docs/reliability.md, "Bounded work"): the
# folder is listed a bounded number of times whatever the number of programs, counted with the
# LD_PRELOAD module count_listings.so rather than timed. Before issue 18 it was listed once more
# per program (the .dat beside each, a call whose case differs from the file name's), so that
# 4 000 programs took 32 s and 20 000 did not end. Checked on two shapes, each with N and 4N
# programs: a main calling N parts in sequence (in lower case), and a chain of N nested calls
# (which must stop at the nesting bound).
#
#   tests/integrity/test_check_scaling.sh <redpost> <count_listings.so> <scratch-dir>
set -euo pipefail

if [[ $# -ne 3 ]]; then
  echo "usage: $0 <redpost> <count_listings.so> <scratch-dir>" >&2
  exit 1
fi
BIN=$1
SHIM=$2
SCRATCH=$3
rm -rf "$SCRATCH"
mkdir -p "$SCRATCH"
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
failures=0

make_sequence() {  # DIR N: MAIN calls p0() .. p(N-1)(), each an empty program P<i>.src
  python3 - "$1" "$2" <<'PY'
import os, sys
d, n = sys.argv[1], int(sys.argv[2])
os.makedirs(d)
with open(os.path.join(d, "MAIN.src"), "w") as f:
    f.write("DEF MAIN()\n" + "".join(f"  p{i}()\n" for i in range(n)) + "END\n")
for i in range(n):
    with open(os.path.join(d, f"P{i}.src"), "w") as f:
        f.write(f"DEF P{i}()\nEND\n")
PY
}
make_chain() {  # DIR N: P0 calls P1 calls ... P(N-1)
  python3 - "$1" "$2" <<'PY'
import os, sys
d, n = sys.argv[1], int(sys.argv[2])
os.makedirs(d)
for i in range(n):
    call = f"  P{i + 1}()\n" if i + 1 < n else ""
    with open(os.path.join(d, f"P{i}.src"), "w") as f:
        f.write(f"DEF P{i}()\n{call}END\n")
PY
}

for shape in sequence chain; do
  for n in 500 2000; do
    dir=$SCRATCH/${shape}_$n
    "make_$shape" "$dir" "$n"
    rc=0
    # The module goes into redpost alone: `timeout` would write its own count (0) at its exit.
    timeout 120 env REDPOST_COUNT_LISTINGS="$SCRATCH/count" LD_PRELOAD="$SHIM" "$BIN" check "$dir" \
      >"$SCRATCH/out" 2>&1 || rc=$?
    count=$(cat "$SCRATCH/count")
    want_rc=0
    [[ $shape == chain ]] && want_rc=1  # nested more than 64 deep: a finding
    if [[ $rc -ne $want_rc ]]; then
      echo "check-scaling: FAIL: $shape of $n: exit $rc, expected $want_rc" >&2
      sed 's/^/  /' "$SCRATCH/out" | head -5 >&2
      failures=$((failures + 1))
    elif [[ $count -gt 10 ]]; then
      echo "check-scaling: FAIL: $shape of $n programs: the folder was listed $count times" >&2
      failures=$((failures + 1))
    else
      echo "check-scaling: $shape of $n programs: exit $rc, $count folder listings"
    fi
  done
done
[[ $failures -eq 0 ]]
