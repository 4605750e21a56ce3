#!/usr/bin/env python3
"""Writes generated toolpaths for the motion-quality checks of the whole-path plan (issue 30,
item 5): rasters and straight passes on the Andres cell's table, with the spacing, point step,
tool tilt and direction as parameters, so that the plan is judged on paths it was not tuned on.

    make_path_apt.py raster OUT.apt [--width MM] [--spacing MM] [--step MM] [--tilt DEG]
                                    [--angle DEG] [--feed MMPM]
    make_path_apt.py pass OUT.apt [--length MM] [--step MM] [--tilt DEG] [--angle DEG]
                                  [--feed MMPM]

raster: a zigzag over a square of --width around (-100, -450, 60), lines --spacing apart, points
--step apart along them, the tool axis tilting smoothly by up to --tilt over the square (as the
benchmark raster does), the lines turned by --angle about z (0: along x).
pass: one straight line of --length from (-100, -300, 60), --angle from the -y direction (the
track's), the tool tilted by --tilt sideways to the line, constant.
"""
import argparse
import math


def goto(x, y, z, axis):
    return "GOTO/%.4f,%.4f,%.4f,%.7f,%.7f,%.7f\n" % (x, y, z, *axis)


def header(w, name, feed, start, axis):
    """The approach as a CAM system writes it: a rapid to 80 mm above the first point along its
    tool axis, with that axis, then the feed."""
    w(f"PARTNO/{name}\nUNITS/MM\nMULTAX/ON\nCUTTER/10.,5.\nLOADTL/1\nSPINDL/15000,RPM,CLW\n")
    above = [start[i] + 80.0 * axis[i] for i in range(3)]
    w("RAPID\n" + goto(above[0], above[1], above[2], axis))
    w(f"FEDRAT/MMPM,{feed:g}\n")


def raster(a, w):
    half = a.width / 2.0
    lines = int(round(a.width / a.spacing)) + 1
    per_line = int(round(a.width / a.step)) + 1
    c, s = math.cos(math.radians(a.angle)), math.sin(math.radians(a.angle))
    tilt = math.radians(a.tilt)

    def axis_at(u, v):
        # The tilt in the raster's own frame, then turned with it.
        ta = tilt * math.sin(0.5 * math.pi * u / half) / math.sqrt(2.0)
        tb = tilt * math.sin(0.5 * math.pi * v / half) / math.sqrt(2.0)
        lx, ly, lz = math.sin(ta) * math.cos(tb), -math.sin(tb), math.cos(ta) * math.cos(tb)
        return (c * lx - s * ly, s * lx + c * ly, lz)

    header(w, "RASTER", a.feed, (-100.0 - half * c + half * s, -450.0 - half * s - half * c, 60.0),
           axis_at(-half, -half))
    for line in range(lines):
        v = -half + line * a.spacing
        for k in range(per_line):
            u = -half + (k if line % 2 == 0 else per_line - 1 - k) * a.step
            w(goto(-100.0 + c * u - s * v, -450.0 + s * u + c * v, 60.0, axis_at(u, v)))
    w("RAPID\n" + goto(-100.0, -450.0, 140.0, (0.0, 0.0, 1.0)) + "FINI\n")


def straight(a, w):
    ang = math.radians(a.angle)
    d = (math.sin(ang), -math.cos(ang))  # along the line; angle 0: -y
    side = (-d[1], d[0])
    t = math.radians(a.tilt)
    axis = (math.sin(t) * side[0], math.sin(t) * side[1], math.cos(t))
    start = (-100.0, -300.0, 60.0)
    header(w, "PASS", a.feed, start, axis)
    n = int(round(a.length / a.step))
    for k in range(n + 1):
        s = k * a.step
        w(goto(start[0] + s * d[0], start[1] + s * d[1], start[2], axis))
    w("RAPID\n" + goto(start[0] + a.length * d[0], start[1] + a.length * d[1], 140.0, axis))
    w("FINI\n")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("kind", choices=("raster", "pass"))
    p.add_argument("out")
    p.add_argument("--width", type=float, default=200.0)
    p.add_argument("--length", type=float, default=1500.0)
    p.add_argument("--spacing", type=float, default=5.0)
    p.add_argument("--step", type=float, default=0.5)
    p.add_argument("--tilt", type=float, default=20.0)
    p.add_argument("--angle", type=float, default=0.0)
    p.add_argument("--feed", type=float, default=10000.0)
    a = p.parse_args()
    with open(a.out, "w", newline="\n") as f:
        (raster if a.kind == "raster" else straight)(a, f.write)


if __name__ == "__main__":
    main()
