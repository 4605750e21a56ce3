#!/usr/bin/env python3
"""The least time the controller's path limits allow for a toolpath, with arms that never limit
it (docs/timing.md, "What is left of 1.10x"; issue 30). Read from a written program alone.

    time_floor.py PROGRAM.src --feed MM_PER_MIN [--acc MM_S2] [--ori DEG_S] [--cdis MM]
                  [--model-log CONVERT_OUTPUT]

PROGRAM is the toolpath, every feed set to --feed, converted with --fit-tol 0 and --krl
krc4_circ for a cell without axis speeds (no $VEL.CP lowered for an axis): one CP motion per CL
point and a CIRC for each CL arc, so its positions are the CL path, its feed moves are written
at the feed and its rapids above it. A PTP's position is known where it prints X, Y, Z (a set
whose rapid statement is a Cartesian PTP); a CP motion after a PTP that does not is left out,
its time at the feed and its floor alike. The cutting motions are the CP motions written at
--feed or below. Along the CP path, the TCP's speed is bounded by:

- the feed on a cutting motion, the written $VEL.CP on any other;
- the tool axis's swivel at $VEL.ORI1 (--ori, 200 deg/s): a motion that tilts the tool by d deg
  over L mm runs at most at L * ori / d;
- on a CIRC of radius r, the normal acceleration v^2 / r at most $ACC.CP (--acc, 2000 mm/s^2);
- at a point where the path turns by phi, the widest arc the blend can take: tangent to both
  motions c from the point, c the blending distance (half the shorter motion, at most --cdis
  where the turn is over 30 deg, the most a SPLINE knot turns), of radius c / tan(phi / 2); so
  at most v^2 = acc * c / tan(phi / 2), 0 at a reversal. A curve with less curvature cannot
  join the two motions within c of the point. A PTP, a WAIT, a HALT and an unblended motion are
  stops;
- the acceleration $ACC.CP between those (the classic forward and backward passes).

No axis limit, no interpolation cycle, no look-ahead: any program within the CL tolerance with
these controller settings needs at least this time (up to how the blend is modelled). Prints
the cutting time at the feeds, the floor, and their ratio. With --model-log, what a conversion
of the same toolpath printed (with any set, preset, reduction and cell; its line "cycle time
... (cutting ..., +P % on the CL feeds' T)"): fails if its CL feeds' time T is not the one
counted here (other motions), or if its cutting time over T is below the floor's ratio by more
than the 0.005 of rounding, which no timing of an arm can be.
"""
import math
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "cli"))
from fit_check import circle_points, unit  # noqa: E402
from speed_check import NUM, aggregate, program_lines, rotation  # noqa: E402

MOTION = re.compile(r"^(LIN|CIRC|PTP)\s*(\{[^}]*\})(?:\s*,\s*(\{[^}]*\}))?(.*)$")
SMOOTH_TURN_RAD = math.radians(30.0)


class Segment:
    def __init__(self, points, speed_cap, cutting):
        self.length = sum(math.dist(points[k], points[k + 1]) for k in range(len(points) - 1))
        self.entry_dir = unit([points[1][i] - points[0][i] for i in range(3)])
        self.exit_dir = unit([points[-1][i] - points[-2][i] for i in range(3)])
        self.cap = speed_cap
        self.cutting = cutting


def tool_axis(values):
    r = rotation(values["A"], values["B"], values["C"])
    return [r[0][2], r[1][2], r[2][2]]


def profile_time(length, u, w, cap, acc):
    """Time over `length` from speed u to w, at most `cap`, accelerating at `acc`."""
    peak = min(cap, math.sqrt(max(0.0, (2 * acc * length + u * u + w * w) / 2)))
    ramps = (2 * peak * peak - u * u - w * w) / (2 * acc)
    return (peak - u) / acc + (peak - w) / acc + max(0.0, length - ramps) / peak


def stretches(lines, feed_mm_s, acc, ori_rad_s):
    """Lists of Segments between stops. The program is krc4_circ's (LIN, CIRC, PTP): a spline
    block's segments are refused rather than read as stops."""
    out, current, pose, vel = [], [], None, None
    def stop():
        nonlocal current
        if current:
            out.append(current)
        current = []
    for code in lines:
        code = code.split(";", 1)[0].strip()
        m = re.match(r"^\$VEL\.CP\s*=\s*(%s)" % NUM, code)
        if m:
            vel = float(m.group(1)) * 1000.0
            continue
        if re.match(r"^(SPLINE|SLIN|SPL|SCIRC)\b", code):
            sys.exit("time_floor: a SPLINE block; convert the reference with --krl krc4_circ")
        if re.match(r"^(WAIT|HALT|END\b)", code):
            stop()
            continue
        m = MOTION.match(code)
        if not m:
            continue
        kind, first, second, rest = m.groups()
        if kind == "PTP":
            stop()
            known = aggregate(first)
            pose = known if all(k in known for k in "XYZABC") else None
            continue
        end = aggregate(second if kind == "CIRC" else first)
        speed = vel
        if pose is None or speed is None:
            pose = end
            continue
        a = (pose["X"], pose["Y"], pose["Z"])
        b = (end["X"], end["Y"], end["Z"])
        if kind == "CIRC":
            aux = aggregate(first)
            points = circle_points(a, (aux["X"], aux["Y"], aux["Z"]), b)
        else:
            points = [a, b]
        cutting = speed <= feed_mm_s + 1e-3  # the printed decimals of $VEL.CP
        cap = feed_mm_s if cutting else speed
        if math.dist(a, b) > 0 or len(points) > 2:
            seg = Segment(points, cap, cutting)
            swivel = math.acos(max(-1.0, min(1.0, sum(
                p * q for p, q in zip(tool_axis(pose), tool_axis(end))))))
            if swivel > 1e-9:
                seg.cap = min(seg.cap, seg.length * ori_rad_s / swivel)
            if kind == "CIRC" and len(points) > 2:
                chord = math.dist(points[0], points[1])
                turn = 2 * math.asin(min(1.0, math.dist(
                    unit([points[1][i] - points[0][i] for i in range(3)]),
                    unit([points[2][i] - points[1][i] for i in range(3)])) / 2))
                if turn > 0:
                    seg.cap = min(seg.cap, math.sqrt(acc * chord / turn))
            current.append(seg)
        if re.search(r"\bC_(DIS|VEL|ORI)\b", rest) is None:
            stop()
        pose = end
    stop()
    return out


def junction_cap(prev, nxt, acc, cdis):
    cos_turn = sum(p * q for p, q in zip(prev.exit_dir, nxt.entry_dir))
    turn = math.acos(max(-1.0, min(1.0, cos_turn)))
    if turn < 1e-9:
        return math.inf
    c = 0.5 * min(prev.length, nxt.length)
    if turn > SMOOTH_TURN_RAD:
        c = min(c, cdis)
    if c <= 0 or turn >= math.pi - 1e-9:
        return 0.0
    return math.sqrt(acc * c / math.tan(turn / 2))


def floor_time(segments, acc, cdis):
    """The floor of one stretch's cutting time."""
    n = len(segments)
    v = [0.0] * (n + 1)  # speed at the junctions; 0 at both ends
    for k in range(1, n):
        v[k] = min(segments[k - 1].cap, segments[k].cap,
                   junction_cap(segments[k - 1], segments[k], acc, cdis))
    for k in range(1, n + 1):  # forward: what acceleration from the last stop allows
        v[k] = min(v[k], math.sqrt(v[k - 1] ** 2 + 2 * acc * segments[k - 1].length))
    for k in range(n - 1, -1, -1):  # backward: what the next stop allows
        v[k] = min(v[k], math.sqrt(v[k + 1] ** 2 + 2 * acc * segments[k].length))
    return sum(profile_time(s.length, v[k], v[k + 1], s.cap, acc)
               for k, s in enumerate(segments) if s.cutting)


def main(argv):
    args = argv[1:]
    def option(name, default):
        if name in args:
            i = args.index(name)
            value = float(args[i + 1])
            del args[i:i + 2]
            return value
        return default
    feed = option("--feed", None)
    acc = option("--acc", 2000.0)
    ori = math.radians(option("--ori", 200.0))
    cdis = option("--cdis", None)
    model_log = None
    if "--model-log" in args:
        i = args.index("--model-log")
        model_log = args[i + 1]
        del args[i:i + 2]
    if feed is None or len(args) != 1:
        sys.exit(__doc__)
    lines = program_lines(args[0])
    if cdis is None:
        m = next((re.match(r"^\$APO\.CDIS\s*=\s*(%s)" % NUM, s) for s in lines
                  if s.startswith("$APO.CDIS")), None)
        cdis = float(m.group(1)) if m else 0.0
    feed_mm_s = feed / 60.0
    at_feed = floor = 0.0
    for stretch in stretches(lines, feed_mm_s, acc, ori):
        floor += floor_time(stretch, acc, cdis)
        at_feed += sum(s.length / feed_mm_s for s in stretch if s.cutting)
    ratio = floor / at_feed if at_feed else 0.0
    print(f"cutting at the feeds {at_feed:.2f} s, floor {floor:.2f} s ({ratio:.3f}x)")
    if model_log is not None:
        m = re.search(r"\(cutting [^,]*, ([-+][0-9.]+) % on the CL feeds' (?:(\d+) min )?([0-9.]+) s\)",
                      Path(model_log).read_text())
        if not m:
            print(f"time_floor: no cutting time in {model_log}")
            return 1
        model_ratio = 1 + float(m.group(1)) / 100
        cl_s = 60 * float(m.group(2) or 0) + float(m.group(3))
        print(f"model {model_ratio:.3f}x of {cl_s:.1f} s: {model_ratio / ratio if ratio else 0:.3f}x "
              f"the floor")
        if abs(cl_s - at_feed) > max(0.06, 0.01 * cl_s):
            print(f"time_floor: the conversion's CL feeds' time {cl_s} s is not the {at_feed:.2f} s "
                  f"of the motions counted here")
            return 1
        if model_ratio < ratio - 0.005:
            print("time_floor: the model is faster than the floor")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
