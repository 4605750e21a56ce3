#!/usr/bin/env bash
# Golden regression of `redpost convert` on the project's examples: every generated file must
# equal the committed one byte for byte (and, once `redpost diff` exists, semantically too).
#
# Usage: run_golden.sh REDPOST SOURCE_DIR WORK_DIR [--update]
#   --update rewrites tests/golden/ from the current output (review the diff before committing).
set -euo pipefail
redpost=$1 src=$2 work=$3 update=${4:-}
cell=$src/definitions/cells/andres2011_kr15_track_table.xml
# The first five run with point reduction off (--fit-tol 0): one motion per CL point, as
# redpost 0.7 wrote them (docs/timing.md, "Point reduction"; 0.8's first-window plan moved their
# external axes); the *_fit cases are the default, reduced program.
cases=(
  "pocket_arcs krc4_lin pocket_arcs.apt --fit-tol 0"
  "pocket_arcs_spline krc4_spline pocket_arcs.apt --fit-tol 0"
  "pocket_arcs_krc2 krc2_lin pocket_arcs.apt --clearance 100 --fit-tol 0"
  "surface_5axis krc4_lin surface_5axis.cls --fit-tol 0"
  "long_pass krc4_lin long_pass.apt --split 150 --fit-tol 0"
  "surface_5axis_fit krc4_lin surface_5axis.cls"
  "long_pass_fit krc4_spline long_pass.apt"
)
rm -rf "$work"
failed=0
for c in "${cases[@]}"; do
  read -r name set input extra <<<"$c"
  out=$work/$name
  mkdir -p "$out"
  # shellcheck disable=SC2086
  "$redpost" convert "$src/examples/cl/$input" --cell "$cell" --krl "$src/definitions/krl/$set.xml" \
    -o "$out" --name "$(echo "$name" | tr '[:lower:]' '[:upper:]')" -q $extra
  if [ "$update" = "--update" ]; then
    rm -rf "$src/tests/golden/$name"
    cp -r "$out" "$src/tests/golden/$name"
    echo "updated tests/golden/$name"
    continue
  fi
  if ! diff -r "$src/tests/golden/$name" "$out" >"$work/$name.diff"; then
    echo "golden $name differs:"; head -20 "$work/$name.diff"; failed=1
  else
    echo "golden $name: identical ($(ls "$out" | wc -l) files)"
  fi
  # And semantically: every motion equal at tolerance 0 (redpost diff, docs/krl-diff.md).
  if ! "$redpost" diff "$src/tests/golden/$name" "$out" --pos-tol 0 --ang-tol 0 --axis-tol 0 \
    >"$work/$name.krldiff" 2>&1; then
    echo "golden $name: redpost diff reports differences:"; head -20 "$work/$name.krldiff"; failed=1
  fi
done
exit $failed
