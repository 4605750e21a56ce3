#!/usr/bin/env bash
# Fuzzes redpost's input readers with libFuzzer (issue 10, docs/reliability.md).
#
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
#
# Builds the targets of tests/fuzz/ with clang (-fsanitize=fuzzer,address,undefined) into
# build-fuzz/, then runs each one for SECONDS_PER_TARGET seconds from its seed corpus
# (tests/fuzz/corpus/<target>/ and tests/fuzz/regression/<target>/) with its dictionary
# (tests/fuzz/dict/<target>.dict). New corpus entries go to a
# scratch directory, never into the repository; crash, leak and timeout inputs are kept in
# $FUZZ_OUT (default build-fuzz/out/<target>/) for a regression file. Prints the executions per
# target and exits non-zero if any target found a crash, a leak, a hang (-timeout) or ran out
# of memory.
#
# Environment: FUZZ_TARGETS="cl_reader convert" runs a subset; FUZZ_JOBS (default 2) the
# build's parallelism; FUZZ_PARALLEL (default: the core count) how many targets fuzz at once.
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-fuzz
out=${FUZZ_OUT:-$build/out}
targets=${FUZZ_TARGETS:-"cl_reader cell_xml krl_template krl_reader calibration_csv convert abi_calls"}

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-dev)" >&2
  exit 2
fi

if [ ! -f "$build/CMakeCache.txt" ]; then
  # -O2 for the execution rate; line tables only: enough for symbolised reports, and a quicker
  # build than full debug information.
  CC=clang CXX=clang++ cmake -S "$root/tests/fuzz" -B "$build" \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
    "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" >/dev/null
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

# One target: fuzzes for $seconds and writes its table row to $out/<target>/row.
fuzz_one() {
  local t=$1 work=$out/$1 rc=0
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/artifacts"
  local log=$work/fuzz.log
  local seeds=("$root/tests/fuzz/corpus/$t")
  [ -d "$root/tests/fuzz/regression/$t" ] && seeds+=("$root/tests/fuzz/regression/$t")
  # The target's dictionary (its keywords, element names, placeholders) lets mutations reach
  # the parsers' deeper branches sooner than byte flips alone.
  local dict=()
  [ -f "$root/tests/fuzz/dict/$t.dict" ] && dict=("-dict=$root/tests/fuzz/dict/$t.dict")
  # ASan's leak check is on by default under libFuzzer; UBSan aborts (built -fno-sanitize-recover).
  ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} \
    "$build/fuzz_$t" "$work/corpus" "${seeds[@]}" "${dict[@]}" \
    -max_total_time="$seconds" -max_len="$(max_len "$t")" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$work/artifacts/" >"$log" 2>&1 || rc=$?
  local execs corpus result=ok
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  # The corpus libFuzzer ended with (seeds and new units, after its own reduction).
  corpus=$(sed -n 's/^#[0-9]*[[:space:]]*DONE.* corp: \([0-9]*\)\/.*/\1/p' "$log" | tail -1)
  if [ "$rc" -ne 0 ] || [ -n "$(ls -A "$work/artifacts")" ]; then
    result="FAILED (exit $rc): $(ls "$work/artifacts" | head -3 | tr '\n' ' ')see $log"
  fi
  printf '%-16s %12s %8s %s\n' "$t" "${execs:-?}" "${corpus:-?}" "$result" >"$work/row"
}

# libFuzzer runs one process on one core: FUZZ_PARALLEL targets (default: the core count) run
# side by side, each still for $seconds.
parallel=${FUZZ_PARALLEL:-$(nproc 2>/dev/null || echo 1)}
running=0
for t in $targets; do
  if [ "$running" -ge "$parallel" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  fuzz_one "$t" &
  running=$((running + 1))
done
wait

status=0
printf '%-16s %12s %8s %s\n' target executions corpus result
for t in $targets; do
  if [ -f "$out/$t/row" ]; then
    cat "$out/$t/row"
    grep -q ' ok$' "$out/$t/row" || status=1
  else
    printf '%-16s %12s %8s %s\n' "$t" "?" "?" "FAILED: no result (see $out/$t/fuzz.log)"
    status=1
  fi
done
exit $status
