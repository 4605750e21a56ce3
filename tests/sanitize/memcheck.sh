#!/usr/bin/env bash
# Runs a program under valgrind memcheck and fails (exit 99) on any memory error and on any
# block not freed at exit, of every leak kind, "still reachable" included: a C host that calls
# rp_reader_free and rp_free ends with an empty heap (measured: all blocks freed), so anything
# left is a missing free in the library or the host. The one exception, memcheck.supp: the
# blocks libfcl and liboctomap allocate in their own static initialisers before main.
#   memcheck.sh PROGRAM [ARGS...]
set -euo pipefail
exec valgrind --quiet --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=all \
  --show-leak-kinds=all --track-origins=yes \
  --suppressions="$(dirname "$0")/memcheck.supp" "$@"
