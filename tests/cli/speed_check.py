#!/usr/bin/env python3
"""Axis speeds of a written program at the $VEL.CP in force, recomputed from the program's own
files and the cell's limits only (docs/timing.md, issue 17). Used by tests/cli/test_speeds.sh.

    speed_check.py PROGRAM.src JOINTS.csv CELL.xml [--feed MM_PER_MIN] [--limit FRACTION]
                   [--max-time-ratio R] [--ipo-cycle MS] [--max-cycle-ratio R]

For every CP motion (LIN, SLIN, CIRC) after the first motion: the TCP path from the printed
positions (a CIRC's arc through its auxiliary point), the time the controller needs at least at
the $VEL.CP in force (and at $VEL.ORI1 for the turn, 200 deg/s unless the program sets it), and
each axis's change from the joints log, whose rows are matched to the motions by the printed
axis values (a split program's parts each start with a PTP to where the last part ended, which
has no row). Prints the highest fraction of a velocity limit and fails above --limit (1.0).

With --feed: the cutting motions are those written at that feed or below it (the rapid speed
is excluded); prints how much longer than at the feed they take at the written $VEL.CP, and
the same with the motions written at the motion rate counted at the feed (a $VEL.CP at which the
motion lasts one interpolation cycle, up to the printed decimals: the clock's limit, not an
axis's), and fails above --max-time-ratio on the latter (issue 17: 1.10 at a production feed,
the axes' share).

The controller's clock (issue 30, docs/timing.md "The interpolation cycle"): counts the CP
motions that last less than one interpolation cycle (--ipo-cycle, 12 ms) at their $VEL.CP, and
with --feed the cutting time when each motion takes at least one cycle; fails above
--max-cycle-ratio when given.
"""
import math
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

NUM = r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?"


def cell_limits(path):
    """Axis name -> velocity limit in controller units per second (deg/s, mm/s)."""
    limits = {}
    for joint in ET.parse(path).getroot().iter("joint"):
        axis, speed = joint.find("axis"), joint.find("speed")
        if axis is None or speed is None or axis.get("name", "none") == "none":
            continue
        text = speed.get("velocity").strip()
        m = re.match(r"^(%s)\s*(\S*)$" % NUM, text)
        value, unit = float(m.group(1)), m.group(2)
        factor = {"": 1.0, "deg/s": 1.0, "mm/s": 1.0, "rad/s": 180.0 / math.pi,
                  "m/s": 1000.0}[unit]
        limits[axis.get("name")] = value * factor
    return limits


def aggregate(text):
    return {k: float(v) for k, v in re.findall(r"\b([A-Z]\d?) (%s)" % NUM, text)}


def program_lines(src):
    """The main program's lines, with every call of a part replaced by the part's lines."""
    folder = Path(src).parent
    out = []
    for line in Path(src).read_text().splitlines():
        code = line.strip()
        m = re.match(r"^(\w+)\( \)$", code)
        part = folder / (m.group(1) + ".src") if m else None
        if part is not None and part.exists() and part.resolve() != Path(src).resolve():
            out.extend(program_lines(part))
        else:
            out.append(code)
    return out


def rotation(a, b, c):
    a, b, c = (math.radians(x) for x in (a, b, c))
    ca, sa, cb, sb, cc, sc = math.cos(a), math.sin(a), math.cos(b), math.sin(b), math.cos(c), math.sin(c)
    return [[ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
            [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
            [-sb, cb * sc, cb * cc]]


def angle_between(r0, r1):
    trace = sum(r0[k][i] * r1[k][i] for i in range(3) for k in range(3))
    return math.acos(max(-1.0, min(1.0, 0.5 * (trace - 1.0))))


def arc_length(a, b, c):
    """Length of the arc from a through b to c (the circle through the three points)."""
    ab = [b[i] - a[i] for i in range(3)]
    ac = [c[i] - a[i] for i in range(3)]
    n = [ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]]
    n2 = sum(x * x for x in n)
    if n2 < 1e-12:
        return math.dist(a, c)
    def cross(u, v):
        return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    t1 = cross(n, ab)
    t2 = cross(ac, n)
    centre = [a[i] + (sum(x * x for x in ac) * t1[i] + sum(x * x for x in ab) * t2[i]) / (2 * n2)
              for i in range(3)]
    r = math.dist(a, centre)
    def ang(p):
        u = [(a[i] - centre[i]) / r for i in range(3)]
        nn = [x / math.sqrt(n2) for x in n]
        v = cross(nn, u)
        d = [p[i] - centre[i] for i in range(3)]
        phi = math.atan2(sum(d[i] * v[i] for i in range(3)), sum(d[i] * u[i] for i in range(3)))
        return phi if phi > 0 else phi + 2 * math.pi
    return r * ang(c)


def main(argv):
    args = argv[1:]
    feed, limit, max_ratio = None, 1.0, None
    cycle, max_cycle_ratio = 0.012, None
    if "--ipo-cycle" in args:
        k = args.index("--ipo-cycle")
        cycle = float(args[k + 1]) / 1000.0
        del args[k:k + 2]
    if "--max-cycle-ratio" in args:
        k = args.index("--max-cycle-ratio")
        max_cycle_ratio = float(args[k + 1])
        del args[k:k + 2]
    if "--max-time-ratio" in args:
        k = args.index("--max-time-ratio")
        max_ratio = float(args[k + 1])
        del args[k:k + 2]
    if "--feed" in args:
        k = args.index("--feed")
        feed = float(args[k + 1])
        del args[k:k + 2]
    if "--limit" in args:
        k = args.index("--limit")
        limit = float(args[k + 1])
        del args[k:k + 2]
    src, csv, cell = args
    limits = cell_limits(cell)
    rows = [line.split(",") for line in Path(csv).read_text().splitlines()]
    header, rows = rows[0], [[float(v) for v in r] for r in rows[1:]]
    col = {h: i for i, h in enumerate(header)}
    axes = [a for a in header if re.match(r"^[AE]\d$", a)]

    vel = None
    ori = 200.0
    motions = []  # (kind, values, aux, vel, ori)
    block = nblocks = 0  # the SPLINE block a motion is in (0: none), for "joined" below
    blocks = []
    for code in program_lines(src):
        if re.match(r"^SPLINE\b", code):
            nblocks += 1
            block = nblocks
            continue
        if re.match(r"^ENDSPLINE\b", code):
            block = 0
            continue
        m = re.match(r"^\$VEL\.CP = (%s)$" % NUM, code)
        if m:
            vel = float(m.group(1)) * 1000.0  # mm/s
            continue
        m = re.match(r"^\$VEL\.ORI1 = (%s)$" % NUM, code)
        if m:
            ori = float(m.group(1))
            continue
        m = re.match(r"^(PTP|LIN|SLIN|SPL|CIRC) (.*)$", code)
        if not m:
            continue
        kind, rest = m.group(1), m.group(2)
        aux = None
        if kind == "CIRC":
            am = re.match(r"^\{X (%s), Y (%s), Z (%s)\}, (.*)$" % (NUM, NUM, NUM), rest)
            aux = [float(am.group(i)) for i in (1, 2, 3)]
            rest = am.group(4)
        # A spline segment's own speed (SLIN/SPL ... WITH $VEL.CP = v), for it alone.
        wm = re.search(r"\bWITH\b.*\$VEL\.CP = (%s)" % NUM, rest)
        motions.append((kind, aggregate(rest), aux,
                        float(wm.group(1)) * 1000.0 if wm else vel, ori))
        blocks.append(block)

    # Match the motions to the log's rows by their printed axes.
    matched = []
    r = 0
    matched_blocks = []
    for i, (kind, values, aux, v, o) in enumerate(motions):
        if r < len(rows):
            ok = all(abs(rows[r][col[a]] - values[a]) < 2e-3 for a in values if a in col)
            if ok:
                matched.append((kind, values, aux, v, o, rows[r]))
                matched_blocks.append(blocks[i])
                r += 1
                continue
        if kind == "PTP" and matched:
            continue  # a part's first PTP to where the last part ended
        print("speed_check: motion %d (%s) matches no row of the joints log (row %d)"
              % (len(matched) + 1, kind, r + 1))
        return 1
    if r != len(rows):
        print("speed_check: %d rows of the joints log left over" % (len(rows) - r))
        return 1

    worst, worst_at = 0.0, None
    cut_written = cut_feed = cut_clocked = cut_axes = 0.0
    cp_count = short = unmeasured = at_rate = 0
    def joined(k):
        """Motion k joins motion k - 1 smoothly: one SPLINE block, one of them an SPL (one path
        the controller plans whole: docs/timing.md, "SPLINE blocks")."""
        return 0 < k < len(matched) and matched_blocks[k] > 0 and \
            matched_blocks[k] == matched_blocks[k - 1] and "SPL" in (matched[k][0], matched[k - 1][0])

    for k in range(1, len(matched)):
        kind, values, aux, v, o, row = matched[k]
        pk, pvalues, _, _, _, prow = matched[k - 1]
        if kind == "PTP":
            continue
        if pk == "PTP" and "X" not in pvalues:
            # The position after a PTP: the log does not print it; take the LIN's own length
            # from the joints only through the time at the orientation/axis rates below.
            pass
        if "X" not in values or "X" not in pvalues:
            unmeasured += 1
            continue  # a CP motion after a PTP to axes: no printed start position
        p0 = [pvalues["X"], pvalues["Y"], pvalues["Z"]]
        p1 = [values["X"], values["Y"], values["Z"]]
        length = arc_length(p0, aux, p1) if aux else math.dist(p0, p1)
        turn = math.degrees(angle_between(rotation(pvalues["A"], pvalues["B"], pvalues["C"]),
                                          rotation(values["A"], values["B"], values["C"])))
        time = max(length / v, turn / o)
        cp_count += 1
        if 0.0 < time < cycle * (1.0 - 1e-4) and not (joined(k) or joined(k + 1)):
            short += 1  # as docs/timing.md counts them
        if feed is not None and v <= feed / 60.0 * (1.0 + 1e-5):
            cut_written += length / v
            cut_feed += length / (feed / 60.0)
            floor = 0.0 if joined(k) or joined(k + 1) else cycle
            cut_clocked += max(length / v, floor) if time > 0.0 else 0.0
            # Written at the motion rate: slower than the feed, and one cycle long (the session
            # takes the length short by the rounding of both ends, up to 5 % on 0.05 mm).
            rate = v < feed / 60.0 * (1.0 - 1e-6) and \
                cycle * (1.0 - 1e-4) <= length / v <= cycle * 1.05
            at_rate += 1 if rate else 0
            cut_axes += length / (feed / 60.0) if rate else length / v
        if time <= 0.0:
            continue
        for a in axes:
            if a not in limits:
                continue
            speed = abs(row[col[a]] - prow[col[a]]) / time
            f = speed / limits[a]
            if f > worst:
                worst, worst_at = f, (a, int(row[col["cl_line"]]), int(row[col["pose"]]))
    print("speed_check: %d CP motions, highest axis speed %.4f of its limit%s"
          % (cp_count, worst,
             " (%s, CL line %d, pose %d)" % worst_at if worst_at else ""))
    print("speed_check: %d of %d CP motions last less than one %g ms interpolation cycle at "
          "their $VEL.CP (%d not measured)" % (short, cp_count, cycle * 1000.0, unmeasured))
    if feed is not None and cut_feed > 0.0:
        print("speed_check: cutting at the written $VEL.CP takes %.4f x the time at %g mm/min"
              % (cut_written / cut_feed, feed))
        print("speed_check: with one motion per %g ms cycle at most, %.4f x"
              % (cycle * 1000.0, cut_clocked / cut_feed))
        print("speed_check: with the %d motion(s) written at the motion rate at the feed, %.4f x"
              % (at_rate, cut_axes / cut_feed))
    if worst > limit:
        print("speed_check: FAIL: an axis passes %.2f of its velocity limit" % limit)
        return 1
    if max_cycle_ratio is not None and cut_feed > 0.0 and cut_clocked / cut_feed > max_cycle_ratio:
        print("speed_check: FAIL: at one motion per cycle, cutting takes more than %.2f x the "
              "time at the feed" % max_cycle_ratio)
        return 1
    if max_ratio is not None and cut_feed > 0.0 and cut_axes / cut_feed > max_ratio:
        print("speed_check: FAIL: cutting takes more than %.2f x the time at the feed (the "
              "motions written at the motion rate counted at the feed)" % max_ratio)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
