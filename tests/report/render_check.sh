#!/bin/sh
# Renders a redpost HTML report in headless Chromium and checks it (issue 9):
#   - no console messages (the report's script logs nothing, so any message is an error),
#   - the page script ran to its end (it marks <html data-report-ready="N">),
#   - the DOM holds exactly EXPECTED <svg class="plot"> elements,
#   - the file refers to nothing outside itself (no http(s) URLs but the SVG namespace),
#   - the screenshot is not blank (PNG decoded by png_image.py: python3's zlib, no extra packages).
# Usage: render_check.sh REPORT.html EXPECTED_SVG_COUNT OUT.png [WINDOW_HEIGHT]
# Exit 0 = pass, 1 = fail, 77 = skipped (no chromium; REDPOST_CHROMIUM overrides the binary).
set -u
if [ $# -lt 3 ]; then
  echo "usage: $0 REPORT.html EXPECTED_SVG_COUNT OUT.png [WINDOW_HEIGHT]" >&2
  exit 2
fi
html=$1
expected=$2
png=$3
height=${4:-768}

# REDPOST_CHROMIUM names another browser binary (a path or a command name).
if [ -n "${REDPOST_CHROMIUM:-}" ]; then
  browser=$(command -v "$REDPOST_CHROMIUM" || true)
else
  browser=$(command -v chromium || command -v chromium-browser || true)
fi
if [ -z "$browser" ]; then
  echo "SKIP: chromium is not installed (apt-get install chromium)"
  exit 77
fi
command -v python3 >/dev/null || { echo "SKIP: python3 is not installed"; exit 77; }
[ -f "$html" ] || { echo "FAIL: no report at $html" >&2; exit 1; }

here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT INT TERM
abs=$(cd "$(dirname "$html")" && pwd)/$(basename "$html")

# Each run gets a new, empty profile; nothing is fetched, synced or updated. The reports' 3D view
# draws with WebGL: without a GPU Chromium renders it with SwiftShader, and says nothing about it
# only when asked for it by these flags (else it logs a deprecation warning per context).
run_chromium() {
  profile=$(mktemp -d "$work/profile.XXXXXX")
  timeout 90 "$browser" --headless --no-sandbox --use-angle=swiftshader \
    --enable-unsafe-swiftshader --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$profile" --hide-scrollbars --enable-logging=stderr --v=0 "$@"
}

rm -f "$png"
run_chromium --window-size=1366,"$height" --screenshot="$png" "file://$abs" \
  >"$work/shot.out" 2>"$work/shot.err"
rc=$?
[ $rc -eq 0 ] || { echo "FAIL: chromium --screenshot exited with $rc" >&2; cat "$work/shot.err" >&2; exit 1; }
run_chromium --window-size=1366,"$height" --dump-dom "file://$abs" \
  >"$work/dom.html" 2>"$work/dom.err"
rc=$?
[ $rc -eq 0 ] || { echo "FAIL: chromium --dump-dom exited with $rc" >&2; cat "$work/dom.err" >&2; exit 1; }

python3 - "$here" "$html" "$work/dom.html" "$expected" "$png" "$work/shot.err" "$work/dom.err" <<'PY'
import re, sys

sys.dont_write_bytecode = True
sys.path.insert(0, sys.argv.pop(1))
import png_image  # tests/report/png_image.py

html_path, dom_path, expected, png_path, *logs = sys.argv[1:]
expected = int(expected)
failures = []

# Console: Chromium logs every console message and uncaught exception as "CONSOLE". One is
# Chromium's own and says nothing about the page: its GPU process's performance note after a
# pixel read-back on SwiftShader (scene_check.py lets the same one through).
notice = re.compile(r'"\[\.WebGL-0x[0-9a-f]+\]GL Driver Message \(OpenGL, Performance, \w+, \w+\): '
                    r'GPU stall due to ReadPixels"')
for log in logs:
    for line in open(log, encoding="utf-8", errors="replace"):
        if notice.search(line):
            print("note: Chromium's own notice, not failed on: " + line.strip())
        elif "CONSOLE" in line or "Uncaught" in line:
            failures.append("console: " + line.strip())

dom = open(dom_path, encoding="utf-8", errors="replace").read()
svgs = re.findall(r'<svg\b[^>]*\bclass="plot[" ]', dom)
if len(svgs) != expected:
    failures.append(f"{len(svgs)} <svg class=\"plot\"> elements in the DOM, expected {expected}")
m = re.search(r'<html\b[^>]*\bdata-report-ready="(\d+)"', dom)
if not m:
    failures.append("the page script did not run to its end (no data-report-ready)")
elif int(m.group(1)) != expected:
    failures.append(f"the page script saw {m.group(1)} plots, expected {expected}")

src = open(html_path, encoding="utf-8", errors="replace").read()
# The inlined libraries (three.js, <script data-library="...">) name their authors' sites and
# XML namespaces in comments and strings; the page itself must name nothing outside the file.
src = re.sub(r'<script data-library="[^"]*">.*?</script>', '', src, flags=re.S)
urls = set(re.findall(r'(?:https?|ftp)://[^\s"\'<>)]*', src)) - {"http://www.w3.org/2000/svg"}
if urls:
    failures.append("external references: " + ", ".join(sorted(urls)[:5]))
if re.search(r'<(?:script|img|link|iframe)\b[^>]*\b(?:src|href)="(?!data:)', src):
    failures.append("an element loads something by src/href")

try:
    # The first screenful (what the reader sees first) is judged; decoding in pure Python is
    # slow, and a taller page only adds more of the same.
    img = png_image.read(png_path, 800)
    w, h, bpp, rows = img.width, img.height, img.bpp, img.rows
    counts = {}
    for r in rows[::2]:  # every second row and column is plenty
        for i in range(0, len(r), 2 * bpp):
            px = r[i:i + 3]
            counts[px] = counts.get(px, 0) + 1
    total = sum(counts.values())
    top = max(counts.values())
    if len(counts) < 8 or (total - top) < 0.005 * total:
        failures.append(f"the screenshot looks blank ({len(counts)} colours, "
                        f"{100.0 * (total - top) / total:.2f} % not background)")
    else:
        print(f"screenshot {w}x{h}, top {len(rows)} rows: {len(counts)} colours, "
              f"{100.0 * (total - top) / total:.1f} % not background")
except Exception as e:  # a PNG we cannot read is a failure, not a pass
    failures.append(f"cannot read the screenshot {png_path}: {e}")

if failures:
    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    sys.exit(1)
print(f"PASS: {expected} plots, no console messages, self-contained, not blank")
PY
