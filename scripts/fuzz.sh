#!/usr/bin/env bash
# Fuzzes redpost's input readers with libFuzzer (issue 10, docs/reliability.md).
#
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
#
# Builds the targets of tests/fuzz/ with clang (-fsanitize=fuzzer,address,undefined) into
# build-fuzz/, then runs each one for SECONDS_PER_TARGET seconds from its seed corpus
# (tests/fuzz/corpus/<target>/ and tests/fuzz/regression/<target>/). New corpus entries go to a
# scratch directory, never into the repository; crash, leak and timeout inputs are kept in
# $FUZZ_OUT (default build-fuzz/out/<target>/) for a regression file. Prints the executions per
# target and exits non-zero if any target found a crash, a leak, a hang (-timeout) or ran out
# of memory.
#
# Environment: FUZZ_TARGETS="cl_reader convert" runs a subset; FUZZ_JOBS (default 2) the
# build's parallelism.
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-fuzz
out=${FUZZ_OUT:-$build/out}
targets=${FUZZ_TARGETS:-"cl_reader cell_xml krl_template krl_reader calibration_csv convert"}

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-dev)" >&2
  exit 2
fi

if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S "$root/tests/fuzz" -B "$build" >/dev/null
fi
make -C "$build" -j"${FUZZ_JOBS:-2}" $(for t in $targets; do echo "fuzz_$t"; done) >/dev/null

# Largest input per target: CL files and KRL programs up to 64 KiB, definitions and CSV less.
max_len() {
  case $1 in
    cl_reader | krl_reader) echo 65536 ;;
    convert) echo 16384 ;;
    *) echo 16384 ;;
  esac
}

status=0
printf '%-16s %12s %8s %s\n' target executions corpus result
for t in $targets; do
  work=$out/$t
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/artifacts"
  log=$work/fuzz.log
  rc=0
  seeds=("$root/tests/fuzz/corpus/$t")
  [ -d "$root/tests/fuzz/regression/$t" ] && seeds+=("$root/tests/fuzz/regression/$t")
  # ASan's leak check is on by default under libFuzzer; UBSan aborts (built -fno-sanitize-recover).
  ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} \
    "$build/fuzz_$t" "$work/corpus" "${seeds[@]}" \
    -max_total_time="$seconds" -max_len="$(max_len "$t")" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$work/artifacts/" >"$log" 2>&1 || rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  # The corpus libFuzzer ended with (seeds and new units, after its own reduction).
  corpus=$(sed -n 's/^#[0-9]*[[:space:]]*DONE.* corp: \([0-9]*\)\/.*/\1/p' "$log" | tail -1)
  result=ok
  if [ "$rc" -ne 0 ] || [ -n "$(ls -A "$work/artifacts")" ]; then
    result="FAILED (exit $rc): $(ls "$work/artifacts" | head -3 | tr '\n' ' ')see $log"
    status=1
  fi
  printf '%-16s %12s %8s %s\n' "$t" "${execs:-?}" "${corpus:-?}" "$result"
done
exit $status
