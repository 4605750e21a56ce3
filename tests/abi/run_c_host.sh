#!/usr/bin/env bash
# The C99 host example converts pocket_arcs.apt through the ABI into a temporary directory; its
# files must equal the golden `redpost convert` output (tests/golden/pocket_arcs) byte for byte.
# Usage: run_c_host.sh C_HOST SOURCE_DIR
set -euo pipefail
host=$1 src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$host" "$src/examples/cl/pocket_arcs.apt" "$src/definitions/cells/andres2011_kr15_track_table.xml" \
  "$work" POCKET_ARCS
diff -r "$src/tests/golden/pocket_arcs" "$work"
echo "c_host: identical to tests/golden/pocket_arcs"
