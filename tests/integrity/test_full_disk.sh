#!/usr/bin/env bash
# A full disk: `redpost convert` (program, --joints-csv, --report) and `redpost calibrate -o`
# must stop with a clear message and exit code 2, and leave no file under a final name and no
# temporary (docs/reliability.md). Two ways of filling the disk, each run when possible:
#   - a 1 MiB tmpfs (needs mount, usually root): write() fails with ENOSPC;
#   - a file-size limit (ulimit -f): write() fails with EFBIG, since redpost ignores SIGXFSZ.
#
#   tests/integrity/test_full_disk.sh <redpost> <source-dir> <scratch-dir>
set -euo pipefail

if [[ $# -ne 3 ]]; then
  echo "usage: $0 <redpost> <source-dir> <scratch-dir>" >&2
  exit 1
fi
BIN=$1
SRC=$2
SCRATCH=$3
CELL=$SRC/definitions/cells/andres2011_kr15_track_table.xml
rm -rf "$SCRATCH"
mkdir -p "$SCRATCH"
# 20 000 poses: about 2 MB of KRL, twice what the disk takes.
# The rasters are converted with one motion per CL point (--fit-tol 0), for their size.
python3 "$SRC/tests/bench/make_raster_apt.py" 20000 "$SCRATCH/raster.apt"
python3 "$SRC/tests/bench/make_raster_apt.py" 300 "$SCRATCH/small.apt"
filler=""
checks=0
failures=0

fail() {
  echo "full-disk: FAIL: $name: $*" >&2
  sed 's/^/  stderr: /' "$SCRATCH/err" >&2
  failures=$((failures + 1))
}

# expect_clean NAME DIR FRAGMENT RC: exit 2, FRAGMENT on stderr, DIR empty.
expect_clean() {
  name=$1
  checks=$((checks + 1))
  if [[ "$4" -ne 2 ]]; then fail "exit code $4, expected 2"; return; fi
  grep -qF -- "$3" "$SCRATCH/err" || { fail "no '$3' on stderr"; return; }
  if [[ -n "$(ls -A "$2")" ]]; then fail "left behind: $(ls -A "$2" | tr '\n' ' ')"; return; fi
  echo "full-disk: $name: exit 2, '$(head -n 1 "$SCRATCH/err")', nothing left"
}

# run_all LABEL DIR FRAGMENT [PREFIX...]: every writer, with the output in DIR (emptied first).
run_all() {
  local label=$1 dir=$2 fragment=$3
  shift 3
  local rc
  rm -rf "${dir:?}"/* "${dir:?}"/.[!.]* 2>/dev/null || true
  rc=0
  "$@" "$BIN" convert "$SCRATCH/raster.apt" --fit-tol 0 --cell "$CELL" -o "$dir" -q 2>"$SCRATCH/err" || rc=$?
  expect_clean "$label: convert, the program" "$dir" "$fragment" "$rc"

  # The program goes elsewhere; the joints log (about 2 MB) fills the disk.
  rm -rf "${dir:?}"/* "${dir:?}"/.[!.]* 2>/dev/null || true
  rc=0
  "$@" "$BIN" convert "$SCRATCH/raster.apt" --fit-tol 0 --cell "$CELL" -o "$SCRATCH/elsewhere" -q \
    --joints-csv "$dir/joints.csv" 2>"$SCRATCH/err" || rc=$?
  rm -rf "$SCRATCH/elsewhere"/*
  expect_clean "$label: convert, --joints-csv" "$dir" "$fragment" "$rc"

  # 300 poses: a 35 kB program and a 93 kB report; the disk keeps 64 kB free (filler), or the
  # file-size limit is 64 KiB.
  [[ -n "$filler" ]] || return 0
  rm -rf "${dir:?}"/* "${dir:?}"/.[!.]* 2>/dev/null || true
  head -c "$filler" /dev/zero >"$dir/.filler" 2>/dev/null || true
  rc=0
  "$@" "$BIN" convert "$SCRATCH/small.apt" --fit-tol 0 --cell "$CELL" -o "$SCRATCH/elsewhere" -q \
    --report "$dir/report.html" 2>"$SCRATCH/err" || rc=$?
  rm -rf "$SCRATCH/elsewhere"/* "$dir/.filler"
  expect_clean "$label: convert, --report" "$dir" "$fragment" "$rc"
}
mkdir -p "$SCRATCH/elsewhere"

# --- a full tmpfs ----------------------------------------------------------------------------
DISK=$SCRATCH/disk
mkdir -p "$DISK"
if mount -t tmpfs -o size=1m tmpfs "$DISK" 2>/dev/null; then
  trap 'umount "$DISK" 2>/dev/null || true' EXIT
  filler=$((1024 * 1024 - 64 * 1024))
  run_all "tmpfs 1 MiB" "$DISK" "No space left on device"
  filler=""
  # calibrate -o: the calibrated cell (a few kB) on a disk with no room left at all.
  "$BIN" calibrate simulate --cell "$CELL" --true "$CELL" --noise-mm 0 \
    -o "$SCRATCH/readings.csv" >/dev/null
  head -c 2000000 /dev/zero >"$DISK/filler" 2>/dev/null || true
  rc=0
  "$BIN" calibrate --cell "$CELL" --readings "$SCRATCH/readings.csv" -o "$DISK/cal.xml" \
    >/dev/null 2>"$SCRATCH/err" || rc=$?
  rm -f "$DISK/filler"
  expect_clean "tmpfs 1 MiB: calibrate -o" "$DISK" "No space left on device" "$rc"
  umount "$DISK"
  trap - EXIT
else
  echo "full-disk: no tmpfs (mount not permitted here): only the file-size limit is tested"
fi

# --- a file-size limit -----------------------------------------------------------------------
# ulimit -f counts 1024-byte blocks here (bash): 256 = 256 KiB per file, half a part's default
# budget.
limited() { (ulimit -f 256 && exec "$@"); }
limited64() { (ulimit -f 64 && exec "$@"); }
LIM=$SCRATCH/limited
mkdir -p "$LIM"
run_all "ulimit -f 256 KiB" "$LIM" "File too large" limited
rm -rf "${LIM:?}"/*
rc=0
limited64 "$BIN" convert "$SCRATCH/small.apt" --fit-tol 0 --cell "$CELL" -o "$SCRATCH/elsewhere" -q \
  --report "$LIM/report.html" 2>"$SCRATCH/err" || rc=$?
rm -rf "$SCRATCH/elsewhere"/*
expect_clean "ulimit -f 64 KiB: convert, --report" "$LIM" "File too large" "$rc"

# The report is written before the program is renamed into place: a report that does not fit
# stops the run with an older program of the same name still whole, not replaced.
rm -rf "${LIM:?}"/* "$SCRATCH/elsewhere"/*
"$BIN" convert "$SCRATCH/raster.apt" --fit-tol 0 --cell "$CELL" -o "$SCRATCH/elsewhere" --name small -q
old=$(cd "$SCRATCH/elsewhere" && sha256sum -- *)
rc=0
limited64 "$BIN" convert "$SCRATCH/small.apt" --fit-tol 0 --cell "$CELL" -o "$SCRATCH/elsewhere" -q \
  --report "$LIM/report.html" 2>"$SCRATCH/err" || rc=$?
name="ulimit -f 64 KiB: --report over an old program"
checks=$((checks + 1))
if [[ $rc -ne 2 ]]; then
  fail "exit code $rc, expected 2"
elif [[ $(cd "$SCRATCH/elsewhere" && sha256sum -- *) != "$old" ]] ||
  [[ -n $(ls -A "$LIM") ]] || [[ -n $(find "$SCRATCH/elsewhere" -name '.*') ]]; then
  fail "the old program changed, or files were left: $(ls -A "$SCRATCH/elsewhere" "$LIM")"
else
  echo "full-disk: $name: exit 2, the old program whole, nothing left"
fi
rm -rf "$SCRATCH/elsewhere"/*

echo "full-disk: $checks checks, $failures failed"
[[ $failures -eq 0 ]]
