#!/usr/bin/env bash
# The bad-input corpus (docs/reliability.md): every case of cases.txt is run in a fresh, empty
# output directory, and must give the expected exit code (2 unless the manifest says
# otherwise), the expected place (file:line) and message fragment on stderr, and leave the
# output directory empty: no .src, .dat, .csv, .json, .html, .tmp or .part~ file, finished or
# not. Cases marked maxrss=KB must also stay under that peak resident size.
#
#   tests/bad-input/run.sh <redpost> <source-dir> <scratch-dir>
#
# Large and special inputs (a 100 MB line, 100 000 nested elements, an unreadable file) are
# made here in <scratch-dir>/gen, never committed.
set -euo pipefail

if [[ $# -ne 3 ]]; then
  echo "usage: $0 <redpost> <source-dir> <scratch-dir>" >&2
  exit 1
fi
BIN=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
SCRATCH=$3
[[ -x "$BIN" ]] || { echo "bad-input: FAIL: '$BIN' is not an executable" >&2; exit 1; }
CASES=$SRC/tests/bad-input/cases
MANIFEST=$SRC/tests/bad-input/cases.txt

rm -rf "$SCRATCH"
mkdir -p "$SCRATCH"
SCRATCH=$(cd "$SCRATCH" && pwd)
GEN=$SCRATCH/gen
mkdir -p "$GEN"

# --- generated inputs ------------------------------------------------------------------------
# n copies of a character, without holding them in memory.
repeat() { head -c "$2" /dev/zero | tr '\0' "$1"; }

# A 100 MB single line (100 000 000 bytes, no newline inside) in each text format.
{ printf 'PARTNO/LONG\nUNITS/MM\nPPRINT/'; repeat A 100000000; printf '\n'; } >"$GEN/long_line.apt"
{ printf 'plane,distance,x,y,z,a,b,c,q1,q2\nz,0.2,'; repeat 1 100000000; printf '\n'; } \
  >"$GEN/long_line.csv"
mkdir -p "$GEN/long_line_krl"
{ printf 'DEF LONG( )\n; '; repeat A 100000000; printf '\nEND\n'; } >"$GEN/long_line_krl/LONG.src"
# 100 000 nested elements under each XML root.
deep() {
  { printf '<?xml version="1.0"?>\n<%s format="1">' "$1"; repeat '<' 100000 | sed 's/</<a>/g'
    repeat '<' 100000 | sed 's|<|</a>|g'; printf '</%s>\n' "$1"; } >"$2"
}
deep cell "$GEN/deep_cell.xml"
deep krl-templates "$GEN/deep_krl.xml"
deep placement_job "$GEN/deep_job.xml"
# A 20 MiB cell (sparse: costs no disk), beyond the 16 MiB limit of a definition.
truncate -s 20M "$GEN/big_cell.xml"
# The deflection (issue 20): a cell without joint stiffness, a feed of 0 and a cut without a
# spindle speed.
sed '/<stiffness/d' "$SRC/definitions/cells/andres2011_kr15_track_table.xml" \
  >"$GEN/no_stiffness_cell.xml"
printf 'UNITS/MM\nCUTTER/16.,0\nLOADTL/1\nSPINDL/8000,RPM,CLW\nFEDRAT/0\nGOTO/-100,-300,60\n' \
  >"$GEN/feed_zero.apt"
printf 'UNITS/MM\nCUTTER/16.,0\nLOADTL/1\nFEDRAT/MMPM,2000\nGOTO/-100,-300,60\nGOTO/-100,-310,60\n' \
  >"$GEN/no_spindle.apt"
# A spindle speed no milling spindle runs (issue 31): refused at its line.
printf 'UNITS/MM\nCUTTER/16.,0\nLOADTL/1\nSPINDL/RPM,5000000,CLW\nFEDRAT/MMPM,2000\nGOTO/-100,-300,60\n' \
  >"$GEN/spindle_5e6.apt"
# Template sets whose fixed text a controller (and redpost check) would reject (issue 31): a
# 40-character name in the src skeleton (line 40, the $ADVANCE line of krc4_lin), and a
# statement that is not KRL.
sed 's/^\$ADVANCE = 3$/AN_IDENTIFIER_OF_FORTY_CHARACTERS_LONG_X = 3/' \
  "$SRC/definitions/krl/krc4_lin.xml" >"$GEN/long_name_krl.xml"
sed 's#^    $TOOL = {tool}$#    SELECT TOOL {tool} NOW#' \
  "$SRC/definitions/krl/krc4_lin.xml" >"$GEN/bad_statement_krl.xml"
# Binary garbage: a compressed CL file (a common mistake) and a compressed readings file.
gzip -c "$SRC/examples/cl/pocket_arcs.apt" >"$GEN/pocket_arcs.apt.gz"
# A NUL in an INSERT's text (it once cut the text there), and a cell file with a second root.
printf 'PARTNO/NUL\nUNITS/MM\nLOADTL/1\nINSERT/A\000BCD\nGOTO/-100,-300,100\n' >"$GEN/nul_in_insert.apt"
{ cat "$SRC/definitions/cells/andres2011_kr15_track_table.xml"; printf '<cell name="second"/>\n'; } \
  >"$GEN/two_roots_cell.xml"
printf 'plane,distance,x,y,z,a,b,c,q1,q2\n' | cat - "$GEN/pocket_arcs.apt.gz" >"$GEN/garbage.csv"
# XML the standard refuses and tinyxml2 would read (issue 48): a comment holding "--" in a cell,
# a bare '&' in a template set, a '<' in a cutting file's value, an undefined entity in a job.
sed '0,/<!-- Collision bodies/s//<!-- Collision -- bodies/' \
  "$SRC/definitions/cells/andres2011_kr15_track_table.xml" >"$GEN/comment_dd_cell.xml"
sed 's/<krl-templates name="krc4_lin"/<krl-templates name="krc4 \& lin"/' \
  "$SRC/definitions/krl/krc4_lin.xml" >"$GEN/bare_amp_krl.xml"
sed 's/<operation name="AB"/<operation name="A<B"/' \
  "$SRC/examples/placement/caro2014_cutting.xml" >"$GEN/lt_in_value_cutting.xml"
sed '0,/<placement_job /s//<placement_job note="\&nbsp;" /' \
  "$SRC/examples/placement/caro2014_job.xml" >"$GEN/entity_job.xml"
# An unreadable file (chmod 000 does not stop root: those cases are skipped as root).
cp "$SRC/examples/cl/pocket_arcs.apt" "$GEN/unreadable.apt"
chmod 000 "$GEN/unreadable.apt"
# A regular file: a path under it cannot be created, not even by root.
printf 'not a directory\n' >"$GEN/a_file"
# A directory where a file is expected.
mkdir -p "$GEN/a_dir.apt"
# A 50 kB token on one line of joint values: refused without echoing it whole.
{ printf '0 0 '; repeat 9 50000; printf '\n'; } >"$GEN/fk_long_token.txt"
# A CL file whose lines end in CR alone, and one named like a KRL keyword.
tr '\n' '\r' <"$SRC/examples/cl/pocket_arcs.apt" >"$GEN/cr_only.apt"
cp "$SRC/examples/cl/pocket_arcs.apt" "$GEN/end.apt"
cp "$SRC/examples/cl/pocket_arcs.apt" "$GEN/a_very_long_program_name_x.apt"
# A placement job whose program is named like a KRL keyword (refused before the optimisation).
sed -e "s|../../definitions|$SRC/definitions|" -e 's|name="CARO2014_PLACEMENT"|name="end"|' \
  "$SRC/examples/placement/caro2014_job.xml" >"$GEN/job_name_end.xml"
# Inputs that an output names: copies, so that a regression destroys nothing in the tree.
cp "$SRC/definitions/cells/andres2011_kr15_track_table.xml" "$GEN/cell_copy.xml"
cp "$SRC/examples/placement/caro2014_job.xml" "$GEN/job_copy.xml"
cp "$SRC/examples/cl/pocket_arcs.apt" "$GEN/in_copy.apt"

# --- the runner ------------------------------------------------------------------------------
if [[ $(id -u) -eq 0 ]]; then IS_ROOT=1; else IS_ROOT=0; fi
if [[ -x /usr/bin/time ]]; then
  measure() { /usr/bin/time -f %M -o "$1" "${@:2}"; }
else
  # Peak RSS of the child in KB from getrusage, as /usr/bin/time -f %M reports it.
  measure() {
    python3 - "$@" <<'PY'
import resource, subprocess, sys
rc = subprocess.call(sys.argv[2:])
open(sys.argv[1], "w").write("%d\n" % resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
sys.exit(rc)
PY
  }
fi

# Under a sanitizer (REDPOST_SANITIZER, set by scripts/reliability.sh) the process starts with
# ~70 MB of shadow memory and runtime before it reads a byte: the maxrss= bounds then apply to
# the growth over that start-up peak, measured here on `redpost --version`. A file read whole
# (100 MB and more) still exceeds them.
rss_baseline=0
if [[ -n "${REDPOST_SANITIZER:-}" ]]; then
  measure "$SCRATCH/baseline_rss" "$BIN" --version >/dev/null
  rss_baseline=$(tail -n 1 "$SCRATCH/baseline_rss")
  echo "bad-input: under ${REDPOST_SANITIZER}: RSS bounds are over a start-up peak of ${rss_baseline} KB"
fi

before=$(cd "$CASES" && find . | LC_ALL=C sort | sha256sum)
total=0
passed=0
skipped=0
failed=0
fail() {
  echo "bad-input: FAIL: $name: $*" >&2
  echo "  command: ${argv[*]}" >&2
  echo "  exit code: $rc" >&2
  sed 's/^/  stderr: /' "$dir/err" | head -c 2000 >&2
  failed=$((failed + 1))
}

while IFS= read -r raw || [[ -n "$raw" ]]; do
  [[ -z "${raw// /}" || "$raw" =~ ^[[:space:]]*# ]] && continue
  IFS='|' read -r name args want_rc where fragment options <<<"$raw"
  trim() { local s=$1; s=${s#"${s%%[![:space:]]*}"}; printf '%s' "${s%"${s##*[![:space:]]}"}"; }
  name=$(trim "$name")
  args=$(trim "$args")
  want_rc=$(trim "$want_rc")
  where=$(trim "$where")
  fragment=$(trim "$fragment")
  options=$(trim "${options:-}")
  total=$((total + 1))
  dir=$SCRATCH/$name
  rm -rf "$dir"
  mkdir -p "$dir/out"
  if [[ " $options " == *" skip-root "* && $IS_ROOT -eq 1 ]]; then
    echo "bad-input: SKIP $name: running as root, for whom chmod 000 does not stop reads"
    skipped=$((skipped + 1))
    continue
  fi
  # Placeholders are replaced word by word, so paths with blanks stay one argument.
  argv=()
  read -ra words <<<"$args"
  for w in "${words[@]}"; do
    w=${w//@CASES@/$CASES}
    w=${w//@GEN@/$GEN}
    w=${w//@OUT@/$dir/out}
    w=${w//@SRC@/$SRC}
    w=${w//@BIN@/$BIN}
    w=${w//@CELL@/$SRC/definitions/cells/andres2011_kr15_track_table.xml}
    w=${w//@KRL@/$SRC/definitions/krl/krc4_lin.xml}
    argv+=("$w")
  done
  # stdin=PATH: what the command reads on its standard input (else /dev/null).
  input=/dev/null
  for o in $options; do
    if [[ $o == stdin=* ]]; then
      input=${o#stdin=}
      input=${input//@GEN@/$GEN}
    fi
  done
  rc=0
  (cd "$dir" && measure "$dir/rss" timeout 120 "$BIN" "${argv[@]}" <"$input" >"$dir/stdout" \
    2>"$dir/err") || rc=$?
  if [[ "$rc" -ne "$want_rc" ]]; then
    fail "exit code $rc, expected $want_rc"
    continue
  fi
  # Errors are on stderr; the findings of `redpost check` (exit 1) on stdout.
  cat "$dir/err" "$dir/stdout" >"$dir/messages"
  if [[ "$where" != "-" ]] && ! grep -qF -- "$where" "$dir/messages"; then
    fail "the message does not name '$where'"
    continue
  fi
  if [[ -n "$fragment" ]] && ! grep -qF -- "$fragment" "$dir/messages"; then
    fail "the message does not say '$fragment'"
    continue
  fi
  if [[ " $options " == *" accepted "* ]]; then
    # Accepted on purpose (docs/reliability.md says why): a complete program, no temporaries.
    if ! ls "$dir/out"/*.src >/dev/null 2>&1 || ls -A "$dir/out" | grep -q 'part~$'; then
      fail "accepted input, but no complete program: $(ls -A "$dir/out" | tr '\n' ' ')"
      continue
    fi
  elif [[ -n "$(ls -A "$dir/out")" ]]; then
    fail "files left in the output directory: $(ls -A "$dir/out" | tr '\n' ' ')"
    continue
  fi
  if [[ -n "$(ls -A "$dir" | grep -vxE 'out|rss|stdout|err|messages')" ]]; then
    fail "files left in the working directory: $(ls -A "$dir" | tr '\n' ' ')"
    continue
  fi
  for opt in $options; do
    if [[ "$opt" == maxrss=* ]]; then
      rss=$(tail -n 1 "$dir/rss")
      bound=$((${opt#maxrss=} + rss_baseline))
      if [[ "$rss" -gt "$bound" ]]; then
        fail "peak RSS $rss KB, more than $bound KB"
        continue 2
      fi
      echo "bad-input: $name: peak RSS $rss KB (bound $bound KB)"
    fi
  done
  passed=$((passed + 1))
done <"$MANIFEST"

chmod 600 "$GEN/unreadable.apt"
rm -rf "$GEN"  # 300 MB of generated inputs
after=$(cd "$CASES" && find . | LC_ALL=C sort | sha256sum)
if [[ "$before" != "$after" ]]; then
  echo "bad-input: FAIL: files were added to or removed from $CASES" >&2
  failed=$((failed + 1))
fi
echo "bad-input: $total cases: $passed passed, $skipped skipped, $failed failed"
[[ $failed -eq 0 ]]
