#!/usr/bin/env bash
# Writes an NX postprocessor that runs redpost (docs/nx-integration.md, "Installing into NX"):
# the Post Builder triple NAME.tcl (the event handler file, which sources redpost's handlers),
# NAME.def (the definition file) and NAME.pui (Post Builder's file of the post), and
# NAME_settings.tcl, the redpost settings of this post (the cell and the template set given here;
# every other setting at convert's default, to edit in the file). Prints the template_post.dat
# line that makes the post appear in NX's Postprocess dialog.
#
# Usage: scripts/make_nx_post.sh --cell CELL.xml --krl SET -o DIR [--name NAME] [--lib LIBDIR]
#                                [--tcl-dir DIR]
#   --krl      a shipped set (krc4_lin, krc4_spline, krc2_lin, krc4_circ) or a template file
#   --name     the post's name (letters, digits, _; default REDPOST_<cell file's name>)
#   --lib      the folder of redpost's pkgIndex.tcl (default: found by the handlers: the install
#              layout, or the source tree's build/plugin)
#   --tcl-dir  the folder of redpost_post.tcl (default: this script's ../tcl)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
cell="" krl="" out="" name="" lib="" tcl_dir=$here/../tcl
usage() {
  echo "usage: $0 --cell CELL.xml --krl SET -o DIR [--name NAME] [--lib LIBDIR] [--tcl-dir DIR]" >&2
  [[ -n "${1:-}" ]] && echo "make_nx_post: $1" >&2
  exit 1
}
while (($#)); do
  case $1 in
    --cell | --krl | -o | --output | --name | --lib | --tcl-dir)
      (($# >= 2)) || usage "$1 needs a value"
      case $1 in
        --cell) cell=$2 ;; --krl) krl=$2 ;; -o | --output) out=$2 ;; --name) name=$2 ;;
        --lib) lib=$2 ;; --tcl-dir) tcl_dir=$2 ;;
      esac
      shift 2 ;;
    -h | --help) usage ;;
    *) usage "unexpected argument '$1'" ;;
  esac
done
[[ -n "$cell" && -n "$krl" && -n "$out" ]] || usage "--cell, --krl and -o are required"
[[ -f "$cell" ]] || usage "--cell $cell: no such file"
[[ -d "$out" ]] || usage "-o $out: the folder does not exist; create it first"
[[ -f "$tcl_dir/redpost_post.tcl" ]] || usage "--tcl-dir $tcl_dir has no redpost_post.tcl"
abs() { (cd "$(dirname "$1")" && echo "$(pwd)/$(basename "$1")"); }
cell=$(abs "$cell")
out=$(cd "$out" && pwd)
tcl_dir=$(cd "$tcl_dir" && pwd)
case $krl in
  */* | *.xml)
    [[ -f "$krl" ]] || usage "--krl $krl: no such file"
    krl=$(abs "$krl") ;;
  krc4_lin | krc4_spline | krc2_lin | krc4_circ) ;;
  *) usage "--krl $krl: a shipped set (krc4_lin, krc4_spline, krc2_lin, krc4_circ) or a file" ;;
esac
if [[ -z "$name" ]]; then
  stem=$(basename "$cell" .xml)
  name=REDPOST_${stem//[^A-Za-z0-9_]/_}
fi
[[ "$name" =~ ^[A-Za-z][A-Za-z0-9_]*$ ]] || usage "--name $name: letters, digits and _, a letter first"
[[ -z "$lib" || -f "$lib/pkgIndex.tcl" ]] || usage "--lib $lib has no pkgIndex.tcl"
[[ -z "$lib" ]] || lib=$(cd "$lib" && pwd)
for f in "$name.tcl" "$name.def" "$name.pui" "${name}_settings.tcl"; do
  [[ ! -e "$out/$f" ]] || usage "$out/$f exists: remove it or choose another --name"
done
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')

# Every write goes to a temporary first: a run that fails leaves no half post.
tmp=$(mktemp -d "$out/.make_nx_post.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

# The settings: redpost's defaults, with this post's cell, template set and library.
tcl_quote() { printf '{%s}' "$1"; }
sed -e "s|^    variable cell .*|    variable cell $(tcl_quote "$cell")|" \
    -e "s|^    variable krl .*|    variable krl $(tcl_quote "$krl")|" \
    -e "s|^    variable library_dir .*|    variable library_dir $(tcl_quote "$lib")|" \
    "$tcl_dir/redpost_settings.tcl" >"$tmp/${name}_settings.tcl"
grep -q "variable cell {$cell}" "$tmp/${name}_settings.tcl" ||
  usage "$tcl_dir/redpost_settings.tcl: no 'variable cell' line to set"
sed -i "1i # The redpost settings of the NX post $name (written by make_nx_post.sh, $stamp).\\
# Edit them here; docs/nx-integration.md lists every setting and its redpost convert option." \
  "$tmp/${name}_settings.tcl"

# The event handler file: NX's base procs when NX has them, then redpost's handlers, which
# replace every MOM_* event proc they define.
cat >"$tmp/$name.tcl" <<EOF
# $name.tcl: the event handler file of the NX postprocessor $name, which writes KUKA KRL with
# redpost (docs/nx-integration.md). Written by make_nx_post.sh, $stamp.
#
# The program is written by redpost (NAME.src/.dat next to NX's output file); NX's own output
# file stays empty. The settings are ${name}_settings.tcl next to this file.

# NX's base procs (listing file, warnings) first, once per interpreter, where NX provides them:
# redpost's handlers are sourced after them and replace the MOM_* procs they define.
if {[llength [info commands MOM_ask_env_var]] && ![info exists mom_sys_post_initialized]} {
    set redpost_cam_post_dir [MOM_ask_env_var UGII_CAM_POST_DIR]
    if {![info exists mom_sys_ugpost_base_initialized] &&
            [file exists [file join \$redpost_cam_post_dir ugpost_base.tcl]]} {
        source [file join \$redpost_cam_post_dir ugpost_base.tcl]
        set mom_sys_ugpost_base_initialized 1
    }
    set mom_sys_post_initialized 1
}

set redpost_settings_file [file join [file dirname [file normalize [info script]]] \\
    ${name}_settings.tcl]
source [list $tcl_dir/redpost_post.tcl]
EOF

# The definition file: redpost writes the program itself, so no address or block is used; a
# sequence and a plain text block keep NX's own output file well formed.
cat >"$tmp/$name.def" <<EOF
# $name.def: the definition file of the NX postprocessor $name (redpost writes the program;
# nothing here is used for it). Written by make_nx_post.sh, $stamp.
MACHINE redpost

FORMATTING
{
  WORD_SEPARATOR " "
  END_OF_LINE ""
  SEQUENCE sequence_number 10 10 1 99999

  FORMAT Text "%s"
  FORMAT Digit_5 "&_05_00"

  ADDRESS N
  {
    FORMAT Digit_5
    FORCE off
    LEADER "N"
  }
  ADDRESS Text
  {
    FORMAT Text
    FORCE always
  }

  BLOCK_TEMPLATE sequence_number
  {
    N[\$mom_seqnum]
  }
  BLOCK_TEMPLATE redpost_text
  {
    Text[\$mom_pprint]
  }
}
EOF

# Post Builder's file of the post: its version, the two files and the kinematics. Opening the
# post in Post Builder and saving it would rewrite $name.tcl without redpost's handlers: keep it
# out of Post Builder (docs/nx-integration.md).
cat >"$tmp/$name.pui" <<EOF
## POSTBUILDER_VERSION=2012.0.1.0
#
# $name.pui: the Post Builder file of the NX postprocessor $name (redpost, written by
# make_nx_post.sh, $stamp). The program is redpost's; do not save this post from Post Builder.
#
## POST EVENT HANDLER START
def_file  $name.def
tcl_file  $name.tcl
## POST EVENT HANDLER END

## KINEMATIC VARIABLES START
"\$mom_kin_machine_type"  "3_axis_mill"
"\$mom_kin_output_unit"   "MM"
## KINEMATIC VARIABLES END
EOF

for f in "$name.tcl" "$name.def" "$name.pui" "${name}_settings.tcl"; do
  mv "$tmp/$f" "$out/$f"
done
echo "make_nx_post: wrote $out/$name.tcl, $name.def, $name.pui and ${name}_settings.tcl"
echo "make_nx_post: add this line to NX's template_post.dat (see docs/nx-integration.md):"
echo "$name,$out/$name.tcl,$out/$name.def"
