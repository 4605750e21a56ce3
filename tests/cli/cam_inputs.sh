# The CAM inputs the whole-program tests convert (sourced after harness.sh): the examples, then
# every real CAM file of ../shared/evaldata when it is present, in `inputs`; `cam_options NAME`
# sets `opts` to what a file needs, or returns 1 for one refused by design.
inputs=("$SRC"/examples/cl/*)
eval_dir=$SRC/../shared/evaldata
if [[ -d $eval_dir ]]; then
  inputs+=("$eval_dir"/apt/*.apt "$eval_dir"/clsf/*)
else
  echo "$HARNESS_NAME: note: ../shared/evaldata not present, the real CAM files are skipped"
fi

cam_options() {
  opts=()
  case $1 in
    swcam_cutcom_multi_op.apt) return 1 ;;  # refused by design: a cycle on at a tool change
    nx_variable_contour_5axis.cls) opts=(--msys apply) ;;
  esac
  return 0
}
