#!/usr/bin/env python3
"""Writes the project's own set-up examples (examples/setup/*.stl): boxes as ASCII STL, in the
CL frame of the examples (mm), for `redpost convert --fixture/--part` (docs/collision.md).

    python3 examples/setup/make_setup.py

The files are committed; this script documents how they were made and regenerates them byte for
byte.
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def box_stl(name, lo, hi):
    """A closed box from corner lo to corner hi: 12 triangles, normals outward."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [((0, 3, 2, 1), (0, 0, -1)), ((4, 5, 6, 7), (0, 0, 1)), ((0, 1, 5, 4), (0, -1, 0)),
             ((2, 3, 7, 6), (0, 1, 0)), ((0, 4, 7, 3), (-1, 0, 0)), ((1, 2, 6, 5), (1, 0, 0))]
    out = [f"solid {name}"]
    for quad, n in faces:
        for tri in ((quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])):
            out.append(f"  facet normal {n[0]} {n[1]} {n[2]}")
            out.append("    outer loop")
            for k in tri:
                out.append("      vertex {:g} {:g} {:g}".format(*v[k]))
            out.append("    endloop")
            out.append("  endfacet")
    out.append(f"endsolid {name}")
    return "\n".join(out) + "\n"


FILES = {
    # The pocket example's stock (examples/cl/pocket_arcs.apt, 120 x 80 mm pocket 6 mm deep in a
    # block 200 x 140 x 60 mm): the finished part, which only the cutter may touch. The pocket
    # itself is not cut out of it: a part file is what the CAM system exports, and the cutter
    # (the whole tool where no flute length is given) may be in it.
    "pocket_block.stl": ((-220.0, -510.0, 0.0), (-20.0, -370.0, 60.0)),
    # A vise jaw beside the pocket, 160 mm tall and 40 mm beyond its edge: clear of everything
    # whatever the plan does (a set-up that changes nothing).
    "vise_jaw.stl": ((-220.0, -550.0, 0.0), (-20.0, -520.0, 160.0)),
    # A clamp tower 450 mm tall, 80 mm beyond the pocket's left edge: the wrist of a plan blind
    # to it passes through it; the plan that knows it turns the table, moves the track or the
    # spin (docs/collision.md, "Steering clear").
    "clamp_tower.stl": ((-280.0, -510.0, 0.0), (-260.0, -370.0, 450.0)),
    # A jaw 10 mm beyond the pocket's front edge, 200 mm tall: the spindle, coaxial with the tool
    # (60 mm in radius), passes through it whatever the redundancy does. No program exists.
    "jaw_too_close.stl": ((-220.0, -500.0, 0.0), (-20.0, -490.0, 200.0)),
    # A clamp strap across the part, 3 to 15 mm above the floor of the two short cuts of
    # tests/cli/test_collision.sh: only the rapid traverse between them, at cutting height,
    # would cross it.
    "clamp_strap.stl": ((-125.0, -470.0, 60.0), (-115.0, -410.0, 72.0)),
}


def main():
    for name, (lo, hi) in FILES.items():
        with open(os.path.join(HERE, name), "w", encoding="ascii", newline="\n") as f:
            f.write(box_stl(name.split(".")[0], lo, hi))


if __name__ == "__main__":
    main()
