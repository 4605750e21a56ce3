#!/usr/bin/env bash
# Set-up, build, then run the main job on a bundled example.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
example=examples/fk/andres_home_and_sweep.txt
echo "== redpost fk on the Andres cell ($example): TCP x y z and rotation, mm"
build/plugin/redpost fk --cell definitions/cells/andres2011_kr15_track_table.xml --axes <"$example"
