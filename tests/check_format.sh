#!/usr/bin/env bash
# Every C/C++ file of the project, and the reports' JavaScript, is clang-formatted with the
# project's .clang-format.
set -euo pipefail
cd "$1"
if ! command -v clang-format >/dev/null; then
  echo "clang-format is not installed (scripts/setup.sh installs it)"; exit 1
fi
bad=0
while IFS= read -r -d '' f; do
  if ! clang-format --style=file --dry-run -Werror "$f" >/dev/null 2>&1; then
    echo "not formatted: $f"; bad=1
  fi
done < <(find core plugin tests examples -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.c' -o -name '*.js' \) -print0)
[ "$bad" -eq 0 ] && echo "all C/C++ and JavaScript files are clang-formatted"
exit "$bad"
