#!/bin/sh
# The C example of docs/c-abi.md, as a reader copies it: the ```c block is cut from the page,
# compiled as C99 against the header and the library, and run from another folder with the
# shipped cell and a fresh output folder. It must write DEMO.src.
#   run_doc_example.sh CC SOURCE_DIR INCLUDE_DIR LIBRARY_DIR WORK_DIR
set -eu
cc=$1
src=$2
include=$3
libdir=$4
work=$5
rm -rf "$work"
mkdir -p "$work/out"
awk '/^```c$/ { on = 1; next } /^```$/ { if (on) exit } on' "$src/docs/c-abi.md" >"$work/demo.c"
[ -s "$work/demo.c" ] || { echo "FAIL: no \`\`\`c block in docs/c-abi.md" >&2; exit 1; }
"$cc" -std=c99 -Wall -Werror "$work/demo.c" -I"$include" -L"$libdir" -lredpost -o "$work/demo"
cd "$work"
LD_LIBRARY_PATH=$libdir ./demo "$src/definitions/cells/andres2011_kr15_track_table.xml" out
[ -s out/DEMO.src ] || { echo "FAIL: the example wrote no DEMO.src" >&2; exit 1; }
echo "the example of docs/c-abi.md compiles, runs and writes out/DEMO.src"
