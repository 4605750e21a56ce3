#!/usr/bin/env python3
"""Is the default plan ever beaten by holding the external axes still? (issue 47, item 3)

    plan_dominance.py --redpost BIN --cell CELL [--feed MMPM] [--jobs N] [--slack 0.02]
                      [--kappa 0.3] [--options "WORDS"] [--small-grid] FILE[::OPTIONS] ...

Converts every FILE with the default plan and with the track (E1) and the table (E2) held at a
grid of fixed values (`--lock E1=v --lock E2=w`): the track at the default program's first-pose
value, 300 mm either side of it and at its home; the table at the first-pose value and every
90 deg from it. OPTIONS (after `::`, words separated by spaces) are passed to every conversion
of that file, --options to every conversion (e.g. "--preset fast"). With --feed every FEDRAT (and a cycle's feed) is set to MMPM first.

From each written program (its .src files, as travel_check.py reads them) the track's and the
table's travel and the track's reversals; from redpost's summary the cycle time (the time model
of docs/timing.md over the written motions) and the lowest 1/kappa_F of the arm.

A held program dominates the default when it is faster by more than --slack (2 %), travels less
(held: not at all), and keeps 1/kappa_F at or above --kappa (the plan's threshold). Prints one
Markdown row per file with the default's figures and the best held program's; exits 1 if any
file's default is dominated, 2 if the default itself does not convert.
"""
import argparse
import concurrent.futures
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from speed_check import program_lines  # noqa: E402  (the same reading of a split program)

NUM = r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?"


def seconds(text):
    """'1 h 2 min 3.4 s', '2 min 3.4 s' or '3.4 s' -> seconds."""
    total = 0.0
    for value, unit in re.findall(r"(%s) (h|min|s)\b" % NUM, text):
        total += float(value) * {"h": 3600.0, "min": 60.0, "s": 1.0}[unit]
    return total


def travel(src):
    """Track travel (mm), its reversals, table travel (deg), and the first E1, E2 written."""
    e1, e2 = [], []
    for code in program_lines(src):
        m = re.match(r"^(PTP|LIN|SLIN|CIRC|SPL|SPTP) (.*)$", code)
        if not m:
            continue
        values = dict(re.findall(r"\b(E[12]) (%s)" % NUM, m.group(2)))
        if "E1" in values:
            e1.append(float(values["E1"]))
        if "E2" in values:
            e2.append(float(values["E2"]))
    steps = [b - a for a, b in zip(e1, e1[1:]) if abs(b - a) > 0.05]
    return {
        "track_mm": sum(abs(b - a) for a, b in zip(e1, e1[1:])),
        "reversals": sum(1 for a, b in zip(steps, steps[1:]) if a * b < 0),
        "table_deg": sum(abs(b - a) for a, b in zip(e2, e2[1:])),
        "e1": e1[0] if e1 else None,
        "e2": e2[0] if e2 else None,
    }


def convert(args, cl, options, work, tag):
    out = os.path.join(work, tag)
    os.makedirs(out, exist_ok=True)
    cmd = [args.redpost, "convert", cl, "--cell", args.cell, "-o", out, "--name", "P"] + options
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        lines = [l for l in run.stderr.splitlines() if l.startswith("redpost:")]
        return {"refused": (lines[0] if lines else run.stderr.strip()[-200:])}
    m = re.search(r"^cycle time (.*?) \(cutting", run.stdout, re.M)
    k = re.search(r"^lowest 1/kappa_F of the arm: (%s)" % NUM, run.stdout, re.M)
    if not m or not k:
        return {"refused": "no cycle time or 1/kappa_F in the summary"}
    figures = travel(os.path.join(out, "P.src"))
    figures.update({"cycle_s": seconds(m.group(1)), "kappa": float(k.group(1))})
    return figures


def with_feed(path, feed, work):
    text = open(path, errors="replace").read()
    text = re.sub(r"FEDRAT/MMPM,[ ]*[0-9.]+", "FEDRAT/MMPM,%g" % feed, text)
    text = re.sub(r"FEDRAT/[ ]*[0-9.]+,[ ]*MMPM", "FEDRAT/%g,MMPM" % feed, text)
    text = re.sub(r"^(CYCLE/.*MMPM,)[ ]*[0-9.]+", r"\g<1>%g" % feed, text, flags=re.M)
    out = os.path.join(work, "fed_" + os.path.basename(path))
    with open(out, "w") as f:
        f.write(text)
    return out


def grid(first, small=False):
    """(E1, E2) held values: the track at its first-pose value, +-300 mm and home (500, clamped
    to the Andres cell's range), the table at its first-pose value and every 90 deg from it.
    small: the track at its first-pose value and home, the table at its first-pose value and
    180 deg from it (the suite under the sanitizers)."""
    e1, e2 = first["e1"], first["e2"]
    offsets = (0.0, 500.0 - e1) if small else (0.0, -300.0, 300.0, 500.0 - e1)
    tracks = sorted({round(min(max(e1 + d, -500.0), 3000.0), 3) for d in offsets})
    tables = []
    for k in ((0, 2) if small else range(4)):
        v = e2 + 90.0 * k
        while v > 720.0:
            v -= 360.0
        tables.append(round(v, 3))
    return [(t, w) for t in tracks for w in tables]


def judge(args, spec, work, pool):
    path, _, opts = spec.partition("::")
    options = args.options.split() + (opts.split() if opts else [])
    name = os.path.basename(path)
    cl = with_feed(path, args.feed, work) if args.feed else path
    default = convert(args, cl, options, work, name + "_default")
    if "refused" in default:
        return name, default, None, None, 0
    jobs = {
        pool.submit(convert, args, cl, options + ["--lock", "E1=%g" % t, "--lock", "E2=%g" % w],
                    work, "%s_held_%g_%g" % (name, t, w)): (t, w)
        for t, w in grid(default, args.small_grid)
    }
    held = []
    for job in concurrent.futures.as_completed(jobs):
        r = job.result()
        if "refused" not in r:
            r["at"] = jobs[job]
            held.append(r)
    dominated = [h for h in held
                 if h["cycle_s"] < (1.0 - args.slack) * default["cycle_s"]
                 and (default["track_mm"] > 0.05 or default["table_deg"] > 0.05)
                 and h["kappa"] >= args.kappa]
    usable = [h for h in held if h["kappa"] >= args.kappa]
    best = min(usable or held, key=lambda h: h["cycle_s"]) if held else None
    return name, default, best, dominated, len(held)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--redpost", required=True)
    p.add_argument("--cell", required=True)
    p.add_argument("--feed", type=float, default=0.0)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--slack", type=float, default=0.02)
    p.add_argument("--kappa", type=float, default=0.3)
    p.add_argument("--options", default="", help="words passed to every conversion (a preset)")
    p.add_argument("--small-grid", action="store_true", help="4 held settings instead of 16")
    p.add_argument("files", nargs="+")
    args = p.parse_args()
    feed = "%g mm/min" % args.feed if args.feed else "own feeds"
    print("| file (%s) | default: cycle, track (reversals), table, lowest 1/kappa_F "
          "| held programs that convert | fastest held with 1/kappa_F >= %g | verdict |" % (feed, args.kappa))
    print("|---|---|---|---|---|")
    worst = 0
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for spec in args.files:
            name, d, best, dominated, n = judge(args, spec, work, pool)
            if "refused" in d:
                print("| %s | refused: %s | | | FAIL |" % (name, d["refused"]))
                worst = max(worst, 2)
                continue
            row = "%.1f s, %.0f mm (%d), %.0f deg, %.3f" % (
                d["cycle_s"], d["track_mm"], d["reversals"], d["table_deg"], d["kappa"])
            b = ("E1=%g E2=%g: %.1f s (%+.1f %%), %.3f" % (
                best["at"][0], best["at"][1], best["cycle_s"],
                100.0 * (best["cycle_s"] / d["cycle_s"] - 1.0), best["kappa"]) if best else "none")
            verdict = "not dominated"
            if dominated:
                h = min(dominated, key=lambda h: h["cycle_s"])
                verdict = "DOMINATED by E1=%g E2=%g" % h["at"]
                worst = max(worst, 1)
            print("| %s | %s | %d | %s | %s |" % (name, row, n, b, verdict))
    return worst


if __name__ == "__main__":
    sys.exit(main())
