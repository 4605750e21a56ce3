#!/usr/bin/env bash
# A kill between two renames of `redpost convert`'s final step (docs/reliability.md). A program
# split into parts is several files renamed one by one, the main .src last; with
# kill_at_rename.so the process is killed before each rename in turn, into an empty folder and
# into a folder that holds an older program of the same name. Whatever the moment:
#   - the main .src, when present, is either the old one with all its files intact, or the new
#     one with every file of the new program byte-identical to an uninterrupted run;
#   - never an old main .src beside new files, nor a new one beside missing or old files.
# Parts or a .dat without a main .src can remain: nothing calls them.
#
#   tests/integrity/test_rename_window.sh <redpost> <kill_at_rename.so> <source-dir> <scratch-dir>
set -euo pipefail

if [[ $# -ne 4 ]]; then
  echo "usage: $0 <redpost> <kill_at_rename.so> <source-dir> <scratch-dir>" >&2
  exit 1
fi
BIN=$1
SHIM=$2
SRC=$3
SCRATCH=$4
CELL=$SRC/definitions/cells/andres2011_kr15_track_table.xml
rm -rf "$SCRATCH"
mkdir -p "$SCRATCH/new" "$SCRATCH/old"
python3 "$SRC/tests/bench/make_raster_apt.py" 3000 "$SCRATCH/new/raster.apt"
python3 "$SRC/tests/bench/make_raster_apt.py" 1500 "$SCRATCH/old/raster.apt"

# Under ASan the shim cannot come first in the library list; it needs no instrumentation.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"

convert() {  # convert INPUT OUT MODE
  local split=()
  [[ $3 == split ]] && split=(--split 1000)
  mkdir -p "$2"
  "$BIN" convert "$1" --cell "$CELL" -o "$2" -q "${split[@]}"
}
# Hidden leftovers of a kill (temporaries, the lock file, old files moved aside) are no program.
same() { diff -rq -x '.*~' "$1" "$2" >/dev/null; }

checked=0
failed=0
for mode in single split; do
  convert "$SCRATCH/new/raster.apt" "$SCRATCH/ref_new_$mode" "$mode"
  convert "$SCRATCH/old/raster.apt" "$SCRATCH/ref_old_$mode" "$mode"
  files=$(ls "$SCRATCH/ref_new_$mode" | wc -l)
  old_files=$(ls "$SCRATCH/ref_old_$mode" | wc -l)
  # One kill before each rename (over an old program: each old file is first moved aside, then
  # each new file renamed in), and one past the last (the run completes).
  renames=$((files + old_files))
  for ((n = 1; n <= renames + 1; ++n)); do
    for start in empty old; do
      out=$SCRATCH/run_${mode}_${start}_$n
      mkdir -p "$out"
      [[ $start == old ]] && cp "$SCRATCH/ref_old_$mode"/* "$out/"
      REDPOST_KILL_AT_RENAME=$n LD_PRELOAD=$SHIM convert "$SCRATCH/new/raster.apt" "$out" \
        "$mode" >/dev/null 2>&1 || true
      if [[ ! -e "$out/raster.src" ]]; then
        outcome="no main .src"
      elif same "$SCRATCH/ref_new_$mode" "$out"; then
        outcome="the new program, complete"
      elif [[ $start == old ]] && same "$SCRATCH/ref_old_$mode" "$out"; then
        outcome="the old program, intact"
      else
        outcome="A MAIN .src BESIDE A MIXED OR INCOMPLETE SET: $(ls -A "$out" | tr '\n' ' ')"
        failed=$((failed + 1))
      fi
      checked=$((checked + 1))
      echo "rename-window: $mode, $start folder, killed at rename $n: $outcome"
    done
  done
  # The last run was not killed: it must have completed.
  same "$SCRATCH/ref_new_$mode" "$SCRATCH/run_${mode}_old_$((renames + 1))" ||
    { echo "rename-window: FAIL: the shim broke an uninterrupted run" >&2; exit 1; }
done
echo "rename-window: $checked kills, $failed left a main .src beside a mixed or incomplete set"
[[ $failed -eq 0 ]] || { echo "rename-window: FAIL" >&2; exit 1; }
