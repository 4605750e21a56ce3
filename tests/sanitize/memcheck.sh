#!/usr/bin/env bash
# Runs a program under valgrind memcheck, failing (exit 99) on any memory error and on leaks
# that are lost (definite, indirect) or only reachable through an inner pointer (possible).
# "Still reachable" blocks are not errors: they are live at exit by design (libstdc++'s
# exception emergency pool, function-local statics) and are freed by the OS.
#   memcheck.sh PROGRAM [ARGS...]
set -euo pipefail
exec valgrind --quiet --error-exitcode=99 --leak-check=full \
  --errors-for-leak-kinds=definite,indirect,possible \
  --show-leak-kinds=definite,indirect,possible --track-origins=yes "$@"
