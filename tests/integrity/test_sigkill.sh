#!/usr/bin/env bash
# SIGKILL at random moments: `redpost convert` must never leave a .src or .dat under its final
# name unless the program is complete (docs/reliability.md). After each kill the output folder
# holds either no final .src/.dat, or exactly the files of an uninterrupted reference run, byte
# for byte (which `redpost check` passes). Temporaries (.NAME.part~) may remain: a killed process
# cannot remove them, but they never carry a final name.
#
#   tests/integrity/test_sigkill.sh <redpost> <source-dir> <scratch-dir> [runs] [poses]
set -euo pipefail

if [[ $# -lt 3 ]]; then
  echo "usage: $0 <redpost> <source-dir> <scratch-dir> [runs] [poses]" >&2
  exit 1
fi
BIN=$1
SRC=$2
SCRATCH=$3
RUNS=${4:-30}
POSES=${5:-200000}
SPLIT=40000
if [[ -n "${REDPOST_TEST_LIGHT:-}" ]]; then
  # Sanitizer builds (scripts/reliability.sh) convert ~8 times slower: a fifth of the program,
  # split in as many parts, and 12 kills. The plain suite runs the full test.
  RUNS=12
  POSES=$((POSES / 5))
  SPLIT=$((SPLIT / 5))
fi
CELL=$SRC/definitions/cells/andres2011_kr15_track_table.xml
rm -rf "$SCRATCH"
mkdir -p "$SCRATCH"
python3 "$SRC/tests/bench/make_raster_apt.py" "$POSES" "$SCRATCH/raster.apt"

# Reference runs, one file and split into parts (the split run renames many files).
declare -A EXTRA=([single]="" [split]="--split $SPLIT")
for mode in single split; do
  mkdir -p "$SCRATCH/ref_$mode"
  start=$(date +%s%N)
  # shellcheck disable=SC2086
  "$BIN" convert "$SCRATCH/raster.apt" --cell "$CELL" -o "$SCRATCH/ref_$mode" -q ${EXTRA[$mode]}
  elapsed_ms=$((($(date +%s%N) - start) / 1000000))
  eval "ref_ms_$mode=$elapsed_ms"
  # The reference is complete: every .src ends with END, and the split one (parts of at most
  # $SPLIT motions, within the controller's file size) passes `redpost check`.
  for f in "$SCRATCH/ref_$mode"/*.src; do
    [[ "$(tail -n 1 "$f" | tr -d '\r')" == "END" ]] ||
      { echo "sigkill: FAIL: reference $f does not end with END" >&2; exit 1; }
  done
  if [[ $mode == split ]]; then
    "$BIN" check "$SCRATCH/ref_$mode" --cell "$CELL" >/dev/null ||
      { echo "sigkill: FAIL: the reference program does not pass redpost check" >&2; exit 1; }
  fi
  echo "sigkill: reference ($mode): $(ls "$SCRATCH/ref_$mode" | wc -l) files, ${elapsed_ms} ms"
done

RANDOM=20240610  # a fixed seed: the same delays on every run of the test
none=0
complete=0
lost=0
temps=0
for ((i = 1; i <= RUNS; ++i)); do
  mode=$([[ $((i % 2)) -eq 0 ]] && echo split || echo single)
  ref_ms_var=ref_ms_$mode
  ref_ms=${!ref_ms_var}
  # Delays over 0..110 % of the uninterrupted run: some kills land after the end.
  delay_ms=$((RANDOM % (ref_ms * 11 / 10 + 1)))
  out=$SCRATCH/run_$i
  mkdir -p "$out"
  # shellcheck disable=SC2086
  "$BIN" convert "$SCRATCH/raster.apt" --cell "$CELL" -o "$out" -q ${EXTRA[$mode]} \
    >/dev/null 2>&1 &
  pid=$!
  sleep "$(printf '%d.%03d' $((delay_ms / 1000)) $((delay_ms % 1000)))"
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  finals=$(cd "$out" && ls -A | grep -Ei '\.(src|dat)$' || true)
  leftover=$(cd "$out" && ls -A | grep -c 'part~$' || true)
  temps=$((temps + leftover))
  if [[ -z "$finals" ]]; then
    none=$((none + 1))
    outcome="no program"
  elif [[ "$(cd "$SCRATCH/ref_$mode" && ls | sort)" == "$(echo "$finals" | sort)" ]] &&
    diff -rq -x '*part~' "$SCRATCH/ref_$mode" "$out" >/dev/null; then
    # Complete: the same set of final files as the reference, each byte-identical.
    complete=$((complete + 1))
    outcome="complete, identical to the reference"
  else
    lost=$((lost + 1))
    outcome="INCOMPLETE PROGRAM UNDER FINAL NAMES: $(echo "$finals" | tr '\n' ' ')"
  fi
  echo "sigkill: run $i ($mode): killed after ${delay_ms} ms: $outcome; $leftover temporaries"
done
echo "sigkill: $RUNS runs: $none without a program, $complete complete, $lost incomplete" \
  "under final names; $temps temporaries left in all"
[[ $lost -eq 0 ]] || { echo "sigkill: FAIL" >&2; exit 1; }
[[ $complete -gt 0 && $none -gt 0 ]] ||
  echo "sigkill: note: the delays did not cover both outcomes; change the seed or the size"
