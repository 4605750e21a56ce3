#!/usr/bin/env bash
# Reliability checks (issue 10, docs/reliability.md), run by .ci/run after scripts/test.sh:
#   1. build-asan/: every target with AddressSanitizer + UndefinedBehaviorSanitizer, and the
#      whole CTest suite on it (the Tcl package test through tests/sanitize/tclsh_asan.sh);
#   2. build-tsan/: the C ABI tests with ThreadSanitizer (two sessions on two threads, the
#      per-thread last error), built at low priority while step 1's suite runs;
#   3. the C host example under valgrind memcheck, against the golden output, on the plain
#      Release build (build/, or $REDPOST_PLAIN_BUILD_DIR).
# Prints a summary with timings; exits 1 if any step failed. Needs what scripts/setup.sh
# installs (gcc's sanitizer runtimes, valgrind, tclsh).
set -uo pipefail
cd "$(dirname "$0")/.."

jobs=$(nproc 2>/dev/null || echo 2)
plain=${REDPOST_PLAIN_BUILD_DIR:-build}
# -O1: fast enough to run the suite, while keeping stack traces readable. -g1: line tables for
# the reports' stack traces, without full debug information (a quicker build). NDEBUG as in
# Release, so the tests see the code CI ships.
opt="-O1 -g1 -DNDEBUG"
sanitizer_build=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$opt"
                 "-DCMAKE_C_FLAGS_RELWITHDEBINFO=$opt" -DREDPOST_BUILD_BENCHMARKS=OFF)

# Every finding aborts the process that made it (REDPOST_SANITIZE also sets
# -fno-sanitize-recover=all), so the test that ran it fails.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"

summary=()
failed=0
# step NAME COMMAND...: runs COMMAND, records ok/FAIL and the seconds it took.
step() {
  local name=$1 start=$SECONDS result=ok
  shift
  echo "reliability: == $name"
  "$@" || { result=FAIL; failed=1; }
  summary+=("$(printf '  %-34s %-4s %5ds' "$name" "$result" $((SECONDS - start)))")
}

asan_build() {
  cmake -S . -B build-asan "${sanitizer_build[@]}" -DREDPOST_SANITIZE=address,undefined \
    "-DTCL_TCLSH=$PWD/tests/sanitize/tclsh_asan.sh" >/dev/null &&
    cmake --build build-asan -j "$jobs"
}
asan_ctest() {
  # The consumer test (cmake.find_package_consumer) links the installed, instrumented
  # libredpost_core.a into a fresh project: LDFLAGS gives that link the sanitizer runtimes.
  # REDPOST_TEST_LIGHT: the placement tests (~40 times slower here) search less
  # (tests/unit/machining/test_placement.cpp, tests/cli/test_place.sh).
  # REDPOST_SANITIZER: tests that bound memory use (peak RSS) can tell ASan's shadow memory and
  # quarantine from a real excess.
  # REDPOST_TEST_LIGHT also makes the SIGKILL test kill a smaller conversion fewer times.
  LDFLAGS="-fsanitize=address,undefined" REDPOST_TEST_LIGHT=1 \
    REDPOST_SANITIZER=address,undefined \
    ctest --test-dir build-asan --output-on-failure -j "$jobs" --timeout 900
}
tsan_build() {
  cmake -S . -B build-tsan "${sanitizer_build[@]}" -DREDPOST_SANITIZE=thread >/dev/null &&
    cmake --build build-tsan -j "$jobs" --target redpost_abi_tests
}
# The TSan build runs at low priority beside the ASan suite, on the core its long single tests
# leave idle; tsan_wait collects it.
tsan_build_start() {
  tsan_log=$(mktemp)
  nice -n 10 bash -c "$(declare -p sanitizer_build jobs); $(declare -f tsan_build); tsan_build" \
    >"$tsan_log" 2>&1 &
  tsan_pid=$!
}
tsan_wait() {
  local rc=0
  wait "$tsan_pid" || rc=$?
  tail -n 20 "$tsan_log"
  rm -f "$tsan_log"
  return $rc
}
tsan_run() {
  # Every ABI test case: the thread ones are the point, the rest are cheap.
  build-tsan/tests/redpost_abi_tests
}
memcheck_c_host() {
  if [[ -f "$plain/CMakeCache.txt" ]]; then
    cmake --build "$plain" -j "$jobs" --target redpost_c_host || return 1
  else
    cmake -S . -B "$plain" -DCMAKE_BUILD_TYPE=Release >/dev/null &&
      cmake --build "$plain" -j "$jobs" --target redpost_c_host || return 1
  fi
  # run_c_host.sh runs "HOST ARGS..." and diffs its output with the golden files: the wrapper
  # puts valgrind in front of the host.
  local wrapper host
  host=$(cd "$plain" && pwd)/plugin/redpost_c_host
  wrapper=$(mktemp)
  printf '#!/bin/sh\nexec "%s" "%s" "$@"\n' "$PWD/tests/sanitize/memcheck.sh" "$host" >"$wrapper"
  chmod +x "$wrapper"
  tests/abi/run_c_host.sh "$wrapper" "$PWD"
  local rc=$?
  rm -f "$wrapper"
  return $rc
}

total_start=$SECONDS
step "asan+ubsan: build (build-asan)" asan_build
tsan_build_start
step "asan+ubsan: ctest (whole suite)" asan_ctest
step "tsan: build (build-tsan, abi), rest" tsan_wait
step "tsan: ABI tests" tsan_run
step "valgrind memcheck: C host" memcheck_c_host

echo "reliability: summary"
printf '%s\n' "${summary[@]}"
printf '  %-34s %-4s %5ds\n' "total" "$( ((failed)) && echo FAIL || echo ok)" \
  $((SECONDS - total_start))
exit $failed
