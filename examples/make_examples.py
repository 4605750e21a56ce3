#!/usr/bin/env python3
"""Writes the project's own example CL files (examples/cl/). Run from anywhere:

    python3 examples/make_examples.py

The files are committed; this script documents how they were made and regenerates them
byte for byte. Coordinates are in the workpiece frame of the Andres cell ({B}: centre of the
rotary table, z up; the part stands on a riser, the table top at z = -250); see docs/cells.md
for where the arm can reach.
"""
import math
import os

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cl")


def f(x):
    return f"{x:.4f}".rstrip("0").rstrip(".") if abs(x) > 5e-5 else "0"


def pocket_with_arcs():
    """A 3-axis rectangular pocket with rounded corners (CIRCLE records), two depth passes."""
    cx, cy, top = -120.0, -440.0, 60.0
    half_x, half_y, r = 60.0, 40.0, 12.0
    out = [
        "PARTNO/POCKET WITH ARCS",
        "$$ redpost example: 3-axis pocket, 120 x 80 mm, corner radius 12 mm",
        "UNITS/MM",
        "CUTTER/10.,0",
        "LOADTL/1",
        "SPINDL/12000,RPM,CLW",
        "COOLNT/FLOOD",
        "RAPID",
        f"GOTO/{f(cx)},{f(cy)},{f(top + 50)}",
    ]
    for depth in (3.0, 6.0):
        z = top - depth
        out += [
            "RAPID",
            f"GOTO/{f(cx)},{f(cy)},{f(top + 2)}",
            "FEDRAT/200,MMPM",
            f"GOTO/{f(cx)},{f(cy)},{f(z)}",
            "FEDRAT/MMPM,900",
            f"GOTO/{f(cx + half_x - r)},{f(cy - half_y)},{f(z)}",
        ]
        # Counter-clockwise around the pocket: straight, corner arc, straight, ...
        corners = [
            (cx + half_x - r, cy - half_y + r, (cx + half_x, cy - half_y + r), (cx + half_x, cy + half_y - r)),
            (cx + half_x - r, cy + half_y - r, (cx + half_x - r, cy + half_y), (cx - half_x + r, cy + half_y)),
            (cx - half_x + r, cy + half_y - r, (cx - half_x, cy + half_y - r), (cx - half_x, cy - half_y + r)),
            (cx - half_x + r, cy - half_y + r, (cx - half_x + r, cy - half_y), (cx, cy - half_y)),
        ]
        for (kx, ky, arc_end, line_end) in corners:
            out.append(f"CIRCLE/{f(kx)},{f(ky)},{f(z)},0,0,1,{f(r)},0.01,0.5,10,0")
            out.append(f"GOTO/{f(arc_end[0])},{f(arc_end[1])},{f(z)}")
            out.append(f"GOTO/{f(line_end[0])},{f(line_end[1])},{f(z)}")
        out += ["RAPID", f"GOTO/{f(cx)},{f(cy - half_y)},{f(top + 50)}"]
    out += ["SPINDL/OFF", "COOLNT/OFF", "FINI"]
    return "\n".join(out) + "\n"


def surface_5axis():
    """NX CLSF style: a 5-axis pass over a convex cylindrical patch, tool normal to it."""
    R = 250.0
    axis_x0, axis_x1 = -220.0, -20.0
    cy, cz = -450.0, 60.0 - R  # the cylinder's top line is at z = 60
    out = [
        "TOOL PATH/SURFACE_5AXIS,TOOL,BALL_D10",
        "TLDATA/MILL,10.0000,5.0000,75.0000,0.0000,0.0000",
        "MSYS/0.0000,0.0000,0.0000,1.0000000,0.0000000,0.0000000,0.0000000,1.0000000,0.0000000",
        "$$ redpost example: variable-axis finishing pass, tool normal to a R250 cylinder",
        "PAINT/PATH",
        "LOAD/TOOL,1,ADJUST,1",
        "SELECT/TOOL,1",
        "MULTAX/ON",
        "SPINDL/RPM,15000,CLW",
        "RAPID",
        f"GOTO/{f(axis_x0)},{f(cy)},{f(cz + R + 60)},0.0000000,0.0000000,1.0000000",
        "FEDRAT/MMPM,1200.0000",
    ]
    passes = 13
    for k in range(passes):
        phi = math.radians(-30.0 + 60.0 * k / (passes - 1))
        ny, nz = math.sin(phi), math.cos(phi)
        y, z = cy + (R + 5.0) * ny, cz + (R + 5.0) * nz  # ball centre 5 mm off the surface
        xs = [axis_x0 + i * 2.0 for i in range(int((axis_x1 - axis_x0) / 2.0) + 1)]
        if k % 2:
            xs.reverse()
        for x in xs:
            out.append(f"GOTO/{x:.4f},{y:.4f},{z:.4f},0.0000000,{ny:.7f},{nz:.7f}")
    out += [
        "RAPID",
        f"GOTO/{f(axis_x0)},{f(cy)},{f(cz + R + 60)},0.0000000,0.0000000,1.0000000",
        "END-OF-PATH",
    ]
    return "\n".join(out) + "\n"


def long_pass():
    """A 2 m straight pass along the track direction: the arm alone cannot finish it."""
    y0, y1, z = -300.0, -2300.0, 60.0
    out = [
        "PARTNO/LONG PASS",
        "$$ redpost example: 2 m along the track (Andres et al. Fig. 14): track and table must move",
        "UNITS/MM",
        "CUTTER/16.,0",
        "LOADTL/2",
        "SPINDL/8000,RPM,CLW",
        "RAPID",
        f"GOTO/-100,{f(y0)},{f(z + 40)}",
        "FEDRAT/MMPM,2000",
        f"GOTO/-100,{f(y0)},{f(z)}",
    ]
    steps = 400
    for i in range(1, steps + 1):
        out.append(f"GOTO/-100,{f(y0 + (y1 - y0) * i / steps)},{f(z)}")
    out += ["RAPID", f"GOTO/-100,{f(y1)},{f(z + 40)}", "SPINDL/OFF", "FINI"]
    return "\n".join(out) + "\n"


def caro2014_contour():
    """The tool path of the placement job (examples/placement/caro2014_job.xml) as a CL file:
    the five 200 mm segments of Caro 2014 Figure 3.1 as chosen there, offset by the 20 mm tool's
    radius away from the material (on the right of the feed), 10 mm between points, one TOOL
    PATH per segment so that the cutting file can give each its width of cut."""
    r, z, points = 10.0, 0.0, 20
    corners = [("A", -400.0, -200.0), ("B", -200.0, -200.0), ("C", -200.0, 0.0),
               ("O_W", 0.0, 0.0), ("D", 0.0, -200.0), ("E", 200.0, -200.0)]
    # The offset path: each segment's line moved by r to the left of its feed; consecutive
    # lines meet at the offset corners (the ends are moved across their own segment only).
    lines = []
    for (_, x0, y0), (_, x1, y1) in zip(corners, corners[1:]):
        dx, dy = (x1 - x0) / 200.0, (y1 - y0) / 200.0
        lines.append(((x0 - dy * r, y0 + dx * r), (x1 - dy * r, y1 + dx * r), (dx, dy)))
    ends = [lines[0][0]]
    for (p0, _, d0), (p1, _, d1) in zip(lines, lines[1:]):
        # Intersection of p0 + s d0 and p1 + t d1 (the segments turn by 90 degrees).
        det = d0[0] * -d1[1] + d1[0] * d0[1]
        s = ((p1[0] - p0[0]) * -d1[1] + d1[0] * (p1[1] - p0[1])) / det
        ends.append((p0[0] + s * d0[0], p0[1] + s * d0[1]))
    ends.append(lines[-1][1])
    out = [
        "PARTNO/CARO2014 CONTOUR",
        "$$ redpost example: the placement job's contour (Caro 2014 Figure 3.1, as chosen in",
        "$$ examples/placement/caro2014_job.xml), 20 mm end mill, material on the right",
        "UNITS/MM",
        "CUTTER/20.,0",
        "LOADTL/1",
        "SPINDL/20000,RPM,CLW",
        "RAPID",
        f"GOTO/{f(ends[0][0])},{f(ends[0][1])},50",
        "FEDRAT/MMPM,4000",
        f"GOTO/{f(ends[0][0])},{f(ends[0][1])},{f(z)}",
    ]
    for k, ((a, _, _), (b, _, _)) in enumerate(zip(corners, corners[1:])):
        out.append(f"TOOL PATH/{a}{b},TOOL,T1")
        (x0, y0), (x1, y1) = ends[k], ends[k + 1]
        n = max(1, round(points * math.hypot(x1 - x0, y1 - y0) / 200.0))
        for i in range(1, n + 1):
            out.append(f"GOTO/{f(x0 + (x1 - x0) * i / n)},{f(y0 + (y1 - y0) * i / n)},{f(z)}")
        out.append("END-OF-PATH")
    out += ["RAPID", f"GOTO/{f(ends[-1][0])},{f(ends[-1][1])},50", "SPINDL/OFF", "FINI"]
    return "\n".join(out) + "\n"


def main():
    os.makedirs(HERE, exist_ok=True)
    placement = os.path.join(os.path.dirname(HERE), "placement", "caro2014_contour.apt")
    with open(placement, "w", newline="\n") as out:
        out.write(caro2014_contour())
    for name, text in (("pocket_arcs.apt", pocket_with_arcs()),
                       ("surface_5axis.cls", surface_5axis()),
                       ("long_pass.apt", long_pass())):
        with open(os.path.join(HERE, name), "w", newline="\n") as out:
            out.write(text)


if __name__ == "__main__":
    main()
