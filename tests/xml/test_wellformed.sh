#!/usr/bin/env bash
# XML that is XML (issue 48): every XML file the project ships passes a standard parser
# (xmllint, Debian's libxml2-utils), and redpost's loader refuses exactly what xmllint refuses.
# The second half takes the Andres cell, changes one thing in it (a comment holding "--", a
# bare '&', an undefined entity, a '<' in a value, a second root, and things XML allows), and
# asks both: xmllint's verdict is the reference; redpost (`fk --cell`, which only loads the
# cell) must refuse the ill-formed ones at the same line with "not well-formed XML" or "second
# root", exit 2, and load the others.
#
# Usage: test_wellformed.sh REDPOST SOURCE_DIR WORK_DIR
set -uo pipefail
redpost=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
command -v xmllint >/dev/null || { echo "xml: xmllint is missing (scripts/setup.sh installs libxml2-utils)"; exit 1; }
fail=0 files=0

# 1. Every shipped XML file: definitions, examples, documentation, tests (but the bad-input
# corpus, whose cases are broken on purpose).
while IFS= read -r f; do
  files=$((files + 1))
  if ! xmllint --noout "$f" 2>"$work/lint.err"; then
    echo "FAIL xmllint refuses $f: $(head -c 300 "$work/lint.err")"
    fail=$((fail + 1))
  fi
done < <(find "$src/definitions" "$src/examples" "$src/docs" "$src/tests" -name '*.xml' \
           -not -path '*/bad-input/cases/*' | sort)
echo "xml: $files shipped XML files checked with xmllint"
# The documentation's ```xml blocks, which users copy.
blocks=$(python3 - "$src" "$work" <<'PY'
import glob, os, re, subprocess, sys
src, work = sys.argv[1], sys.argv[2]
for md in sorted(glob.glob(os.path.join(src, "docs", "*.md")) + [os.path.join(src, "README.md")]):
    text = open(md, encoding="utf-8").read()
    for m in re.finditer(r"```xml\n(.*?)```", text, re.S):
        line = text[: m.start()].count("\n") + 2
        r = subprocess.run(["xmllint", "--noout", "-"], input=m.group(1).encode(), capture_output=True)
        name = "%s:%d" % (os.path.relpath(md, src), line)
        print(("BAD " if r.returncode else "OK ") + name + " " + r.stderr.decode().split("\n")[0])
PY
)
while IFS= read -r b; do
  [[ -z "$b" ]] && continue
  files=$((files + 1))
  if [[ $b == BAD* ]]; then
    echo "FAIL xmllint refuses the block at ${b#BAD }"
    fail=$((fail + 1))
  fi
done <<<"$blocks"
echo "xml: $(grep -c . <<<"$blocks") XML blocks of the documentation checked with xmllint"

# 2. One change to the cell each: [name]=old|new (the first occurrence of old replaced).
cell=$src/definitions/cells/andres2011_kr15_track_table.xml
declare -a cases=(
  'comment_dd|<!-- Collision bodies|<!-- Collision -- bodies'
  'comment_end|ASSUMED. -->|ASSUMED. --->'
  'bare_amp|<cell name="|<cell name="A&B '
  'undefined_entity|<cell name="|<cell name="&nbsp;'
  'lt_in_value|<cell name="|<cell name="a<b '
  'second_root|</cell>|</cell><cell/>'
  'ok_amp_entity|<cell name="|<cell name="A&amp;B&#38;&#x26; '
  'ok_comment_amp|<!-- Collision bodies|<!-- Collision & < - bodies'
  'ok_gt_in_value|<cell name="|<cell name="a>b '
)
n=0
for c in "${cases[@]}"; do
  name=${c%%|*} rest=${c#*|}
  old=${rest%%|*} new=${rest#*|}
  f=$work/$name.xml
  OLD=$old NEW=$new python3 - "$cell" "$f" <<'PY'
import os, sys
text = open(sys.argv[1], encoding="utf-8").read()
old, new = os.environ["OLD"], os.environ["NEW"]
assert old in text, old
open(sys.argv[2], "w", encoding="utf-8").write(text.replace(old, new, 1))
PY
  n=$((n + 1))
  xmllint --noout "$f" 2>"$work/$name.lint"
  lint=$?
  lint_line=$(sed -n 's/^[^:]*:\([0-9]*\): parser error.*/\1/p' "$work/$name.lint" | head -1)
  "$redpost" fk --cell "$f" </dev/null >/dev/null 2>"$work/$name.err"
  rc=$?
  if ((lint == 0)); then
    if ((rc != 0)); then
      echo "FAIL $name: xmllint accepts it, redpost refuses: $(head -c 300 "$work/$name.err")"
      fail=$((fail + 1))
    else
      echo "xml: $name: both accept"
    fi
    continue
  fi
  where=$(grep -o "$name.xml:[0-9]*" "$work/$name.err" | head -1)
  if ((rc != 2)) || ! grep -q -e "not well-formed XML" -e "second root" "$work/$name.err"; then
    echo "FAIL $name: xmllint refuses it (line $lint_line), redpost exit $rc: $(head -c 300 "$work/$name.err")"
    fail=$((fail + 1))
  elif [[ "$where" != "$name.xml:$lint_line" ]]; then
    echo "FAIL $name: xmllint refuses it at line $lint_line, redpost at $where"
    fail=$((fail + 1))
  else
    echo "xml: $name: both refuse at line $lint_line"
  fi
done
echo "xml: $fail failure(s) of $((files + n)) checks"
((fail == 0))
