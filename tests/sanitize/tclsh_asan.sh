#!/usr/bin/env bash
# tclsh for the AddressSanitizer build (scripts/reliability.sh configures it as TCL_TCLSH).
# Debian's tclsh is not instrumented and loads the instrumented libredpost.so with `load`; the
# ASan runtime must then come first in the process, hence LD_PRELOAD. The variable is inherited
# by what the test execs (tclsh again for nx_replay.tcl, and `redpost`, which links the same
# runtime anyway).
set -euo pipefail
# libstdc++ is preloaded too: tclsh is a C program, and ASan's __cxa_throw interceptor must find
# the real __cxa_throw when it starts, not when the package's `load` brings libstdc++ in (else
# the first C++ exception aborts with "CHECK failed: ... real___cxa_throw").
asan=$(gcc -print-file-name=libasan.so)
cxx=$(gcc -print-file-name=libstdc++.so)
for lib in "$asan" "$cxx"; do
  [[ -f "$lib" ]] || { echo "tclsh_asan: gcc does not know $lib" >&2; exit 1; }
done
export LD_PRELOAD="$asan:$cxx${LD_PRELOAD:+:$LD_PRELOAD}"
exec tclsh "$@"
