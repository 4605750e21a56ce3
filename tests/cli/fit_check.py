#!/usr/bin/env python3
"""Does a point-reduced program still pass through every CL point? Recomputed from the written
KRL alone (docs/timing.md, "Point reduction"; issue 30).

    fit_check.py REDUCED.src REFERENCE.src [--tol MM] [--ang-tol DEG]
                 [--slack-mm MM] [--slack-deg DEG]

REFERENCE is the same toolpath converted with --fit-tol 0: one CP motion per CL point, so its
printed positions and tool axes are the CL points. REDUCED is the program to check. The path of
REDUCED is interpolated as the controller does: a LIN straight, its orientation turned from one
frame to the next at the same fraction (the quaternion slerp of KUKA's standard orientation
control), a CIRC along the circle through its auxiliary point, the segments of a SPLINE block
as the model of docs/krl-templates.md ("SPL segments") draws them. Every reference point must lie
within --tol (0.01 mm) of that path, in order, and its tool axis (z of the frame) within
--ang-tol (0.1 deg) of the path's tool axis where the path passes it, plus what the printed
decimals of the reference can hide (--slack-mm 0.001, --slack-deg 0.0002; a reference written
with 6 decimals, as tests/bench/motion_rate_table.sh writes it, needs none: the REDUCED
program's own decimals must then stay within the tolerances). PTPs split both programs into stretches that must
match one for one; the reference's first point of a stretch must be a point of the reduced one
(the reduction never drops the point after a PTP, whose position the program does not print),
and the reduced motions before it are not checked. Between the points, every sample of a curve
(a CIRC, an SPL segment) must lie within --tol of the reference's polyline.
Prints the largest deviations and fails above the tolerances.
"""
import math
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from speed_check import aggregate, program_lines, rotation  # noqa: E402

POS_SLACK_MM = 1e-3  # the printed decimals of both programs: where a stretch starts


def quat(r):
    """Unit quaternion (w, x, y, z) of a rotation matrix."""
    t = r[0][0] + r[1][1] + r[2][2]
    if t > 0:
        s = math.sqrt(t + 1.0) * 2
        q = (0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s)
    elif r[0][0] > r[1][1] and r[0][0] > r[2][2]:
        s = math.sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2
        q = ((r[2][1] - r[1][2]) / s, 0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s)
    elif r[1][1] > r[2][2]:
        s = math.sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2
        q = ((r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s)
    else:
        s = math.sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2
        q = ((r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s)
    n = math.sqrt(sum(x * x for x in q))
    return tuple(x / n for x in q)


def slerp(q0, q1, t):
    d = sum(a * b for a, b in zip(q0, q1))
    if d < 0:
        q1, d = tuple(-x for x in q1), -d
    if d > 0.9999995:
        q = tuple(a + t * (b - a) for a, b in zip(q0, q1))
    else:
        th = math.acos(d)
        s0, s1 = math.sin((1 - t) * th) / math.sin(th), math.sin(t * th) / math.sin(th)
        q = tuple(s0 * a + s1 * b for a, b in zip(q0, q1))
    n = math.sqrt(sum(x * x for x in q))
    return tuple(x / n for x in q)


def z_axis(q):
    w, x, y, z = q
    return (2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y))


def angle(u, v):
    c = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    return math.degrees(math.atan2(math.sqrt(sum(x * x for x in c)), sum(a * b for a, b in zip(u, v))))


def pose(values):
    p = (values["X"], values["Y"], values["Z"])
    return p, quat(rotation(values["A"], values["B"], values["C"]))


def circle_points(a, b, c, sagitta_mm=1e-4):
    """Points of the arc from a through b to c (the circle through the three points), close
    enough that the chords between them stay within sagitta_mm of the arc."""
    ab = [b[i] - a[i] for i in range(3)]
    ac = [c[i] - a[i] for i in range(3)]
    def cross(u, v):
        return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    nrm = cross(ab, ac)
    n2 = sum(x * x for x in nrm)
    if n2 < 1e-12:
        return [a, c]
    t1, t2 = cross(nrm, ab), cross(ac, nrm)
    centre = [a[i] + (sum(x * x for x in ac) * t1[i] + sum(x * x for x in ab) * t2[i]) / (2 * n2)
              for i in range(3)]
    r = math.dist(a, centre)
    u = [(a[i] - centre[i]) / r for i in range(3)]
    nn = [x / math.sqrt(n2) for x in nrm]
    v = cross(nn, u)
    d = [c[i] - centre[i] for i in range(3)]
    sweep = math.atan2(sum(d[i] * v[i] for i in range(3)), sum(d[i] * u[i] for i in range(3)))
    sweep = sweep if sweep > 0 else sweep + 2 * math.pi
    n = max(16, min(100000, math.ceil(sweep / (2 * math.acos(max(-1.0, 1 - sagitta_mm / r))))))
    return [tuple(centre[i] + r * (math.cos(sweep * k / n) * u[i] + math.sin(sweep * k / n) * v[i])
                  for i in range(3)) for k in range(n + 1)]


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v] if n > 0 else [0.0, 0.0, 0.0]


def bessel(a, b, c):
    """Unit tangent at b of the parabola through a, b, c with chord-length parameters."""
    l1, l2 = math.dist(a, b), math.dist(b, c)
    if l1 == 0 or l2 == 0:
        return [0.0, 0.0, 0.0]
    return unit([(l2 / (l1 + l2)) * (b[i] - a[i]) / l1 + (l1 / (l1 + l2)) * (c[i] - b[i]) / l2
                 for i in range(3)])


def spline_samples(start, block, step_mm=0.05):
    """The path of a SPLINE block's segments [(keyword, pose)] from `start` (a pose), as the
    model of docs/krl-templates.md ("SPL segments") draws it: an SLIN straight; an SPL a cubic
    Hermite curve whose tangent at a point inside the block is the SLIN's next to it (an SLIN
    dominates), else Bessel's through the point's neighbours, and at the block's ends its own
    chord. The orientation turned over each segment as on a LIN. Returns the samples after
    `start` and the indices of those that are curve points between two written points."""
    pts = [start] + [p for _, p in block]
    kinds = [k for k, _ in block]
    n = len(block)

    def tangent(j):  # at pts[j], j = 1 .. n - 1 (inside the block)
        before, after = kinds[j - 1], kinds[j]
        if before == "SLIN" and after == "SLIN":
            return None  # a corner inside the block (the controller stops there)
        if before == "SLIN":
            return unit([pts[j][0][i] - pts[j - 1][0][i] for i in range(3)])
        if after == "SLIN":
            return unit([pts[j + 1][0][i] - pts[j][0][i] for i in range(3)])
        return bessel(pts[j - 1][0], pts[j][0], pts[j + 1][0])

    out, curve = [], []
    for k in range(1, n + 1):
        p0, p1 = pts[k - 1], pts[k]
        chord = [p1[0][i] - p0[0][i] for i in range(3)]
        length = math.sqrt(sum(x * x for x in chord))
        if kinds[k - 1] != "SPL" or length == 0:
            out.append(p1)
            continue
        t0 = tangent(k - 1) if k - 1 >= 1 else None
        t1 = tangent(k) if k <= n - 1 else None
        m0 = chord if t0 is None else [length * x for x in t0]
        m1 = chord if t1 is None else [length * x for x in t1]
        steps = max(8, min(20000, math.ceil(length / step_mm)))
        for s_ in range(1, steps + 1):
            u = s_ / steps
            h00, h10 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u
            h01, h11 = -2 * u**3 + 3 * u**2, u**3 - u**2
            p = tuple(h00 * p0[0][i] + h10 * m0[i] + h01 * p1[0][i] + h11 * m1[i]
                      for i in range(3))
            if s_ < steps:
                curve.append(len(out))
            out.append((p, slerp(p0[1], p1[1], u)) if s_ < steps else p1)
    return out, curve


def stretches(src, curves=None):
    """The program's CP motions, split at every PTP: a list of stretches, each a list of
    (position, quaternion) samples of the path, a CIRC and an SPL segment as many samples.
    With `curves` (a list), the samples that lie between written points on a curve, per
    stretch, as lists of indices."""
    out, cur, cur_curve = [], [], []
    block = None  # the SPLINE block being read: [(keyword, pose)]

    def close_block():
        nonlocal block
        if block and cur:
            samples, curve = spline_samples(cur[-1], block)
            cur_curve.extend(len(cur) + i for i in curve)
            cur.extend(samples)
        elif block:
            cur.extend(p for _, p in block)
        block = None

    def close_stretch():
        nonlocal cur, cur_curve
        close_block()
        if cur:
            out.append(cur)
            if curves is not None:
                curves.append(cur_curve)
        cur, cur_curve = [], []

    for line in program_lines(src):
        code = line.split(";")[0].strip()
        if re.match(r"^(PTP|SPTP)\b", code):
            close_stretch()
            continue
        if re.match(r"^SPLINE\b", code):
            close_block()
            block = []
            continue
        if re.match(r"^ENDSPLINE\b", code):
            close_block()
            continue
        m = re.match(r"^(SLIN|SPL)\s*\{E6POS:(.*?)\}", code)
        if m and block is not None:
            block.append((m.group(1), pose(aggregate(m.group(2)))))
            continue
        m = re.match(r"^(LIN|SLIN)\s*\{E6POS:(.*?)\}", code)
        if m:
            cur.append(pose(aggregate(m.group(2))))
            continue
        # The auxiliary point as redpost writes it ({X, Y, Z}: the controller takes its position
        # only) or as a full E6POS.
        m = re.match(r"^(CIRC|SCIRC)\s*\{(?:E6POS:|POS:)?(.*?)\}\s*,\s*\{E6POS:(.*?)\}", code)
        if m and cur:
            a = aggregate(m.group(2))
            aux_p, end = (a["X"], a["Y"], a["Z"]), pose(aggregate(m.group(3)))
            start = cur[-1]
            pts = circle_points(start[0], aux_p, end[0])
            for k, p in enumerate(pts[1:], 1):
                if k < len(pts) - 1:
                    cur_curve.append(len(cur))
                cur.append((p, slerp(start[1], end[1], k / (len(pts) - 1))))
    close_stretch()
    return out


def nearest(a, b, p):
    d = [b[i] - a[i] for i in range(3)]
    l2 = sum(x * x for x in d)
    t = 0.0 if l2 == 0 else max(0.0, min(1.0, sum((p[i] - a[i]) * d[i] for i in range(3)) / l2))
    return t, math.dist(p, [a[i] + t * d[i] for i in range(3)])


def main(argv):
    args = argv[1:]
    tol, ang_tol = 0.01, 0.1
    if "--tol" in args:
        k = args.index("--tol"); tol = float(args[k + 1]); del args[k:k + 2]
    if "--ang-tol" in args:
        k = args.index("--ang-tol"); ang_tol = float(args[k + 1]); del args[k:k + 2]
    slack_mm, slack_deg = 1e-3, 2e-4
    if "--slack-mm" in args:
        k = args.index("--slack-mm"); slack_mm = float(args[k + 1]); del args[k:k + 2]
    if "--slack-deg" in args:
        k = args.index("--slack-deg"); slack_deg = float(args[k + 1]); del args[k:k + 2]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    curves = []
    reduced, reference = stretches(args[0], curves), stretches(args[1])
    if len(reduced) != len(reference):
        print(f"fit_check: {len(reduced)} stretches between PTPs, the reference has "
              f"{len(reference)}")
        return 1
    worst_d, worst_a, worst_c, points, failures = 0.0, 0.0, 0.0, 0, 0
    for g, (path, ref) in enumerate(zip(reduced, reference)):
        # The reduced stretch may begin with steps along the line from the PTP's end (which the
        # program does not print) to the reference's first point.
        start = next((k for k, s in enumerate(path) if math.dist(s[0], ref[0][0]) <= POS_SLACK_MM),
                     None)
        if start is None:
            print(f"fit_check: stretch {g + 1}: the reference's first point {ref[0][0]} is not "
                  f"on the reduced path")
            return 1
        path = path[start:]
        j = 0
        for p, q in ref:
            points += 1
            found = None
            for k in range(j, len(path) - 1):
                t, d = nearest(path[k][0], path[k + 1][0], p)
                if d <= tol + slack_mm:
                    found = (k, t, d)
                    break
            if found is None:
                d = math.dist(path[-1][0], p) if j == len(path) - 1 else float("inf")
                if d <= tol + slack_mm:
                    found = (len(path) - 1, 0.0, d)
            if found is None:
                failures += 1
                if failures <= 10:
                    print(f"fit_check: stretch {g + 1}: the point {p} is not within {tol} mm of "
                          f"the path after its motion {j + 1}")
                continue
            k, t, d = found
            j = k
            q_path = path[k][1] if k == len(path) - 1 else slerp(path[k][1], path[k + 1][1], t)
            a = angle(z_axis(q_path), z_axis(q))
            worst_d, worst_a = max(worst_d, d), max(worst_a, a)
            if a > ang_tol + slack_deg:
                failures += 1
                if failures <= 10:
                    print(f"fit_check: stretch {g + 1}: at {p} the tool axis is {a:.4f} deg from "
                          f"the reference's (at most {ang_tol})")
        # Between the points too: every sample of a curve (a CIRC, an SPL segment) within the
        # tolerance of the reference's polyline, searched forward along it.
        r = 0
        for i in curves[g]:
            if i < start:
                continue
            p = path[i - start][0]
            found = None
            for k in range(r, min(len(ref) - 1, r + 5000)):
                _, d = nearest(ref[k][0], ref[k + 1][0], p)
                if d <= tol + slack_mm:
                    found = (k, d)
                    break
            if found is None:
                failures += 1
                if failures <= 10:
                    print(f"fit_check: stretch {g + 1}: the curve's point {p} is not within "
                          f"{tol} mm of the CL polyline")
                continue
            r = found[0]
            worst_c = max(worst_c, found[1])
    motions = sum(len(s) for s in reduced)
    print(f"fit_check: {points} reference points, {sum(len(s) for s in reference)} reference "
          f"samples, {motions} path samples; largest deviation {worst_d:.4f} mm and "
          f"{worst_a:.4f} deg of the tool axis; {failures} outside the tolerance; curves within "
          f"{worst_c:.4f} mm of the CL polyline")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
