#!/usr/bin/env bash
# krc4_spline at a production feed (issue 30, docs/krl-templates.md "SPL segments"): the examples,
# a 5000-point raster and the NX NURBS job of ../shared/evaldata (when present), each feed set to
# 10 000 mm/min. From the written programs alone: every CL point lies within 0.01 mm and 0.1 deg
# of the path the model of the controller's spline draws through the SLIN and SPL segments, and
# every point of those curves within 0.01 mm of the CL polyline (fit_check.py); every axis stays
# within its velocity limit at the $VEL.CP in force or the segment's own (speed_check.py); no
# motion lasts less than one 12 ms cycle, as convert says and as the text shows. And the time
# model never says a program runs faster than the floor that $ACC.CP, $VEL.ORI1 and the blend
# allow its CL path (tests/bench/time_floor.py), with any set and preset.
#
# Usage: test_spline.sh REDPOST SOURCE_DIR
. "$(dirname "$0")/harness.sh" cli.spline "$@"
. "$(dirname "$0")/speeds_helpers.sh"

begin "SPL where the path is smooth: the model's path within 0.01 mm of every CL point, its curves of the CL polyline, within the axis speeds and the cycle"
$py "$SRC/tests/bench/make_raster_apt.py" 5000 "$TMP/raster5k.apt"
inputs=("$SRC"/examples/cl/* "$TMP/raster5k.apt")
nurbs=$SRC/../shared/evaldata/clsf/nx_nurbs_fixed_contour.clsf
[[ -f $nurbs ]] && inputs+=("$nurbs")
for f in "${inputs[@]}"; do
  name=fastfit_$(basename "$f")_spline
  fast "$f" "$TMP/$name.cl"
  fit "$name" "$TMP/$name.cl" --krl krc4_spline
  spl=$(grep -c '^SPL ' "$TMP/$name/P.src" || true)
  echo "cli.spline: $name: $spl SPL segments"
  # The reference (--fit-tol 0) is 0.7's program: SLINs only.
  if grep -q '^SPL ' "${TMP}/${name}_ref/P.src"; then
    fail "$name: SPL written with --fit-tol 0"
  fi
done
# The raster's tracked steps along its lines and the NURBS job's curve are smooth: SPL.
spl=$(grep -c '^SPL ' "$TMP/fastfit_raster5k.apt_spline/P.src" || true)
((spl >= 100)) || fail "raster: only $spl SPL segments"
if [[ -f $nurbs ]]; then
  spl=$(grep -c '^SPL ' "$TMP/fastfit_nx_nurbs_fixed_contour.clsf_spline/P.src" || true)
  ((spl >= 4000)) || fail "NURBS job: only $spl SPL segments"
fi
passed

begin "the time model is never faster than the floor the CL path allows (time_floor.py), with each set"
# The floor's reference: every CL point as a motion, printed with 6 decimals, rapids as Cartesian
# PTPs (their positions known), for a cell without axis speeds (every feed move at its feed).
sed '/<speed velocity=/d' "$cell" >"$TMP/free_cell.xml"
sed 's#<statement name="rapid">PTP {E6AXIS:[^<]*<#<statement name="rapid">PTP {E6POS: X {x}, Y {y}, Z {z}, A {a}, B {b}, C {c}{ext}}<#' \
  "$(exact_set krc4_circ)" >"$TMP/floor_set.xml"
# The raster's first feed move comes from the program's first PTP, whose position is not printed:
# a rapid to 10 mm above its start first, so that the floor counts every feed move.
sed '0,/^FEDRAT/s//RAPID\nGOTO\/-300.0000,-650.0000,70.0000,-0.2369232,0.2443282,0.9403037\nFEDRAT/' \
  "$TMP/raster5k.apt" >"$TMP/raster5k_start.apt"
floor_inputs=("$SRC/examples/cl/pocket_arcs.apt" "$TMP/raster5k_start.apt")
for f in "$nurbs" "$SRC"/../shared/evaldata/apt/swcam_{gasket_circles,drill_cycles}.apt; do
  [[ -f $f ]] && floor_inputs+=("$f")
done
for f in "${floor_inputs[@]}"; do
  name=$(basename "$f")
  fast "$f" "$TMP/floor_$name.cl"
  mkdir -p "$TMP/floor_$name" "$TMP/model_$name"
  run convert "$TMP/floor_$name.cl" --cell "$TMP/free_cell.xml" -o "$TMP/floor_$name" --name P \
    --krl "$TMP/floor_set.xml" --fit-tol 0 --plan local -q
  expect_rc 0
  for krl in krc4_lin krc4_circ krc4_spline; do
    for preset in smooth fast; do
      run convert "$TMP/floor_$name.cl" --cell "$cell" -o "$TMP/model_$name" --name P \
        --krl "$krl" --preset "$preset"
      expect_rc 0
      $py "$SRC/tests/bench/time_floor.py" "$TMP/floor_$name/P.src" --feed 10000 \
        --model-log "$TMP/out" >"$TMP/floor" 2>&1 || fail "$name, $krl, $preset: $(cat "$TMP/floor")"
      echo "cli.spline: $name, $krl, $preset: $(tr '\n' ' ' <"$TMP/floor")"
    done
  done
done
passed

echo "cli.spline: $checks checks passed"
