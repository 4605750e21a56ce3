#!/usr/bin/env python3
"""Checks the <collision> bodies of the cell files (docs/cells.md, "Collision bodies").

    python3 tests/tools/collision_bodies_check.py [options] [CELL.xml ...]

Without a CELL.xml it checks the three shipped cells in definitions/cells/. Plain Python 3, no
third-party module; it reads the XML files itself and implements the forward kinematics of
docs/conventions.md on its own (standard DH Rz(theta) Tz(d) Tx(a) Rx(alpha), modified DH
Rx(alpha) Tx(a) Rz(theta) Tz(d), <base>/<fixed>/<tool> as x y z and KUKA A B C = Rz Ry Rx,
limits and home "in axis" converted by q = (axis - offset) / sign). A body on link="base" moves
with {B}; a body on link="NAME" with the frame after joint NAME's link.

What it checks, for each cell:
  1. the block itself: unique body names, known links, positive sizes, <allow> pairs naming
     existing bodies;
  2. skeleton: at home, points every 10 mm along the segment from the origin of frame i-1 to
     the origin of frame i (the link between two consecutive joint axes) lie inside the bodies
     of link i-1 or link i, for every joint of the arm (<conditioning first= last=>);
  3. home: no pair of bodies that is not <allow>ed overlaps or comes closer than --margin
     (the smallest clearances are listed);
  4. random postures: --samples postures drawn uniformly within the joint limits (seeded; the
     virtual joints stay at home); for each pair that is not allowed, in how many of them it
     overlaps. Self-collision there is expected for some pairs and is only reported;
  5. an SVG per cell (--svg DIR): side view (x-z of {B}) and top view (x-y of {B}) at home,
     with the bodies' outlines and the kinematic skeleton (frame origins joined in chain order).
Exit status 1 if check 1, 2 or 3 fails, else 0.

Distances between primitives (sphere, capsule, cylinder, box) are computed exactly up to
1e-3 mm with GJK on their support functions.

Options: --samples N (200), --seed S (1), --margin MM (0), --svg DIR (none), --quiet.
"""
import argparse
import math
import os
import random
import re
import sys
import xml.etree.ElementTree as ET

# ---------------------------------------------------------------- numbers and small linear algebra


def parse_number(text, kind, where):
    """A value of the cell format: lengths in mm (or 'm'/'mm'), angles in deg (or 'deg'/'rad')."""
    m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([a-z]*)\s*", text or "")
    if not m:
        raise ValueError(f"{where}: '{text}' is not a number")
    v, unit = float(m.group(1)), m.group(2)
    if kind == "angle":
        if unit in ("", "deg"):
            return math.radians(v)
        if unit == "rad":
            return v
    elif kind == "length":
        if unit in ("", "mm"):
            return v
        if unit == "m":
            return v * 1000.0
    raise ValueError(f"{where}: unknown unit '{unit}' for a {kind}")


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def norm(a):
    return math.sqrt(dot(a, a))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


class Frame:
    """A rigid transform: rotation R (3 rows) and translation t."""

    def __init__(self, R=None, t=(0.0, 0.0, 0.0)):
        self.R = R or ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        self.t = tuple(t)

    def __mul__(self, o):
        R = tuple(tuple(sum(self.R[i][k] * o.R[k][j] for k in range(3)) for j in range(3))
                  for i in range(3))
        return Frame(R, self.apply(o.t))

    def apply(self, p):
        return tuple(dot(self.R[i], p) + self.t[i] for i in range(3))

    def rotate(self, v):
        return tuple(dot(self.R[i], v) for i in range(3))

    def inverse(self):
        Rt = tuple(tuple(self.R[j][i] for j in range(3)) for i in range(3))
        return Frame(Rt, tuple(-dot(Rt[i], self.t) for i in range(3)))


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return Frame(((1, 0, 0), (0, c, -s), (0, s, c)))


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return Frame(((c, 0, s), (0, 1, 0), (-s, 0, c)))


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return Frame(((c, -s, 0), (s, c, 0), (0, 0, 1)))


def trans(x, y, z):
    return Frame(None, (x, y, z))


def kuka_frame(x, y, z, a, b, c):
    """x y z (mm) and KUKA A B C (rad): Trans * Rz(a) * Ry(b) * Rx(c)."""
    return trans(x, y, z) * rot_z(a) * rot_y(b) * rot_x(c)


# ---------------------------------------------------------------- the cell file


class Cell:
    pass


def read_cell(path):
    root = ET.parse(path).getroot()
    cell = Cell()
    cell.path, cell.name = path, root.get("name", os.path.basename(path))
    default_dh = root.get("dh", "standard")
    cell.chain, cell.joints = [], []  # chain: ('fixed', Frame) or ('joint', dict)
    cell.arm = None
    cell.collision = None

    def frame_of(e, where):
        g = lambda k, kind: parse_number(e.get(k, "0"), kind, where)
        return kuka_frame(g("x", "length"), g("y", "length"), g("z", "length"),
                          g("a", "angle"), g("b", "angle"), g("c", "angle"))

    for e in root:
        where = f"{path}: <{e.tag}>"
        if e.tag in ("base", "fixed", "tool"):
            cell.chain.append(("fixed", frame_of(e, where)))
        elif e.tag == "joint":
            d = e.find("dh")
            j = {"name": e.get("name"), "type": e.get("type"), "dh": e.get("dh", default_dh)}
            where = f"{path}: joint '{j['name']}'"
            for k in ("alpha", "theta"):
                j[k] = parse_number(d.get(k), "angle", where)
            for k in ("a", "d"):
                j[k] = parse_number(d.get(k), "length", where)
            ax = e.find("axis")
            sign = float(ax.get("sign", "1")) if ax is not None else 1.0
            offset = float(ax.get("offset", "0")) if ax is not None else 0.0
            j["axis"] = ax.get("name", "none") if ax is not None else "none"
            j["sign"], j["offset"] = sign, offset

            def to_q(elem, key):
                v = float(elem.get(key))
                return (v - offset) / sign if elem.get("in", "dh") == "axis" else v

            lim, home = e.find("limits"), e.find("home")
            lo, hi = to_q(lim, "min"), to_q(lim, "max")
            j["lo"], j["hi"], j["home"] = min(lo, hi), max(lo, hi), to_q(home, "value")
            cell.joints.append(j)
            cell.chain.append(("joint", j))
        elif e.tag == "conditioning":
            cell.arm = (e.get("first"), e.get("last"))
        elif e.tag == "collision":
            cell.collision = e
    return cell


def link_transform(j, q):
    """The link of joint j at joint value q (deg or mm)."""
    if j["type"] == "prismatic":
        theta, d = j["theta"], j["d"] + q
    else:
        theta, d = j["theta"] + math.radians(q), j["d"]
    if j["dh"] == "modified":
        return rot_x(j["alpha"]) * trans(j["a"], 0, 0) * rot_z(theta) * trans(0, 0, d)
    return rot_z(theta) * trans(0, 0, d) * trans(j["a"], 0, 0) * rot_x(j["alpha"])


def forward_kinematics(cell, q):
    """{'base': identity, joint name: T_B_link (frame after that joint's link)}, and the list of
    (joint name, frame before the link, frame after it) in chain order."""
    T = Frame()
    frames, links = {"base": Frame()}, []
    for kind, item in cell.chain:
        if kind == "fixed":
            T = T * item
        else:
            before = T
            T = T * link_transform(item, q[item["name"]])
            frames[item["name"]] = T
            links.append((item["name"], before, T))
    frames["tcp"] = T
    return frames, links


def home_posture(cell):
    return {j["name"]: j["home"] for j in cell.joints}


def random_posture(cell, rng):
    return {j["name"]: (j["home"] if j["type"] == "virtual" else rng.uniform(j["lo"], j["hi"]))
            for j in cell.joints}


# ---------------------------------------------------------------- collision bodies


class Primitive:
    """A primitive in its link's frame; .world(T) gives it in {B}."""

    def __init__(self, kind, data, where):
        self.kind, self.data, self.where = kind, data, where

    def world(self, T):
        k, d = self.kind, self.data
        if k == "sphere":
            return WorldPrim(k, c=T.apply(d["c"]), r=d["r"])
        if k in ("capsule", "cylinder"):
            return WorldPrim(k, p1=T.apply(d["p1"]), p2=T.apply(d["p2"]), r=d["r"])
        R = T * d["frame"]
        axes = tuple(tuple(R.R[i][col] for i in range(3)) for col in range(3))
        return WorldPrim(k, c=R.t, axes=axes, h=d["h"])


class WorldPrim:
    def __init__(self, kind, **kw):
        self.kind = kind
        self.__dict__.update(kw)
        if kind == "sphere":
            self.centre, self.bound = self.c, self.r
        elif kind in ("capsule", "cylinder"):
            self.centre = scale(add(self.p1, self.p2), 0.5)
            half = norm(sub(self.p2, self.p1)) / 2
            self.bound = half + self.r if kind == "capsule" else math.hypot(half, self.r)
            length = 2 * half
            self.u = scale(sub(self.p2, self.p1), 1 / length) if length > 0 else (0, 0, 1)
        else:
            self.centre, self.bound = self.c, norm(self.h)

    def support(self, d):
        k = self.kind
        n = norm(d)
        if k == "sphere":
            return add(self.c, scale(d, self.r / n)) if n > 0 else self.c
        if k == "capsule":
            p = self.p2 if dot(d, sub(self.p2, self.p1)) > 0 else self.p1
            return add(p, scale(d, self.r / n)) if n > 0 else p
        if k == "cylinder":
            du = dot(d, self.u)
            p = self.p2 if du > 0 else self.p1
            w = sub(d, scale(self.u, du))
            nw = norm(w)
            return add(p, scale(w, self.r / nw)) if nw > 1e-12 else p
        p = self.c
        for axis, h in zip(self.axes, self.h):
            p = add(p, scale(axis, h if dot(d, axis) >= 0 else -h))
        return p

    def contains(self, p, tol=1e-6):
        k = self.kind
        if k == "sphere":
            return norm(sub(p, self.c)) <= self.r + tol
        if k in ("capsule", "cylinder"):
            L = norm(sub(self.p2, self.p1))
            s = dot(sub(p, self.p1), self.u)
            if k == "cylinder":
                if s < -tol or s > L + tol:
                    return False
                return norm(sub(sub(p, self.p1), scale(self.u, s))) <= self.r + tol
            s = min(max(s, 0.0), L)
            return norm(sub(p, add(self.p1, scale(self.u, s)))) <= self.r + tol
        q = sub(p, self.c)
        return all(abs(dot(q, a)) <= h + tol for a, h in zip(self.axes, self.h))


def _closest_on_simplex(points):
    """The point of the convex hull of 1..4 points nearest the origin, and the points that
    support it. Every face of the simplex is tried: the nearest point lies in the relative
    interior of one of them, where it is the projection of the origin onto that face's
    affine hull with all barycentric coordinates >= 0."""
    best, best_set = None, None
    n = len(points)
    for mask in range(1, 1 << n):
        P = [points[i] for i in range(n) if mask >> i & 1]
        p0 = P[0]
        E = [sub(p, p0) for p in P[1:]]
        k = len(E)
        if k == 0:
            lam, x = [1.0], p0
        else:
            G = [[dot(E[i], E[j]) for j in range(k)] for i in range(k)]
            rhs = [-dot(E[i], p0) for i in range(k)]
            mu = _solve(G, rhs)
            if mu is None:
                continue
            lam = [1.0 - sum(mu)] + mu
            if min(lam) < -1e-12:
                continue
            x = p0
            for e, m in zip(E, mu):
                x = add(x, scale(e, m))
        d2 = dot(x, x)
        if best is None or d2 < dot(best, best) - 1e-15:
            best = x
            best_set = [p for p, l in zip(P, lam) if l > 1e-12] or [P[0]]
    return best, best_set


def _solve(G, rhs):
    k = len(G)
    A = [row[:] + [r] for row, r in zip(G, rhs)]
    scale_ = max(abs(v) for row in G for v in row) or 1.0
    for c in range(k):
        piv = max(range(c, k), key=lambda r: abs(A[r][c]))
        if abs(A[piv][c]) < 1e-10 * scale_:
            return None
        A[c], A[piv] = A[piv], A[c]
        for r in range(k):
            if r != c:
                f = A[r][c] / A[c][c]
                A[r] = [a - f * b for a, b in zip(A[r], A[c])]
    return [A[i][k] / A[i][i] for i in range(k)]


def distance(A, B, tol=1e-3):
    """Euclidean distance between two convex primitives (0 when they overlap), by GJK."""
    def s(d):
        return sub(A.support(d), B.support(scale(d, -1.0)))

    v = sub(A.centre, B.centre)
    if norm(v) < 1e-9:
        v = (1.0, 0.0, 0.0)
    v = s(scale(v, -1.0))
    simplex = [v]
    for _ in range(100):
        vv = dot(v, v)
        if vv < 1e-12:
            return 0.0
        w = s(scale(v, -1.0))
        if vv - dot(v, w) <= tol * math.sqrt(vv):
            return math.sqrt(vv)
        if any(norm(sub(w, p)) < 1e-9 for p in simplex):
            return math.sqrt(vv)
        v, simplex = _closest_on_simplex(simplex + [w])
        if len(simplex) == 4:
            return 0.0
    return norm(v)


def read_collision(cell):
    """{body: (link, [Primitive])}, [(a, b)] allowed; raises ValueError with every problem."""
    errors, bodies, allowed = [], {}, []
    col = cell.collision
    if col is None:
        return bodies, allowed
    links = {"base"} | {j["name"] for j in cell.joints}
    for e in col:
        if e.tag == "body":
            name, link = e.get("name"), e.get("link")
            where = f"{cell.path}: body '{name}'"
            if not name or name in bodies:
                errors.append(f"{where}: missing or duplicate name")
            if link not in links:
                errors.append(f"{where}: unknown link '{link}'")
            prims = []
            for p in e:
                try:
                    prims.append(read_primitive(p, f"{where} <{p.tag}>"))
                except ValueError as ex:
                    errors.append(str(ex))
            if not prims:
                errors.append(f"{where}: no primitive")
            bodies[name] = (link, prims)
        elif e.tag == "allow":
            allowed.append((e.get("a"), e.get("b")))
        else:
            errors.append(f"{cell.path}: unknown element <{e.tag}> in <collision>")
    for a, b in allowed:
        if a not in bodies or b not in bodies or a == b:
            errors.append(f"{cell.path}: <allow a='{a}' b='{b}'> does not name two bodies")
    if errors:
        raise ValueError("\n".join(errors))
    return bodies, {frozenset(p) for p in allowed}


def read_primitive(e, where):
    L = lambda k: parse_number(e.get(k), "length", where)
    A = lambda k: parse_number(e.get(k, "0"), "angle", where)
    if e.tag == "sphere":
        data = {"c": (L("x"), L("y"), L("z")), "r": L("radius")}
        sizes = [data["r"]]
    elif e.tag in ("capsule", "cylinder"):
        data = {"p1": (L("x1"), L("y1"), L("z1")), "p2": (L("x2"), L("y2"), L("z2")),
                "r": L("radius")}
        sizes = [data["r"]]
        if e.tag == "cylinder":
            sizes.append(norm(sub(data["p2"], data["p1"])))
    elif e.tag == "box":
        data = {"frame": kuka_frame(L("x"), L("y"), L("z"), A("a"), A("b"), A("c")),
                "h": (L("dx") / 2, L("dy") / 2, L("dz") / 2)}
        sizes = list(data["h"])
    else:
        raise ValueError(f"{where}: unknown primitive")
    if min(sizes) <= 0:
        raise ValueError(f"{where}: sizes must be > 0")
    return Primitive(e.tag, data, where)


def world_bodies(bodies, frames):
    return {name: [p.world(frames[link]) for p in prims] for name, (link, prims) in bodies.items()}


def body_distance(A, B, stop_below=None):
    best = math.inf
    for a in A:
        for b in B:
            if norm(sub(a.centre, b.centre)) - a.bound - b.bound >= best:
                continue
            best = min(best, distance(a, b))
            if stop_below is not None and best <= stop_below:
                return best
    return best


def checked_pairs(bodies, allowed):
    names = sorted(bodies)
    return [(a, b) for i, a in enumerate(names) for b in names[i + 1:]
            if frozenset((a, b)) not in allowed]


# ---------------------------------------------------------------- the checks


def check_skeleton(cell, bodies, frames, links):
    """Points along each arm link's segment must lie inside that link's bodies or its parent's."""
    problems = []
    if cell.arm is None:
        return ["no <conditioning first= last=>: the arm's joints are unknown"]
    names = [j["name"] for j in cell.joints]
    first, last = names.index(cell.arm[0]), names.index(cell.arm[1])
    world = world_bodies(bodies, frames)
    by_link = {}
    for body, (link, _) in bodies.items():
        by_link.setdefault(link, []).extend(world[body])
    for idx in range(first, last + 1):
        name, before, after = links[idx]
        parent = "base" if idx == 0 else links[idx - 1][0]
        prims = by_link.get(name, []) + by_link.get(parent, [])
        p0, p1 = before.t, after.t
        n = max(1, int(norm(sub(p1, p0)) / 10.0))
        outside = [i for i in range(n + 1)
                   if not any(pr.contains(add(p0, scale(sub(p1, p0), i / n)), 0.5) for pr in prims)]
        if outside:
            p = add(p0, scale(sub(p1, p0), outside[0] / n))
            problems.append(f"link '{name}': {len(outside)} of {n + 1} skeleton points outside the "
                            f"bodies of '{name}' and '{parent}' (first at "
                            f"{p[0]:.0f} {p[1]:.0f} {p[2]:.0f} in {{B}})")
    return problems


def check_cell(cell, args, out):
    ok = True
    try:
        bodies, allowed = read_collision(cell)
    except ValueError as ex:
        out(f"  FAIL block: {ex}")
        return False
    if not bodies:
        out("  no <collision> block")
        return True
    nprim = sum(len(p) for _, p in bodies.values())
    out(f"  {len(bodies)} bodies, {nprim} primitives, {len(allowed)} allowed pairs")
    frames, links = forward_kinematics(cell, home_posture(cell))

    problems = check_skeleton(cell, bodies, frames, links)
    for p in problems:
        out(f"  FAIL skeleton: {p}")
    if not problems:
        out("  skeleton: every arm link's segment lies inside its bodies")
    ok &= not problems

    pairs = checked_pairs(bodies, allowed)
    world = world_bodies(bodies, frames)
    clear = sorted((body_distance(world[a], world[b]), a, b) for a, b in pairs)
    bad = [c for c in clear if c[0] <= args.margin]
    for d, a, b in bad:
        out(f"  FAIL home: '{a}' and '{b}' are {d:.1f} mm apart (margin {args.margin:g} mm)")
    ok &= not bad
    out(f"  home: {len(pairs)} pairs checked, {len(bad)} closer than the margin; smallest "
        "clearances: " + ", ".join(f"{a}/{b} {d:.0f} mm" for d, a, b in clear[:5]))

    rng = random.Random(args.seed)
    counts = {p: 0 for p in pairs}
    for _ in range(args.samples):
        fr, _ = forward_kinematics(cell, random_posture(cell, rng))
        w = world_bodies(bodies, fr)
        for a, b in pairs:
            if body_distance(w[a], w[b], stop_below=args.margin) <= args.margin:
                counts[(a, b)] += 1
    hits = sorted(((n, a, b) for (a, b), n in counts.items() if n), reverse=True)
    out(f"  random postures ({args.samples}, seed {args.seed}): "
        + ("no pair overlaps" if not hits else f"{len(hits)} pairs overlap somewhere:"))
    for n, a, b in hits:
        out(f"    {a} / {b}: {n}")

    if args.svg:
        os.makedirs(args.svg, exist_ok=True)
        path = os.path.join(args.svg, f"collision_{cell.name}.svg")
        write_svg(cell, bodies, frames, links, path)
        out(f"  picture: {path}")
    return ok


# ---------------------------------------------------------------- the picture


def outline(prim, view):
    """2D convex outline of a world primitive projected on the view's two axes."""
    ax = {"side": (0, 2), "top": (0, 1)}[view]
    pts = []
    if prim.kind == "sphere":
        pts = [(prim.c[ax[0]] + prim.r * math.cos(t), prim.c[ax[1]] + prim.r * math.sin(t))
               for t in (i * math.pi / 24 for i in range(48))]
        return pts
    if prim.kind in ("capsule", "cylinder"):
        u = prim.u
        e1 = cross(u, (1, 0, 0)) if abs(u[0]) < 0.9 else cross(u, (0, 1, 0))
        e1 = scale(e1, 1 / norm(e1))
        e2 = cross(u, e1)
        for end in (prim.p1, prim.p2):
            for i in range(48):
                t = i * math.pi / 24
                if prim.kind == "capsule":
                    for j in range(-6, 7):
                        phi = j * math.pi / 12
                        d = add(scale(add(scale(e1, math.cos(t)), scale(e2, math.sin(t))),
                                      math.cos(phi)), scale(u, math.sin(phi)))
                        p = add(end, scale(d, prim.r))
                        pts.append((p[ax[0]], p[ax[1]]))
                else:
                    p = add(end, scale(add(scale(e1, math.cos(t)), scale(e2, math.sin(t))), prim.r))
                    pts.append((p[ax[0]], p[ax[1]]))
    else:
        for sx in (-1, 1):
            for sy in (-1, 1):
                for sz in (-1, 1):
                    p = prim.c
                    for axis, h, s in zip(prim.axes, prim.h, (sx, sy, sz)):
                        p = add(p, scale(axis, h * s))
                    pts.append((p[ax[0]], p[ax[1]]))
    return convex_hull(pts)


def convex_hull(pts):
    pts = sorted(set((round(x, 3), round(y, 3)) for x, y in pts))
    if len(pts) < 3:
        return pts

    def half(points):
        h = []
        for p in points:
            while len(h) >= 2 and ((h[-1][0] - h[-2][0]) * (p[1] - h[-2][1])
                                   - (h[-1][1] - h[-2][1]) * (p[0] - h[-2][0])) <= 0:
                h.pop()
            h.append(p)
        return h

    lower, upper = half(pts), half(list(reversed(pts)))
    return lower[:-1] + upper[:-1]


COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
           "#7f7f7f", "#bcbd22", "#17becf", "#393b79", "#637939", "#8c6d31", "#843c39"]


def write_svg(cell, bodies, frames, links, path):
    world = world_bodies(bodies, frames)
    names = sorted(bodies)
    views = []
    for view in ("side", "top"):
        shapes = [(n, outline(p, view)) for n in names for p in world[n]]
        ax = {"side": (0, 2), "top": (0, 1)}[view]
        skel = [(frames["base"].t[ax[0]], frames["base"].t[ax[1]])]
        skel += [(after.t[ax[0]], after.t[ax[1]]) for _, _, after in links]
        pts = [p for _, o in shapes for p in o] + skel
        box = (min(p[0] for p in pts) - 100, max(p[0] for p in pts) + 100,
               min(p[1] for p in pts) - 100, max(p[1] for p in pts) + 100)
        views.append((view, shapes, skel, box))
    # one scale for both views: the larger extent of either fills 700 px
    k = 700.0 / max(max(b[1] - b[0], b[3] - b[2]) for _, _, _, b in views)
    W = [(b[1] - b[0]) * k for _, _, _, b in views]
    H = max((b[3] - b[2]) * k for _, _, _, b in views)
    width = max(20 + W[0] + 20 + W[1] + 20, 700)
    rows = (len(names) + 2) // 3
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" '
           f'height="{H + 90 + 18 * rows:.0f}" font-family="sans-serif" font-size="12">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<text x="20" y="16">{cell.name} at home: bodies (outlines) and the chain of frame '
           'origins (black)</text>']
    ox = 20
    for vi, (view, shapes, skel, (x0, x1, y0, y1)) in enumerate(views):
        X = lambda x, ox=ox, x0=x0: ox + (x - x0) * k
        Y = lambda y, y1=y1: 50 + (y1 - y) * k
        label = "side view: x right, z up, in {B}" if view == "side" else "top view: x right, y up"
        svg.append(f'<text x="{ox:.0f}" y="40">{label}</text>')
        svg.append(f'<rect x="{ox:.0f}" y="50" width="{W[vi]:.0f}" height="{(y1 - y0) * k:.0f}" '
                   'fill="none" stroke="#ccc"/>')
        for n, o in shapes:
            c = COLOURS[names.index(n) % len(COLOURS)]
            d = " ".join(f"{X(x):.1f},{Y(y):.1f}" for x, y in o)
            svg.append(f'<polygon points="{d}" fill="{c}" fill-opacity="0.18" stroke="{c}" '
                       'stroke-width="1"/>')
        d = " ".join(f"{X(x):.1f},{Y(y):.1f}" for x, y in skel)
        svg.append(f'<polyline points="{d}" fill="none" stroke="black" stroke-width="2"/>')
        for x, y in skel:
            svg.append(f'<circle cx="{X(x):.1f}" cy="{Y(y):.1f}" r="3" fill="black"/>')
        base = 50 + (y1 - y0) * k
        svg.append(f'<line x1="{ox + 10:.0f}" y1="{base - 10:.0f}" x2="{ox + 10 + 500 * k:.0f}" '
                   f'y2="{base - 10:.0f}" stroke="black" stroke-width="3"/>')
        svg.append(f'<text x="{ox + 10:.0f}" y="{base - 16:.0f}">500 mm</text>')
        ox += W[vi] + 20
    for i, n in enumerate(names):
        c = COLOURS[i % len(COLOURS)]
        x, y = 20 + (i % 3) * 230, H + 80 + 18 * (i // 3)
        svg.append(f'<rect x="{x}" y="{y - 10:.0f}" width="10" height="10" fill="{c}"/>')
        svg.append(f'<text x="{x + 14}" y="{y:.0f}">{n} ({bodies[n][0]})</text>')
    svg.append("</svg>")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(svg) + "\n")


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    cells_dir = os.path.normpath(os.path.join(here, "..", "..", "definitions", "cells"))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("cells", nargs="*")
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--margin", type=float, default=0.0)
    ap.add_argument("--svg", default=None)
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    paths = args.cells or sorted(os.path.join(cells_dir, f) for f in os.listdir(cells_dir)
                                 if f.endswith(".xml"))
    ok = True
    for path in paths:
        lines = []
        cell = read_cell(path)
        cell_ok = check_cell(cell, args, lines.append)
        ok &= cell_ok
        if not args.quiet or not cell_ok:
            print(f"{path}: {'ok' if cell_ok else 'FAILED'}")
            print("\n".join(lines))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
