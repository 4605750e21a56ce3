#!/usr/bin/env bash
# Checks libFuzzer dictionaries against the syntax libFuzzer accepts (ParseDictionaryFile):
# blank lines, '#' comments, and entries name="value" or "value" where the value's only escapes
# are \\, \" and \xHH. libFuzzer refuses a whole run on one bad line, so CI's fuzz step would
# fail; this catches it in the normal suite first.
#
# Usage: check_dict.sh FILE...   exit 1 naming file:line on the first bad entry of each file.
set -euo pipefail
status=0
entry='^[[:space:]]*([A-Za-z0-9_]+=)?"(\\\\|\\"|\\x[0-9A-Fa-f]{2}|[^\\"])*"[[:space:]]*$'
for file in "$@"; do
  n=0
  entries=0
  while IFS= read -r line || [ -n "$line" ]; do
    n=$((n + 1))
    case $line in
      '' | \#*) continue ;;
    esac
    if ! LC_ALL=C grep -Eq "$entry" <<<"$line" || LC_ALL=C grep -q '[^ -~]' <<<"$line"; then
      echo "$file:$n: not a libFuzzer dictionary entry: $line" >&2
      echo "  write an entry as \"value\" with only \\\\, \\\" and \\xHH escapes" >&2
      status=1
      break
    fi
    entries=$((entries + 1))
  done <"$file"
  if [ "$entries" -eq 0 ]; then
    echo "$file: no entries" >&2
    status=1
  fi
done
exit $status
