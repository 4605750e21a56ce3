#!/usr/bin/env python3
"""The fixture scene of the collision benchmarks (collision_bench.sh, review_bench.sh).

make_raster_apt.py's raster covers x -300..100, y -650..-250 at z 60: two clamps 40 mm beyond
its left and right edges, 120 mm tall, and the part (a box) under it, as STL in the CL frame.

Usage: write_fixture_scene.py OUT_DIR   (writes clamp_left.stl, clamp_right.stl, part.stl)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "examples", "setup"))
from make_setup import box_stl  # noqa: E402

out = sys.argv[1]
for name, lo, hi in (("clamp_left", (-370, -560, 0), (-340, -340, 120)),
                     ("clamp_right", (140, -560, 0), (170, -340, 120)),
                     ("part", (-310, -660, 0), (110, -240, 55))):
    with open(os.path.join(out, name + ".stl"), "w") as f:
        f.write(box_stl(name, lo, hi))
