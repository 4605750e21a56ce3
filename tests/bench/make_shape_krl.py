#!/usr/bin/env python3
"""Writes a KRL program of N LIN motions in one of the shapes that once made `redpost diff` and
`redpost check` slow (issue 48), or a plain raster of the same size to compare with.

    make_shape_krl.py SHAPE N OUT [--jitter MM] [--seed S] [--part MOTIONS]

SHAPE:
  raster     400 mm lines 2 mm apart, 0.5 mm between points (the reference)
  point      every motion to one point (a dwell loop, a probing routine, a broken export)
  backforth  a 100 mm segment traversed back and forth, 0.5 mm between points
  line       every motion on one straight line, back and forth over 400 mm in steps that do
             not repeat (0.5 mm plus a small drift), so no two points coincide
  finish     a finishing raster: 100 mm lines 0.05 mm apart, 1 mm between points (many passes
             in each cell of the path grid, none a duplicate)
--jitter MM moves every point by a seeded random amount up to MM in each coordinate (a second
program that differs a little from the first).

The program is one module OUT (a .src) with a PTP to start and its motions as E6POS LINs, as
redpost's krc4_lin templates write them, with a `; CL line` comment every motion (for the CL-line
alignment) unless --no-cl-lines. With --part MOTIONS, OUT is a folder: SHAPE.src calls
SHAPE_P001.src, SHAPE_P002.src, ... of at most MOTIONS motions each, as redpost splits a
program.
"""
import os
import argparse
import random


def zigzag(n, length, step, spacing, lines, x0, y0):
    """A raster of lines `length` long along x, points `step` apart, `spacing` apart in y, the
    direction turning at each line, back to the first after `lines` lines."""
    per_line = int(round(length / step)) + 1
    for k in range(n):
        line, j = divmod(k, per_line)
        x = j * step if line % 2 == 0 else length - j * step
        yield (x0 + x, y0 + spacing * (line % lines), 60.0)


def points(shape, n):
    if shape == "raster":
        yield from zigzag(n, 400.0, 0.5, 2.0, 100, -300.0, -500.0)
    elif shape == "point":
        for _ in range(n):
            yield (-100.0, -450.0, 60.0)
    elif shape == "backforth":
        for k in range(n):
            j = k % 400
            x = j * 0.5 if j < 200 else (400 - j) * 0.5
            yield (-150.0 + x, -450.0, 60.0)
    elif shape == "line":
        x, step = 0.0, 0.5
        for k in range(n):
            yield (-300.0 + x, -450.0, 60.0)
            x += step + 1e-6 * k
            if x > 400.0 or x < 0.0:
                step = -step
                x += 2.0 * step
    elif shape == "finish":
        yield from zigzag(n, 100.0, 1.0, 0.05, 4000, -150.0, -500.0)
    else:
        raise SystemExit("unknown shape " + shape)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("shape")
    p.add_argument("n", type=int)
    p.add_argument("out")
    p.add_argument("--jitter", type=float, default=0.0)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--no-cl-lines", action="store_true")
    p.add_argument("--part", type=int, default=0)
    a = p.parse_args()
    rng = random.Random(a.seed)
    name = "SHAPE"
    lines = []
    for k, (x, y, z) in enumerate(points(a.shape, a.n)):
        if a.jitter > 0.0:
            x += rng.uniform(-a.jitter, a.jitter)
            y += rng.uniform(-a.jitter, a.jitter)
            z += rng.uniform(-a.jitter, a.jitter)
        text = "" if a.no_cl_lines else "; CL line %d\n" % (k + 10)
        lines.append(text + "LIN {E6POS: X %.4f, Y %.4f, Z %.4f, A 0.0000, B 0.0000, C 180.0000, "
                     "S 2, T 35, E1 0.0000, E2 0.0000} C_DIS\n" % (x, y, z))
    head = ("$VEL.CP = 0.200000\n$APO.CDIS = 0.500\nBAS (#VEL_PTP,20)\n"
            "PTP {E6AXIS: A1 0.0, A2 -90.0, A3 90.0, A4 0.0, A5 45.0, A6 0.0, E1 0.0, E2 0.0}\n")
    if a.part <= 0:
        with open(a.out, "w") as f:
            f.write("DEF %s( )\n" % name + head + "".join(lines) + "END\n")
        return
    os.makedirs(a.out, exist_ok=True)
    parts = [lines[i:i + a.part] for i in range(0, len(lines), a.part)]
    with open(os.path.join(a.out, name + ".src"), "w") as f:
        f.write("DEF %s( )\n" % name + head)
        for i in range(len(parts)):
            f.write("%s_P%03d( )\n" % (name, i + 1))
        f.write("END\n")
    for i, part in enumerate(parts):
        with open(os.path.join(a.out, "%s_P%03d.src" % (name, i + 1)), "w") as f:
            f.write("DEF %s_P%03d( )\n" % (name, i + 1) + "".join(part) + "END\n")

if __name__ == "__main__":
    main()
