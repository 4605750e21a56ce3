#!/usr/bin/env bash
# What `redpost convert` does to the files around it (docs/reliability.md, "Output files"):
#   - a second writer of the same program gets a clear error and the first one's program is
#     whole, byte for byte;
#   - symbolic links planted at temporary or final names are never written through;
#   - outputs that name an input, each other, a device or a link are refused, the input intact;
#   - a run that cannot complete its swap keeps the old split program whole;
#   - SIGTERM, SIGINT and SIGHUP, and a Tcl `exit` with a session open, leave no temporary.
#
#   tests/integrity/test_output_files.sh <redpost> <source-dir> <scratch-dir> <tclsh> <libdir>
set -euo pipefail

if [[ $# -ne 5 ]]; then
  echo "usage: $0 <redpost> <source-dir> <scratch-dir> <tclsh> <libdir>" >&2
  exit 1
fi
BIN=$1
SRC=$2
SCRATCH=$3
TCLSH=$4
LIBDIR=$5
CELL=$SRC/definitions/cells/andres2011_kr15_track_table.xml
APT=$SRC/examples/cl/pocket_arcs.apt
rm -rf "$SCRATCH"
mkdir -p "$SCRATCH"
# Long enough (about 2 s) that a second run and a signal land while it writes.
# The rasters are converted with one motion per CL point (--fit-tol 0): a long run, a program
# of many parts; point reduction would make both small.
python3 "$SRC/tests/bench/make_raster_apt.py" 200000 "$SCRATCH/big.apt"
python3 "$SRC/tests/bench/make_raster_apt.py" 3000 "$SCRATCH/mid.apt"
checks=0
failures=0

fail() {
  echo "output-files: FAIL: $*" >&2
  [[ -f $SCRATCH/err ]] && sed 's/^/  stderr: /' "$SCRATCH/err" >&2
  failures=$((failures + 1))
}
ok() { echo "output-files: $*"; }
# Every hidden leftover of a run: temporaries, lock files, old files moved aside.
leftovers() { find "$1" -maxdepth 1 -name '.*~' -printf '%f '; }
sums() { (cd "$1" && sha256sum -- *.src *.dat 2>/dev/null) || true; }

# run NAME EXPECTED_RC FRAGMENT CMD...: the exit code and a fragment of stderr.
run() {
  local name=$1 want_rc=$2 fragment=$3 rc=0
  shift 3
  checks=$((checks + 1))
  "$@" >/dev/null 2>"$SCRATCH/err" || rc=$?
  if [[ $rc -ne $want_rc ]]; then fail "$name: exit code $rc, expected $want_rc"; return 0; fi
  if [[ -n $fragment ]] && ! grep -qF -- "$fragment" "$SCRATCH/err"; then
    fail "$name: no '$fragment' on stderr"
    return 0
  fi
  ok "$name: exit $rc${fragment:+, '$(head -n 1 "$SCRATCH/err")'}"
}

# wait_for FILE: until it exists (at most 20 s).
wait_for() {
  for _ in $(seq 200); do [[ -e $1 ]] && return 0; sleep 0.1; done
  return 1
}

# --- a second writer of the same program -----------------------------------------------------
REF=$SCRATCH/ref
mkdir -p "$REF"
"$BIN" convert "$SCRATCH/big.apt" --fit-tol 0 --cell "$CELL" -o "$REF" --name BIG -q
OUT=$SCRATCH/two_writers
mkdir -p "$OUT"
"$BIN" convert "$SCRATCH/big.apt" --fit-tol 0 --cell "$CELL" -o "$OUT" --name BIG -q 2>"$SCRATCH/err1" &
first=$!
wait_for "$OUT/.BIG.lock~" || fail "two writers: the first run never took its lock"
run "two writers: the second is refused" 2 \
  "is being written into this folder by another redpost run or session" \
  "$BIN" convert "$SRC/examples/cl/long_pass.apt" --cell "$CELL" -o "$OUT" --name BIG -q
rc=0
wait "$first" || rc=$?
checks=$((checks + 1))
if [[ $rc -ne 0 ]]; then
  fail "two writers: the first run failed ($rc): $(cat "$SCRATCH/err1")"
elif ! diff -rq -x '.*~' "$REF" "$OUT" >/dev/null; then
  fail "two writers: the first run's program differs from an undisturbed run"
elif [[ -n $(leftovers "$OUT") ]]; then
  fail "two writers: left behind: $(leftovers "$OUT")"
else
  ok "two writers: the first run's program is the undisturbed one, byte for byte"
fi
# A lock held by another process (flock(1) on the same file) is seen as such.
flock "$OUT/.BIG.lock~" sleep 3 &
holder=$!
sleep 0.3
run "a held lock" 2 "is being written" "$BIN" convert "$APT" --cell "$CELL" -o "$OUT" --name BIG -q
wait "$holder" || true

# --- symbolic links planted in the output folder ---------------------------------------------
OUT=$SCRATCH/links
mkdir -p "$OUT"
printf 'precious\n' >"$SCRATCH/victim"
# The temporaries' old fixed names, and a link at the joints CSV's.
ln -s "$SCRATCH/victim" "$OUT/.POCKET.src.part~"
ln -s "$SCRATCH/victim" "$OUT/.POCKET.dat.part~"
ln -s "$SCRATCH/victim" "$OUT/.joints.csv.part~"
run "links at temporary names" 0 "" \
  "$BIN" convert "$APT" --cell "$CELL" -o "$OUT" --name POCKET --joints-csv "$OUT/joints.csv" -q
checks=$((checks + 1))
if [[ $(cat "$SCRATCH/victim") != precious ]]; then
  fail "links at temporary names: the link's target was written"
elif [[ -L $OUT/POCKET.src || ! -f $OUT/POCKET.src || -L $OUT/joints.csv ]]; then
  fail "links at temporary names: an output is a link, or missing"
else
  ok "links at temporary names: the target is untouched, the outputs are regular files"
fi
# A link at the final name is refused (a rename would replace the link, not write its target).
ln -s "$SCRATCH/victim" "$OUT/LINKED.src"
run "a link at the program's name" 2 "is a symbolic link" \
  "$BIN" convert "$APT" --cell "$CELL" -o "$OUT" --name LINKED -q
[[ -L $OUT/LINKED.src && $(cat "$SCRATCH/victim") == precious ]] ||
  fail "a link at the program's name: the link or its target changed"

# --- outputs that name an input, each other, a device or a link ------------------------------
OUT=$SCRATCH/clash
mkdir -p "$OUT"
cp "$APT" "$OUT/in.apt"
cp "$CELL" "$OUT/cell.xml"
before=$(sha256sum "$OUT/in.apt" "$OUT/cell.xml")
run "--joints-csv is the CL input" 2 "--joints-csv names the same file as the CL input" \
  "$BIN" convert "$OUT/in.apt" --cell "$OUT/cell.xml" -o "$OUT" --joints-csv "$OUT/in.apt" -q
run "--report is the cell (by another path)" 2 "--report names the same file as --cell" \
  "$BIN" convert "$OUT/in.apt" --cell "$OUT/cell.xml" -o "$OUT" --report "$OUT/./cell.xml" -q
run "--report is the program" 2 "--report names the same file as the program's .src" \
  "$BIN" convert "$OUT/in.apt" --cell "$OUT/cell.xml" -o "$OUT" --name P --report "$OUT/P.src" -q
run "--report is --joints-csv" 2 "--report names the same file as --joints-csv" \
  "$BIN" convert "$OUT/in.apt" --cell "$OUT/cell.xml" -o "$OUT" --joints-csv "$OUT/j" \
  --report "$OUT/j" -q
run "--report is a character device" 2 "--report is a character device" \
  "$BIN" convert "$OUT/in.apt" --cell "$OUT/cell.xml" -o "$OUT" --report /dev/null -q
ln -s /proc/self/fd/1 "$OUT/stdout.csv"
run "--joints-csv is a link to a descriptor" 2 "the joints CSV is a symbolic link" \
  "$BIN" convert "$OUT/in.apt" --cell "$OUT/cell.xml" -o "$OUT" --joints-csv "$OUT/stdout.csv" -q
checks=$((checks + 1))
if [[ $(sha256sum "$OUT/in.apt" "$OUT/cell.xml") != "$before" || ! -c /dev/null ]]; then
  fail "clashes: an input or /dev/null changed"
elif [[ -n $(find "$OUT" -maxdepth 1 \( -name '*.src' -o -name '*.dat' -o -name '.*~' \)) ]]; then
  fail "clashes: left behind: $(ls -A "$OUT" | tr '\n' ' ')"
else
  ok "clashes: the inputs and /dev/null are intact, nothing was written"
fi

# --- a swap that cannot complete keeps the old split program ---------------------------------
OUT=$SCRATCH/old_kept
mkdir -p "$OUT"
"$BIN" convert "$SCRATCH/mid.apt" --fit-tol 0 --cell "$CELL" -o "$OUT" --name MID --split 1000 -q
old=$(sums "$OUT")
# A folder where the new run's second part goes.
rm "$OUT/MID_P002.src"
mkdir "$OUT/MID_P002.src"
old=$(sums "$OUT")
run "a folder under a part's name" 2 "is a folder" \
  "$BIN" convert "$SRC/examples/cl/long_pass.apt" --cell "$CELL" -o "$OUT" --name MID --fit-tol 0 --split 20 -q
checks=$((checks + 1))
if [[ $(sums "$OUT") != "$old" || ! -d $OUT/MID_P002.src || -n $(leftovers "$OUT") ]]; then
  fail "a folder under a part's name: the old program changed: $(ls -A "$OUT" | tr '\n' ' ')"
else
  ok "a folder under a part's name: the old program is whole, nothing left behind"
fi
# An immutable old part (chattr +i, where the file system has the flag): the swap cannot move
# it aside, and puts back what it had moved.
rmdir "$OUT/MID_P002.src"
"$BIN" convert "$SCRATCH/mid.apt" --fit-tol 0 --cell "$CELL" -o "$OUT" --name MID --split 1000 -q
old=$(sums "$OUT")
if chattr +i "$OUT/MID_P002.src" 2>/dev/null; then
  rc=0
  "$BIN" convert "$SRC/examples/cl/long_pass.apt" --cell "$CELL" -o "$OUT" --name MID --fit-tol 0 \
    --split 20 -q 2>"$SCRATCH/err" || rc=$?
  chattr -i "$OUT/MID_P002.src"
  checks=$((checks + 1))
  if [[ $rc -ne 2 ]] || ! grep -qF "the old files are kept" "$SCRATCH/err"; then
    fail "an immutable part: exit $rc"
  elif [[ $(sums "$OUT") != "$old" || -n $(leftovers "$OUT") ]]; then
    fail "an immutable part: the old program changed: $(ls -A "$OUT" | tr '\n' ' ')"
  else
    ok "an immutable part: exit 2, '$(grep -m1 '^redpost:' "$SCRATCH/err")', the old program whole"
  fi
else
  ok "SKIP an immutable part: this file system has no immutable flag"
fi

# --- stop signals, and Tcl exit ----------------------------------------------------------------
for sig in TERM INT HUP; do
  OUT=$SCRATCH/signal_$sig
  mkdir -p "$OUT"
  "$BIN" convert "$SCRATCH/big.apt" --fit-tol 0 --cell "$CELL" -o "$OUT" --joints-csv "$OUT/j.csv" \
    --report "$OUT/r.html" -q 2>/dev/null &
  pid=$!
  wait_for "$OUT/.big.lock~" || fail "SIG$sig: the run never started"
  sleep 0.5
  kill -s "$sig" "$pid"
  rc=0
  wait "$pid" || rc=$?
  checks=$((checks + 1))
  want=$((128 + $(kill -l "$sig")))
  if [[ $rc -ne $want ]]; then
    fail "SIG$sig: exit code $rc, expected $want (ended by the signal)"
  elif [[ -n $(ls -A "$OUT") ]]; then
    fail "SIG$sig: left behind: $(ls -A "$OUT" | tr '\n' ' ')"
  else
    ok "SIG$sig: ended by the signal, nothing left in the folder"
  fi
done

# The same with the pipeline's threads writing the parts (--threads 2): a stop request that lands
# on one thread while another makes a part's temporary must still leave nothing (a temporary
# made after the handler's clean-up once did). Staggered times, so that some land mid-part.
for k in 1 2 3 4 5 6; do
  OUT=$SCRATCH/threads_$k
  mkdir -p "$OUT"
  "$BIN" convert "$SCRATCH/big.apt" --fit-tol 0 --cell "$CELL" -o "$OUT" --threads 2 -q \
    2>/dev/null &
  pid=$!
  wait_for "$OUT/.big.lock~" || fail "--threads 2, run $k: the run never started"
  sleep "0.$((k * 15))"
  kill -s HUP "$pid"
  rc=0
  wait "$pid" || rc=$?
  checks=$((checks + 1))
  if [[ $rc -ne $((128 + $(kill -l HUP))) ]]; then
    fail "--threads 2, SIGHUP after 0.$((k * 15)) s: exit code $rc, expected $((128 + $(kill -l HUP)))"
  elif [[ -n $(ls -A "$OUT") ]]; then
    fail "--threads 2, SIGHUP after 0.$((k * 15)) s: left behind: $(ls -A "$OUT" | tr '\n' ' ')"
  fi
done
ok "--threads 2: six stop requests at staggered times, nothing left behind"

# A FIFO with no writer as the CL input: the run waits for it before any output file exists.
# SIGKILL, so that no handler can tidy up: the folder is empty only if nothing was made.
OUT=$SCRATCH/fifo
mkdir -p "$OUT"
mkfifo "$SCRATCH/in.fifo"
rc=0
timeout -s KILL 2 "$BIN" convert "$SCRATCH/in.fifo" --cell "$CELL" -o "$OUT" -q 2>/dev/null ||
  rc=$?
checks=$((checks + 1))
if [[ $rc -ne 137 ]]; then
  fail "a FIFO without a writer: exit $rc, expected 137 (still waiting when timeout killed it)"
elif [[ -n $(ls -A "$OUT") ]]; then
  fail "a FIFO without a writer: files made while waiting: $(ls -A "$OUT" | tr '\n' ' ')"
else
  ok "a FIFO without a writer: waits with nothing in the output folder"
fi

OUT=$SCRATCH/tcl_exit
mkdir -p "$OUT"
cat >"$SCRATCH/exit.tcl" <<TCL
lappend auto_path $LIBDIR
package require redpost
set s [::redpost::open -cell $CELL -output $OUT -name TCLEXIT -source t.apt -plan local \
    -joints-csv $OUT/j.csv]
::redpost::feed \$s 900
::redpost::linear_move \$s -120 -440 110 0 0 1
::redpost::linear_move \$s -72 -480 57 0 0 1
if {[llength [glob -nocomplain -directory $OUT -types hidden *]] == 0} {
    puts "no temporaries while the session is open"
    exit 1
}
exit 0
TCL
run "Tcl exit with a session open" 0 "" "$TCLSH" "$SCRATCH/exit.tcl"
[[ -z $(ls -A "$OUT") ]] || fail "Tcl exit: left behind: $(ls -A "$OUT" | tr '\n' ' ')"

echo "output-files: $checks checks, $failures failed"
[[ $failures -eq 0 ]]
