# Sourced by the convert benchmarks (deflection_bench.sh, report_bench.sh) once $top (the source
# tree) and $build are set: sets $redpost, $cell (the Andres cell) and $work (a folder removed at
# exit), prints the machine line, and defines best_of_3 INPUT OUT [convert options...], which
# prints "seconds peak_kib", the fastest of three `redpost convert` runs (GNU time).
redpost=$build/plugin/redpost
cell=$top/definitions/cells/andres2011_kr15_track_table.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v /usr/bin/time >/dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC')"

best_of_3() {
  local input=$1 out=$2
  shift 2
  local best_s="" best_k=0
  for _ in 1 2 3; do
    rm -rf "$out" && mkdir -p "$out"
    /usr/bin/time -f "%e %M" -o "$work/t" "$redpost" convert "$input" --cell "$cell" -o "$out" \
      --name P -q "$@" 2>/dev/null
    read -r s k <"$work/t"
    if [[ -z "$best_s" ]] || awk -v a="$s" -v b="$best_s" 'BEGIN { exit !(a < b) }'; then
      best_s=$s
      best_k=$k
    fi
  done
  echo "$best_s $best_k"
}
