# The helpers of the axis-speed tests (test_speeds.sh, test_spline.sh), sourced after
# harness.sh: the reference cell, the checks from the written text, and the runs below.
cell=$SRC/definitions/cells/andres2011_kr15_track_table.xml
check_py=$SRC/tests/cli/speed_check.py
py=python3

# speeds NAME CL_FILE [convert options...]: converts with a joints log and runs the check (with
# --feed 10000 when NAME starts with "fast" or "evalfast": the time at the written $VEL.CP
# against the time at that feed).
speeds() {
  local name=$1 cl=$2
  shift 2
  mkdir -p "$TMP/$name"
  run convert "$cl" --cell "$cell" -o "$TMP/$name" --name P --joints-csv "$TMP/$name/joints.csv" "$@"
  expect_rc 0
  expect_out "cycle time "
  expect_out "axis speeds: at most "
  local feed=()
  [[ $name == fast* ]] && feed=(--feed 10000)
  # Issue 17: at a production feed the real CAM files take at most 10 % longer than the feed asks.
  [[ $name == evalfast* ]] && feed=(--feed 10000 --max-time-ratio 1.10)
  $py "$check_py" "$TMP/$name/P.src" "$TMP/$name/joints.csv" "$cell" "${feed[@]}" \
    >"$TMP/check" 2>&1 || fail "$name: $(cat "$TMP/check")"
  echo "cli.speeds: $name: $(tr '\n' ' ' <"$TMP/check")"
  # The motions shorter than one interpolation cycle: convert's count (from its own figures)
  # and the check's (from the written text) agree but for the motions the check cannot measure
  # (a LIN after a PTP to axes has no printed start).
  local said counted unmeasured
  said=$(sed -n 's/^interpolation cycle 12 ms: \([0-9]*\) of .*/\1/p' "$TMP/out")
  counted=$(sed -n 's/^speed_check: \([0-9]*\) of [0-9]* CP motions last less than one .*/\1/p' "$TMP/check")
  unmeasured=$(sed -n 's/.*(\([0-9]*\) not measured)$/\1/p' "$TMP/check")
  [[ -n "$said" && -n "$counted" && -n "$unmeasured" ]] || fail "$name: no count of short motions"
  local gap=$((said - counted))
  ((gap >= 0 && gap <= unmeasured)) ||
    fail "$name: convert says $said motions are shorter than a cycle, the program shows $counted"
}

# fast CL_FILE OUT: the CL file with every feed set to 10 000 mm/min (a cycle's feed too).
fast() {
  sed -E 's#FEDRAT/MMPM,[ ]*[0-9.]+#FEDRAT/MMPM,10000#; s#FEDRAT/[ ]*[0-9.]+,[ ]*MMPM#FEDRAT/10000,MMPM#; s#^(CYCLE/.*MMPM,)[ ]*[0-9.]+#\110000#' \
    "$1" >"$2"
  grep -Eq 'FEDRAT/(MMPM,10000|10000,MMPM)|^CYCLE/.*MMPM,10000' "$2" || fail "no feed replaced in $1"
}

# exact_set NAME: the shipped template set NAME printed with 6 decimals (a file in $TMP): a
# program of it states the CL points to 1e-6 mm, so that a check against them needs no slack.
exact_set() {
  local out=$TMP/${1}_exact.xml
  [[ -f $out ]] ||
    sed 's#<numbers [^>]*>#<numbers position="6" angle="6" external="6" velocity="6" rpm="0"/>#' \
      "$SRC/definitions/krl/$1.xml" >"$out"
  echo "$out"
}

# fit NAME CL_FILE [convert options...]: converts CL_FILE with the point reduction (the default)
# and without it (--fit-tol 0, the same set printed with 6 decimals), both with a joints log, and
# checks from the two written programs that every CL point lies within 0.01 mm and 0.1 deg of
# the reduced program's path as it is printed, with no slack (tests/cli/fit_check.py), and the
# reduced one's axis speeds (speed_check.py).
fit() {
  local name=$1 cl=$2
  shift 2
  speeds "$name" "$cl" "$@"
  cp "$TMP/out" "$TMP/$name.out"
  local ref_options=() set=krc4_lin
  while (($#)); do
    if [[ $1 == --krl ]]; then
      set=$2
      shift 2
    else
      ref_options+=("$1")
      shift
    fi
  done
  mkdir -p "$TMP/${name}_ref"
  # One file (--max-bytes): the comparison reads the stretches between PTPs, and a part's start
  # is one.
  run convert "$cl" --cell "$cell" -o "$TMP/${name}_ref" --name P --fit-tol 0 -q \
    --max-bytes 100000000 --krl "$(exact_set "$set")" "${ref_options[@]}"
  expect_rc 0
  $py "$SRC/tests/cli/fit_check.py" "$TMP/$name/P.src" "$TMP/${name}_ref/P.src" \
    --slack-mm 1e-6 --slack-deg 1e-5 >"$TMP/fit" 2>&1 || fail "$name: $(cat "$TMP/fit")"
  echo "cli.speeds: $name: $(cat "$TMP/fit")"
  # Issue 30: with the reduction no CP motion lasts less than one cycle at its \$VEL.CP, as
  # convert says and as the check counts from the text.
  grep -q "^interpolation cycle 12 ms: 0 of " "$TMP/$name.out" ||
    fail "$name: $(grep '^interpolation' "$TMP/$name.out")"
  grep -q "^speed_check: 0 of [0-9]* CP motions last less than one" "$TMP/check" ||
    fail "$name: $(grep 'last less than' "$TMP/check")"
}
