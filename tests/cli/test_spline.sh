#!/usr/bin/env bash
# krc4_spline at a production feed (issue 30, docs/krl-templates.md "SPL segments"): the examples,
# a 5000-point raster and the NX NURBS job of ../shared/evaldata (when present), each feed set to
# 10 000 mm/min. From the written programs alone: every CL point lies within 0.01 mm and 0.1 deg
# of the path the model of the controller's spline draws through the SLIN and SPL segments, and
# every point of those curves within 0.01 mm of the CL polyline (fit_check.py); every axis stays
# within its velocity limit at the $VEL.CP in force or the segment's own (speed_check.py); no
# motion lasts less than one 12 ms cycle, as convert says and as the text shows.
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

echo "cli.spline: $checks checks passed"
