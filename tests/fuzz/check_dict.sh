#!/usr/bin/env bash
# Checks libFuzzer dictionaries against the syntax libFuzzer accepts (ParseDictionaryFile):
# blank lines, '#' comments, and entries name="value" or "value" where the value is printable
# ASCII whose only escapes are \\, \" and \xHH. libFuzzer refuses a whole run on one bad line,
# so CI's fuzz step would fail; this catches it in the normal suite first.
#
# Usage: check_dict.sh FILE...   exit 1, naming file:line, if a file has a bad line or no entry.
set -euo pipefail
entry='[[:space:]]*([A-Za-z0-9_]+=)?"(\\\\|\\"|\\x[0-9A-Fa-f]{2}|[^\\"])*"[[:space:]]*'
status=0
for file in "$@"; do
  bad=$(LC_ALL=C grep -nvE "^(|#.*|$entry)$" "$file" || true)
  bad=$bad$(LC_ALL=C grep -n '[^ -~]' "$file" || true)
  if [ -n "$bad" ]; then
    first=${bad%%$'\n'*}
    echo "$file:${first%%:*}: not a libFuzzer dictionary entry: ${first#*:}" >&2
    echo "  write an entry as \"value\" with only \\\\, \\\" and \\xHH escapes" >&2
    status=1
  elif ! LC_ALL=C grep -qE "^$entry$" "$file"; then
    echo "$file: no entries" >&2
    status=1
  fi
done
exit $status
