#!/usr/bin/env bash
# scripts/make_nx_post.sh (issue 29, "Install into NX"): the post it writes for a cell and a
# template set (NAME.tcl, NAME.def, NAME.pui and its settings) runs redpost's handlers with
# them: a CL file replayed through the post, as NX would source it, gives the program
# `redpost convert` writes with that cell and set. Bad arguments write nothing.
#
# Usage: test_nx_post.sh REDPOST TCLSH LIBDIR SOURCE_DIR WORK_DIR
set -uo pipefail
redpost=$1 tclsh=$2 libdir=$3 src=$4 work=$5
cell=$src/definitions/cells/andres2011_kr15_track_table.xml
make=$src/scripts/make_nx_post.sh
rm -rf "$work" && mkdir -p "$work/post" "$work/bad"
fail=0
no() { echo "FAIL $*"; fail=1; }

"$make" --cell "$cell" --krl krc2_lin -o "$work/post" --name RP_KRC2 --lib "$libdir" \
  >"$work/make.out" 2>&1 || no "make_nx_post.sh failed: $(cat "$work/make.out")"
for f in RP_KRC2.tcl RP_KRC2.def RP_KRC2.pui RP_KRC2_settings.tcl; do
  [[ -s "$work/post/$f" ]] || no "no $f"
done
[[ "$(head -1 "$work/post/RP_KRC2.pui")" == "## POSTBUILDER_VERSION="* ]] || no "the .pui's first line"
grep -q '^def_file  RP_KRC2.def$' "$work/post/RP_KRC2.pui" || no "the .pui names no .def"
grep -q '^tcl_file  RP_KRC2.tcl$' "$work/post/RP_KRC2.pui" || no "the .pui names no .tcl"
grep -q '^MACHINE ' "$work/post/RP_KRC2.def" || no "the .def has no MACHINE"
grep -q "^RP_KRC2,$work/post/RP_KRC2.tcl,$work/post/RP_KRC2.def\$" "$work/make.out" ||
  no "no template_post.dat line: $(cat "$work/make.out")"

# Through the post, as NX sources it, against convert with the post's cell and set.
for input in pocket_arcs.apt surface_5axis.cls; do
  a=$work/convert_$input b=$work/post_$input
  mkdir -p "$a" "$b"
  "$redpost" convert "$src/examples/cl/$input" --cell "$cell" --krl krc2_lin -o "$a" --name P -q \
    2>/dev/null || no "convert $input"
  "$tclsh" "$src/tcl/nx_replay.tcl" --post "$work/post/RP_KRC2.tcl" -o "$b" --name P -q \
    "$src/examples/cl/$input" 2>"$work/post_$input.err" || no "the post on $input: $(cat "$work/post_$input.err")"
  diff -r "$a" "$b" >/dev/null || no "$input: the post's program is not convert's"
  grep -q '^DEF P( )' "$b/P.src" && ! grep -q 'EK(MACHINE_DEF' "$b/P.src" || no "$input: not KR C2"
done

# Bad arguments: a message, exit 1, nothing written.
bad() {
  if "$make" "$@" >"$work/bad.out" 2>&1; then no "accepted: $*"; fi
  [[ -z "$(ls -A "$work/bad")" ]] || no "files left by: $*: $(ls -A "$work/bad")"
}
bad --cell "$work/none.xml" --krl krc4_lin -o "$work/bad"
bad --cell "$cell" --krl krc9 -o "$work/bad"
bad --cell "$cell" --krl krc4_lin -o "$work/none"
bad --cell "$cell" --krl krc4_lin -o "$work/bad" --name "9 bad"
bad --cell "$cell" --krl krc4_lin -o "$work/bad" --lib "$work"
"$make" --cell "$cell" --krl krc4_lin -o "$work/post" --name RP_KRC2 >/dev/null 2>&1 &&
  no "a second post of the same name was written over the first"

((fail == 0)) && echo "nx_post: the post runs redpost with its settings; bad arguments write nothing"
exit $fail
