#!/usr/bin/env bash
# The NX path writes the program `redpost convert` writes (issue 29): every example and every CL
# file of ../shared/evaldata (where present) converted by `redpost convert` and replayed through
# the NX handlers by tcl/nx_replay.tcl (which reads the file itself and plays it as NX's MOM
# events), with the default options and with each option the file exercises; the .src/.dat, the
# joints log and the report (but its conversion time) must be byte-identical, and a refused file
# must be refused by both, with the same file:line and message.
#
# Usage: test_parity.sh REDPOST TCLSH LIBDIR SOURCE_DIR WORK_DIR [PART]
# PART: examples, apt (the evaldata's APT files) or clsf (its NX CLSF files); all three when not
# given. CTest runs the parts as three tests, side by side: under the sanitizers the whole took
# more than 600 s.
set -uo pipefail
redpost=$1 tclsh=$2 libdir=$3 src=$4 work=$5 part=${6:-all}
case $part in
  all | examples | apt | clsf) ;;
  *) echo "test_parity.sh: PART must be examples, apt or clsf, not '$part'" >&2; exit 2 ;;
esac
cell=$src/definitions/cells/andres2011_kr15_track_table.xml
rm -rf "$work" && mkdir -p "$work"
pass=0 fail=0

# What the CAM files lack for the deflection model (a diameter, a spindle speed), and a tool
# table for the job whose tool 20 has no TOOL_DATA of its own.
cat >"$work/cutting.xml" <<'EOF'
<cutting format="1">
  <defaults teeth="4" ae="50%" ap="2" diameter="20" spindle_rpm="12000"/>
</cutting>
EOF
{
  echo '<tool-table>'
  for t in 1 2 6 15 16 18 20; do
    echo "  <tool number=\"$t\" data=\"$((t % 16 + 1))\" length=\"100\"/>"
  done
  echo '</tool-table>'
} >"$work/tools.xml"

# case NAME INPUT [convert options...]
case_() {
  local name=$1 input=$2
  shift 2
  local a=$work/$name/convert b=$work/$name/nx
  mkdir -p "$a" "$b"
  "$redpost" convert "$input" --cell "$cell" -o "$a" --name PARITY -q --joints-csv "$a/joints.csv" \
    --report "$a/report.html" "$@" >"$work/$name/convert.out" 2>"$work/$name/convert.err"
  local ra=$?
  "$tclsh" "$src/tcl/nx_replay.tcl" --lib "$libdir" --cell "$cell" -o "$b" --name PARITY -q \
    --joints-csv "$b/joints.csv" --report "$b/report.html" "$@" "$input" \
    >"$work/$name/nx.out" 2>"$work/$name/nx.err"
  local rb=$?
  if ((ra != rb)); then
    echo "FAIL $name: convert exit $ra, nx_replay exit $rb: $(head -c 300 "$work/$name/nx.err")"
    fail=$((fail + 1))
    return
  fi
  if ((ra != 0)); then
    # Refused by both: the same file:line and message (the handlers put the NX event first).
    local ma mb
    ma=$(sed -n 's/^redpost: //p' "$work/$name/convert.err" | head -1)
    mb=$(grep -o "$(basename "$input"):[0-9]*: .*" "$work/$name/nx.err" | head -1)
    if [[ -z "$ma" || "$ma" != *"$mb" || -n "$(ls -A "$b")" ]]; then
      echo "FAIL $name: refused differently: convert '$ma' / nx '$mb' / left: $(ls -A "$b")"
      fail=$((fail + 1))
      return
    fi
    echo "parity: $name: refused by both at ${mb%%: *}"
    pass=$((pass + 1))
    return
  fi
  sed -i '/conversion time/d' "$a/report.html" "$b/report.html"
  if ! diff -r "$a" "$b" >"$work/$name/diff" 2>&1; then
    echo "FAIL $name: the programs differ: $(head -c 400 "$work/$name/diff")"
    fail=$((fail + 1))
    return
  fi
  echo "parity: $name: $(ls "$a" | tr '\n' ' ')identical"
  pass=$((pass + 1))
}

# wants PART: true when this run covers PART.
wants() { [[ $part == all || $part == "$1" ]]; }

ex=$src/examples/cl
if wants examples; then
  for f in pocket_arcs.apt long_pass.apt surface_5axis.cls; do
    case_ "ex_${f%%.*}" "$ex/$f"
    case_ "ex_${f%%.*}_spline" "$ex/$f" --krl krc4_spline
    case_ "ex_${f%%.*}_local" "$ex/$f" --plan local
  done
  case_ ex_pocket_circ "$ex/pocket_arcs.apt" --krl krc4_circ
  # Collisions (issue 46): a set-up the plan steers clear of, and one that is refused.
  setup=$src/examples/setup
  case_ ex_pocket_clamp "$ex/pocket_arcs.apt" --fixture "$setup/clamp_tower.stl" \
    --part "$setup/pocket_block.stl"
  case_ ex_pocket_clamp_local "$ex/pocket_arcs.apt" --fixture "$setup/clamp_tower.stl" \
    --fixture "$setup/vise_jaw.stl" --plan local --collision-margin 4
  case_ ex_pocket_jaw "$ex/pocket_arcs.apt" --fixture "$setup/jaw_too_close.stl"
  case_ ex_pocket_krc2 "$ex/pocket_arcs.apt" --krl krc2_lin
  case_ ex_pocket_clearance "$ex/pocket_arcs.apt" --clearance 80 --rapid-vel 0.5
  case_ ex_pocket_compensate "$ex/pocket_arcs.apt" --compensate --cutting "$work/cutting.xml"
  case_ ex_pocket_tools "$ex/pocket_arcs.apt" --tools "$work/tools.xml" --split 40
  case_ ex_long_pass_lock "$ex/long_pass.apt" --lock E2 --preset stiff --keyframe-spacing 30
  case_ ex_pocket_threads "$ex/pocket_arcs.apt" --threads 0
  case_ ex_surface_bytes "$ex/surface_5axis.cls" --max-bytes 16384 --apo 1 --cl-line-every 10
  # The point reduction (issue 30): off, looser, and a dense raster at a production feed.
  case_ ex_surface_nofit "$ex/surface_5axis.cls" --fit-tol 0
  case_ ex_long_pass_fit "$ex/long_pass.apt" --fit-tol 0.05 --fit-ang-tol 0.5 --krl krc4_spline
  python3 "$src/tests/bench/make_raster_apt.py" 3000 "$work/raster.apt"
  sed -i 's#FEDRAT/MMPM,3000#FEDRAT/MMPM,10000#' "$work/raster.apt"
  case_ raster_fast "$work/raster.apt"
  case_ raster_fast_loose "$work/raster.apt" --fit-tol 0.1 --fit-ang-tol 1
fi

ev=$src/../shared/evaldata
if [[ $part == examples ]]; then
  :
elif [[ -d "$ev" ]]; then
  files=()
  wants apt && files+=("$ev"/apt/*.apt)
  wants clsf && files+=("$ev"/clsf/*)
  for f in "${files[@]}"; do
    base=$(basename "$f")
    name=ev_${base%%.*}
    case $base in
      nx_variable_contour_5axis.cls)
        case_ "$name" "$f"  # its z-down MCS: refused by both
        case_ "${name}_msys" "$f" --msys apply
        case_ "${name}_msys_local" "$f" --msys apply --plan local
        case_ "${name}_msys_spline" "$f" --msys apply --krl krc4_spline ;;
      swcam_cutcom_multi_op.apt)
        case_ "$name" "$f"  # tool 20 without a tool table: refused by both
        case_ "${name}_tools" "$f" --tools "$work/tools.xml" ;;  # its cycle left on: refused
      *)
        case_ "$name" "$f"
        case_ "${name}_local" "$f" --plan local
        case_ "${name}_compensate" "$f" --compensate --cutting "$work/cutting.xml" ;;
    esac
  done
  if wants apt; then
    for f in swcam_gasket_circles.apt swcam_drill_cycles.apt; do
      name=ev_${f%%.*}
      case_ "${name}_circ" "$ev/apt/$f" --krl krc4_circ
      case_ "${name}_spline" "$ev/apt/$f" --krl krc4_spline
      case_ "${name}_clearance" "$ev/apt/$f" --clearance 119.7
      case_ "${name}_tools" "$ev/apt/$f" --tools "$work/tools.xml"
    done
  fi
  if wants clsf; then
    for f in nx_kontur_nar_40_circle.cls nx_cutcom_load_tool.clsf; do
      name=ev_${f%%.*}
      case_ "${name}_circ" "$ev/clsf/$f" --krl krc4_circ
      case_ "${name}_msys" "$ev/clsf/$f" --msys apply
    done
    case_ ev_nx_nurbs_fixed_contour_spline "$ev/clsf/nx_nurbs_fixed_contour.clsf" --krl krc4_spline
    case_ ev_nx_nurbs_fixed_contour_loose "$ev/clsf/nx_nurbs_fixed_contour.clsf" --fit-tol 0.1 \
      --fit-ang-tol 1
    case_ ev_nx_variable_contour_5axis_nofit "$ev/clsf/nx_variable_contour_5axis.cls" \
      --msys apply --fit-tol 0
    case_ ev_nx_cycle_drill_deep_msys "$ev/clsf/nx_cycle_drill_deep.clsf" --msys apply
  fi
else
  echo "parity: note: ../shared/evaldata not present, only the examples are compared"
fi

echo "parity: $pass passed, $fail failed"
((fail == 0))
