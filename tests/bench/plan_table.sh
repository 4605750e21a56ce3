#!/usr/bin/env bash
# The whole-path plan against holding the external axes (issue 47; docs/redundancy.md, "Held or
# moved"): every example, the 20 000-pose raster and every file of ../shared/evaldata, at its own
# feeds and at 10 000 mm/min, converted with each preset and with the track and the table held
# at a grid of values (tests/cli/plan_dominance.py). Prints one Markdown table per preset and
# feed: the plan's cycle time, track travel (reversals), table travel and lowest 1/kappa_F, the
# fastest held program with 1/kappa_F >= 0.3, and whether the plan is dominated.
#
# Usage: tests/bench/plan_table.sh [BUILD_DIR] [PRESETS...]   (default: smooth fast stiff)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
shift || true
presets=("${@:-smooth fast stiff}")
[[ $# -gt 0 ]] || presets=(smooth fast stiff)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"
python3 "$top/tests/bench/make_raster_apt.py" 20000 "$work/raster_20k.apt"
files=("$top"/examples/cl/* "$work/raster_20k.apt")
evaldata=$top/../shared/evaldata
if [[ -d $evaldata ]]; then
  for f in "$evaldata"/apt/*.apt "$evaldata"/clsf/*; do
    case $(basename "$f") in
      swcam_cutcom_multi_op.apt) ;;  # refused by design (a cycle left on over a tool change)
      nx_variable_contour_5axis.cls) files+=("$f::--msys apply") ;;
      *) files+=("$f") ;;
    esac
  done
fi
for preset in "${presets[@]}"; do
  for feed in 0 10000; do
    echo
    echo "preset $preset, $([[ $feed == 0 ]] && echo "the files' own feeds" || echo "every feed $feed mm/min"):"
    echo
    python3 "$top/tests/cli/plan_dominance.py" --redpost "$build/plugin/redpost" \
      --cell "$top/definitions/cells/andres2011_kr15_track_table.xml" --feed "$feed" \
      --options "--preset $preset" "${files[@]}" || true
  done
done
