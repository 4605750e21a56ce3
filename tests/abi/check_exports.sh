#!/usr/bin/env bash
# libredpost.so exports the C ABI (rp_*) and the Tcl entry points, nothing else, and its SONAME
# is libredpost.so.<major>. Usage: check_exports.sh LIBRARY_FILE
set -euo pipefail
lib=$1
failed=0
# Defined dynamic symbols, without version suffixes and without the version node itself.
symbols=$(nm -D --defined-only "$lib" | awk '$2 != "A" {print $3}' | sed 's/@.*//' | sort -u)
others=$(echo "$symbols" | grep -Ev '^(rp_[a-z_]+|Redpost_Init|Redpost_SafeInit)$' || true)
if [ -n "$others" ]; then
  echo "unexpected exported symbols:"; echo "$others" | head -20; failed=1
fi
for f in rp_open rp_prepare rp_close rp_remove_temporaries rp_free rp_last_error rp_session_event rp_reader_open rp_circular_move \
         rp_joint_range rp_set_motion_observer rp_cycle_define rp_nurbs_move rp_machine_frame \
         rp_operator_text rp_warn rp_last_error_line rp_sync Redpost_Init; do
  # A here-string, not a pipe: grep -q stops at its match, and under pipefail the echo's SIGPIPE
  # would fail the check.
  grep -qx "$f" <<<"$symbols" || { echo "missing export: $f"; failed=1; }
done
soname=$(objdump -p "$lib" | awk '$1 == "SONAME" {print $2}')
if [ "$soname" != "libredpost.so.0" ]; then
  echo "SONAME is '$soname', expected libredpost.so.0"; failed=1
fi
[ "$failed" -eq 0 ] && echo "exports: $(echo "$symbols" | wc -l) symbols, all rp_* or Tcl entry points; SONAME $soname"
exit "$failed"
