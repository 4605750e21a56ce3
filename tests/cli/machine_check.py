#!/usr/bin/env python3
"""Checks a written KRL program on the machine's terms, independently of redpost's own figures
(issue 16). Used by tests/cli/test_machine.sh.

    machine_check.py statements DIR
        every line of every .src/.dat in DIR is one of the statement forms a KR C4 accepts in
        redpost's template subset: headers, DEF/END, folds and comments, declarations, motions
        to literal aggregates, assignments of literals, WAIT SEC, HALT, calls. Free text as code
        (INSERT's holder descriptions, "Stock Size ...") fails.

    machine_check.py ptps PROGRAM.src JOINTS.csv CL_FILE REDPOST CELL.xml REFERENCE_LENGTH
        every PTP after the first motion, interpolated in joint space as a synchronous PTP does
        (a straight line from the joints of the motion before it, from the joints log, whose
        rows are first checked against the program's own E6AXIS values), through `redpost fk`
        (the chain's TCP, moved to the active tool's tip by the tool's length from the CL file's
        CUTTER/TLDATA): below the part's top (the holes' z) the tool tip may not be more than
        0.05 mm from a hole's axis.
"""
import re
import subprocess
import sys
from pathlib import Path

STATEMENT_FORMS = [
    r"&ACCESS \w+", r"&REL \d+", r"&PARAM \w+ = .*",
    r"(GLOBAL )?DEF \w+\( \)", r"END", r"DEFDAT \w+( PUBLIC)?", r"ENDDAT",
    r";.*",  # comments, folds
    r"(GLOBAL )?INTERRUPT DECL \d+ WHEN \$STOPMESS==TRUE DO IR_STOPM \( \)",
    r"INTERRUPT ON \d+", r"BAS \(#\w+,\s*\d+\s*\)",
    r"EXT \w+ ?\(.*\)",
    r"\$(BASE|TOOL) = (BASE_DATA|TOOL_DATA)\[\d+\]",
    r"\$BASE = EK\(MACHINE_DEF\[\d+\]\.ROOT, MACHINE_DEF\[\d+\]\.MECH_TYPE, BASE_DATA\[\d+\]\)",
    r"\$BASE = EK\(EX_AX_DATA\[\d+\]\.ROOT, EX_AX_DATA\[\d+\]\.EX_KIN, BASE_DATA\[\d+\]\)",
    r"\$LOAD = LOAD_DATA\[\d+\]", r"CONTINUE",
    r"\$(ACT_EX_AX|ACT_BASE|ACT_TOOL|ADVANCE) = \d+", r"\$APO\.CDIS = -?\d+\.\d+", r"\$VEL\.CP = \d+\.\d+",
    r"\$ORI_TYPE = #VAR", r"\$CIRC_TYPE = #BASE",
    r"(PTP|LIN|SLIN) \{(E6AXIS|E6POS): [^{}]*\}( C_DIS| C_PTP)?",
    r"CIRC \{X -?[\d.]+, Y -?[\d.]+, Z -?[\d.]+\}, \{E6POS: [^{}]*\}( C_DIS)?",
    r"SPLINE", r"ENDSPLINE( C_SPL)?",
    r"HALT( ;.*)?", r"WAIT SEC \d+(\.\d+)?",
    r"\w+\( \)",  # a call of a program part
    r"\$OUT\[\d+\] = (TRUE|FALSE)",  # what the tests pass through with INSERT/KRL:
]
STATEMENT_RE = re.compile("^(" + "|".join("(?:%s)" % f for f in STATEMENT_FORMS) + ")$")


def check_statements(folder):
    bad = []
    files = sorted(Path(folder).glob("*.src")) + sorted(Path(folder).glob("*.dat"))
    if not files:
        return ["no program in %s" % folder]
    for f in files:
        raw = f.read_bytes()
        if b"\r\n" not in raw or raw.replace(b"\r\n", b"").find(b"\n") >= 0:
            bad.append("%s: line ends are not CRLF throughout" % f)
        for n, line in enumerate(raw.decode("ascii").split("\r\n"), 1):
            code = line.strip()
            if code and not STATEMENT_RE.match(code):
                bad.append("%s:%d: not a statement of the subset: %s" % (f.name, n, code))
    return bad


def aggregate(text):
    return {k: float(v) for k, v in re.findall(r"([A-Z]+\d?) (-?\d+(?:\.\d+)?)", text)}


def tool_lengths(cl_file):
    """Tool number -> length from CUTTER (7th value) or TLDATA/MILL (4th), as the CL file says."""
    lengths, pending = {}, 0.0
    for line in Path(cl_file).read_text(errors="replace").splitlines():
        word = line.split("/")[0].strip().upper()
        values = line.split("/", 1)[1].split(",") if "/" in line else []
        if word == "CUTTER" and len(values) == 7:
            pending = float(values[6])
        elif word == "TLDATA" and len(values) >= 4 and values[0].strip().upper() == "MILL":
            pending = float(values[3])
        elif word in ("LOAD", "LOADTL"):
            number = int(float(values[1] if word == "LOAD" else values[0]))
            lengths[number] = pending
    return lengths


def holes(cl_file):
    """The hole points (x, y, z of the part's top) of the drilling cycles."""
    out, in_cycle = [], False
    for line in Path(cl_file).read_text(errors="replace").splitlines():
        u = line.strip().upper()
        if u.startswith("CYCLE/"):
            kind = u[6:].split(",")[0]
            in_cycle = kind not in ("OFF", "INIT")
        elif u.startswith("GOTO/") and in_cycle:
            out.append([float(v) for v in u[5:].split(",")[:3]])
    return out


def check_ptps(src, csv, cl_file, redpost, cell, reference_length):
    program = Path(src).read_text()
    rows = [line.split(",") for line in Path(csv).read_text().splitlines()]
    header, rows = rows[0], [[float(v) for v in r] for r in rows[1:]]
    # The joints are the columns between time_s and the first controller axis; with the
    # deflection model more columns follow the axes (docs/deflection.md).
    first_axis = next(i for i, h in enumerate(header) if re.match(r"^[AE]\d$", h))
    joints = list(range(header.index("time_s") + 1, first_axis))
    axis_col = {h: i for i, h in enumerate(header) if re.match(r"^[AE]\d$", h)}
    lengths = tool_lengths(cl_file)
    hole_points = holes(cl_file)
    top = min(h[2] for h in hole_points)
    motions, tool = [], None
    for line in program.splitlines():
        m = re.match(r"\$TOOL = TOOL_DATA\[(\d+)\]", line)
        if m:
            tool = int(m.group(1))
        m = re.match(r"(PTP|LIN|SLIN|CIRC) (.*)", line)
        if m:
            motions.append((m.group(1), m.group(2), tool))
    problems = []
    if len(motions) != len(rows):
        return ["%d motions in the program, %d rows in the joints log" % (len(motions), len(rows))]
    samples, spans = [], []
    for k, (kind, target, t) in enumerate(motions):
        if kind != "PTP":
            continue
        values = aggregate(target)
        for name, v in values.items():  # the log is the program's own postures
            if name in axis_col and abs(rows[k][axis_col[name]] - v) > 6e-4:
                problems.append("motion %d: %s %.4f in the program, %.4f in the log"
                                % (k + 1, name, v, rows[k][axis_col[name]]))
        if k == 0 or "A1" not in values:
            continue
        q0 = [rows[k - 1][i] for i in joints]
        q1 = [rows[k][i] for i in joints]
        first = len(samples)
        for s in range(201):
            samples.append([a + (b - a) * s / 200.0 for a, b in zip(q0, q1)])
        spans.append((k, first, len(samples), lengths.get(t, reference_length)))
    if not samples:
        return problems + ["no PTP after the first motion"]
    text = "\n".join(" ".join("%.12g" % v for v in q) for q in samples) + "\n"
    out = subprocess.run([redpost, "fk", "--cell", cell], input=text, capture_output=True,
                         text=True, check=True).stdout.split("\n")
    worst = 0.0
    for k, first, last, length in spans:
        for line in out[first:last]:
            v = [float(x) for x in line.split()]
            z_axis = (v[5], v[8], v[11])  # the third column of the rotation
            shift = length - reference_length  # the tool's tip beyond the chain's TCP
            tip = [v[i] - shift * z_axis[i] for i in range(3)]
            if tip[2] >= top:
                continue
            off = min(((tip[0] - h[0]) ** 2 + (tip[1] - h[1]) ** 2) ** 0.5 for h in hole_points)
            worst = max(worst, off)
            if off > 0.05:
                problems.append("PTP %d: tip %.3f mm below the part's top, %.3f mm off every "
                                "hole's axis" % (k + 1, top - tip[2], off))
                break
    print("ptps: %d PTPs sampled, worst distance from a hole's axis below the top %.4f mm"
          % (len(spans), worst))
    return problems


def main(argv):
    if len(argv) == 3 and argv[1] == "statements":
        problems = check_statements(argv[2])
    elif len(argv) == 8 and argv[1] == "ptps":
        problems = check_ptps(argv[2], argv[3], argv[4], argv[5], argv[6], float(argv[7]))
    else:
        print(__doc__)
        return 2
    for p in problems[:20]:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
