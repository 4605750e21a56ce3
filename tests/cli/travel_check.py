#!/usr/bin/env python3
"""External axis travel of a written program, from its .src files alone (issue 17).

    travel_check.py PROGRAM.src [--track-per-mm MAX] [--track-net-min MM] [--track-travel-max MM]

Reads every motion's E1 (the track, mm) and E2 (the table, deg) as printed, and the TCP path of
the CP motions (LIN/SLIN/CIRC positions, straight between them). Prints the path length, the
track's travel (sum of |dE1|), its net change, its reversals, the table's travel, and the track
travel per mm of path. Fails when a given bound is broken.
"""
import re
import sys

from speed_check import program_lines  # the same reading of a (split) program

NUM = r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?"


def main(argv):
    args = argv[1:]
    bounds = {}
    for flag in ("--track-per-mm", "--track-net-min", "--track-travel-max"):
        if flag in args:
            k = args.index(flag)
            bounds[flag] = float(args[k + 1])
            del args[k:k + 2]
    src = args[0]
    e1, e2, path = [], [], 0.0
    last_xyz = None
    for code in program_lines(src):
        m = re.match(r"^(PTP|LIN|SLIN|CIRC) (.*)$", code)
        if not m:
            continue
        values = {k: float(v) for k, v in re.findall(r"\b([A-Z]\d?) (%s)" % NUM, m.group(2))}
        if "E1" in values:
            e1.append(values["E1"])
        if "E2" in values:
            e2.append(values["E2"])
        if "X" in values:
            xyz = (values["X"], values["Y"], values["Z"])
            if last_xyz is not None and m.group(1) != "PTP":
                path += sum((a - b) ** 2 for a, b in zip(xyz, last_xyz)) ** 0.5
            last_xyz = xyz
    travel = sum(abs(b - a) for a, b in zip(e1, e1[1:]))
    table = sum(abs(b - a) for a, b in zip(e2, e2[1:]))
    steps = [b - a for a, b in zip(e1, e1[1:]) if abs(b - a) > 0.05]
    reversals = sum(1 for a, b in zip(steps, steps[1:]) if a * b < 0)
    net = abs(e1[-1] - e1[0]) if e1 else 0.0
    per_mm = travel / path if path > 0 else 0.0
    print("travel_check: path %.1f mm, track travel %.1f mm (net %.1f mm, %d reversals), "
          "%.3f mm per mm of path, table travel %.1f deg"
          % (path, travel, net, reversals, per_mm, table))
    failed = False
    if "--track-per-mm" in bounds and per_mm > bounds["--track-per-mm"]:
        print("travel_check: FAIL: track travel %.3f mm per mm, more than %g"
              % (per_mm, bounds["--track-per-mm"]))
        failed = True
    if "--track-net-min" in bounds and net < bounds["--track-net-min"]:
        print("travel_check: FAIL: the track covers %.1f mm, less than %g"
              % (net, bounds["--track-net-min"]))
        failed = True
    if "--track-travel-max" in bounds and travel > bounds["--track-travel-max"]:
        print("travel_check: FAIL: the track travels %.1f mm, more than %g"
              % (travel, bounds["--track-travel-max"]))
        failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
