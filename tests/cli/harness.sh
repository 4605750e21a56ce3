# The shared part of the CLI test scripts: sourced as
#
#   . "$(dirname "$0")/harness.sh" NAME "$@"     # NAME: the test's name; "$@": REDPOST SOURCE_DIR
#
# It sets BIN, SRC and a scratch directory TMP (removed on exit), and defines the helpers below.
# A failed expectation prints the check's name, stdin, stdout, stderr and exit code, and exits 1.
set -euo pipefail

HARNESS_NAME=$1
shift
if [[ $# -ne 2 ]]; then
  echo "usage: $0 <path-to-redpost> <source-dir>" >&2
  exit 1
fi
BIN=$1
SRC=$2
[[ -x "$BIN" ]] || { echo "$HARNESS_NAME: FAIL: '$BIN' is not an executable" >&2; exit 1; }

TMP=$(mktemp -d "${TMPDIR:-/tmp}/redpost_${HARNESS_NAME//./_}.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

checks=0
current=""
RC=""
OUT=""
ERR=""

fail() {
  {
    echo "$HARNESS_NAME: FAIL: ${current}: $*"
    if [[ -f "$TMP/in" ]]; then echo "--- stdin:"; cat "$TMP/in"; fi
    echo "--- stdout:"; cat "$TMP/out" 2>/dev/null || true
    echo "--- stderr:"; cat "$TMP/err" 2>/dev/null || true
    echo "--- exit code: ${RC:-?}"
  } >&2
  exit 1
}

begin() { current=$1; }
passed() { checks=$((checks + 1)); }

# run ARGS...: runs redpost with no input; stdout and stderr to $TMP/out, $TMP/err (and OUT, ERR),
# the exit code to RC.
run() {
  rm -f "$TMP/in"
  RC=0
  "$BIN" "$@" </dev/null >"$TMP/out" 2>"$TMP/err" || RC=$?
  OUT=$(cat "$TMP/out")
  ERR=$(cat "$TMP/err")
}

# run_with_stdin TEXT ARGS...: the same with TEXT on stdin. The input comes from a file, not a
# pipe, so that an early exit of redpost cannot turn into a SIGPIPE status.
run_with_stdin() {
  printf '%s' "$1" >"$TMP/in"
  shift
  RC=0
  "$BIN" "$@" <"$TMP/in" >"$TMP/out" 2>"$TMP/err" || RC=$?
  OUT=$(cat "$TMP/out")
  ERR=$(cat "$TMP/err")
}

expect_rc() { [[ "$RC" -eq "$1" ]] || fail "exit code $RC, expected $1"; }
expect_out() { grep -qF -- "$1" "$TMP/out" || fail "no '$1' in stdout"; }
expect_err() { grep -qF -- "$1" "$TMP/err" || fail "no '$1' in stderr"; }
