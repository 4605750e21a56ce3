#!/usr/bin/env python3
"""Writes a 5-axis APT raster of N poses for the convert benchmark (not committed output).

    python3 make_raster_apt.py N OUT.apt [--lift]

A zigzag over a 400 x 400 mm square on the Andres cell's table around (-100, -450, 60), 0.5 mm
between points, the tool axis tilting smoothly by up to 20 degrees; the raster repeats over the
square until N poses are written. With --lift the tool lifts 20 mm at the end of each line,
goes over the next line's start at the rapid speed and plunges at the feed: out of the material
once per line. Streams its output: memory does not grow with N.
"""
import math
import sys


def main():
    n = int(sys.argv[1])
    out = open(sys.argv[2], "w", newline="\n")
    lift = "--lift" in sys.argv[3:]
    w = out.write
    w("PARTNO/RASTER BENCHMARK\nUNITS/MM\nMULTAX/ON\nCUTTER/10.,5.\nLOADTL/1\n")
    w("SPINDL/15000,RPM,CLW\nRAPID\nGOTO/-100.0000,-450.0000,140.0000,0.0000000,0.0000000,1.0000000\n")
    w("FEDRAT/MMPM,3000\n")
    per_line, lines = 801, 126
    tilt = math.radians(20.0)
    written = 0
    line = 0
    while written < n:
        l = line % (2 * lines)
        v = (l if l < lines else 2 * lines - 1 - l) * (400.0 / (lines - 1)) - 200.0
        for k in range(per_line):
            if written >= n:
                break
            idx = k if line % 2 == 0 else per_line - 1 - k
            u = idx * 0.5 - 200.0
            a = tilt * math.sin(0.5 * math.pi * u / 200.0) / math.sqrt(2.0)
            b = tilt * math.sin(0.5 * math.pi * v / 200.0) / math.sqrt(2.0)
            # axis = Ry(a) Rx(b) z
            ax = math.sin(a) * math.cos(b)
            ay = -math.sin(b)
            az = math.cos(a) * math.cos(b)
            pose = f"{ax:.7f},{ay:.7f},{az:.7f}"
            if lift and k == 0 and line > 0:
                # From above the last line's end: rapid to above this start, plunge at the feed.
                w(f"RAPID\nGOTO/{-100.0 + u:.4f},{-450.0 + v:.4f},80.0000,{pose}\n")
            w(f"GOTO/{-100.0 + u:.4f},{-450.0 + v:.4f},60.0000,{pose}\n")
            written += 1
            if lift and k == per_line - 1:
                w(f"RAPID\nGOTO/{-100.0 + u:.4f},{-450.0 + v:.4f},80.0000,{pose}\n")
        line += 1
    w("RAPID\nGOTO/-100.0000,-450.0000,140.0000,0.0000000,0.0000000,1.0000000\nSPINDL/OFF\nFINI\n")
    out.close()


if __name__ == "__main__":
    main()
