#!/usr/bin/env bash
# No function in core/ or plugin/ over about 120 lines (docs/architecture.md): clang-tidy's
# readability-function-size over every source, with a build's compile_commands.json.
# Usage: scripts/check_function_size.sh [BUILD_DIR]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f "$build/compile_commands.json" ] || { echo "no $build/compile_commands.json: build first"; exit 2; }
command -v clang-tidy >/dev/null || { echo "clang-tidy is not installed"; exit 2; }
config='{Checks: "-*,readability-function-size", CheckOptions: [{key: readability-function-size.LineThreshold, value: 120}]}'
out=$(find core plugin -name '*.cpp' -print0 | sort -z |
  xargs -0 -P "$(nproc 2>/dev/null || echo 2)" -n 4 clang-tidy -p "$build" --quiet --config="$config" 2>/dev/null |
  grep -A1 'warning: function' || true)
if [ -n "$out" ]; then
  echo "$out"
  echo "functions over 120 lines: split them into named steps (docs/architecture.md)"
  exit 1
fi
echo "no function in core/ or plugin/ over 120 lines"
