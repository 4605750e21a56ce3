#!/usr/bin/env python3
"""Checks the source layout against docs/architecture.md (issue 19).

    check_layout.py ROOT        check the tree at ROOT; exit 1 and name every breach
    check_layout.py --self-test build a small tree that breaks each rule and require that every
                                breach is found (so that the check itself cannot rot)

The dependency rule is read from the table in docs/architecture.md between the markers
`<!-- layers:begin -->` and `<!-- layers:end -->`: one row per concept folder of core/, the last
column lists (in backticks) the concepts it may include. The doc is the single statement of the
rule; this script only enforces it.

What is checked:
- every `#include "redpost/<concept>/..."` (public) and `#include "<concept>/..."` (private,
  core/src) in core/ is allowed for the including file's concept;
- core/ includes nothing of plugin/ (redpost.h, redpost/report/, Tcl, CLI11);
- plugin/report/ includes nothing of core/ (it draws plain data);
- core/src and core/include/redpost have the same concept folders, each one in the table, and
  tests/unit has a folder for each;
- at most 2 files directly in core/src and in core/include/redpost, at most 4 in tests/unit;
- no C/C++ file in core/ or plugin/ over 800 lines.
"""
import os
import re
import sys
import tempfile

MAX_FILE_LINES = 800
MAX_TOP_FILES = {"core/src": 2, "core/include/redpost": 2, "tests/unit": 4}
CODE_EXT = (".cpp", ".hpp", ".h", ".c")
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')


def read_rule(root):
    """{concept: set(allowed concepts)} from the table in docs/architecture.md."""
    path = os.path.join(root, "docs", "architecture.md")
    try:
        text = open(path, encoding="utf-8").read()
    except OSError as e:
        return None, [f"{path}: cannot read the dependency rule: {e.strerror}"]
    m = re.search(r"<!-- layers:begin -->(.*?)<!-- layers:end -->", text, re.S)
    if not m:
        return None, [f"{path}: no table between <!-- layers:begin --> and <!-- layers:end -->"]
    rule = {}
    for line in m.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or not cells[0].startswith("`"):
            continue
        concept = cells[0].strip("`")
        rule[concept] = set(re.findall(r"`([a-z_]+)`", cells[-1]))
    if not rule:
        return None, [f"{path}: the layers table has no rows"]
    return rule, []


def code_files(top):
    for dirpath, dirnames, filenames in os.walk(top):
        dirnames.sort()
        for name in sorted(filenames):
            if name.endswith(CODE_EXT):
                yield os.path.join(dirpath, name)


def includes(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f, 1):
            m = INCLUDE_RE.match(line)
            if m:
                yield number, m.group(1)


def concept_of(root, path):
    """The concept folder of a file under core/src or core/include/redpost, or None."""
    rel = os.path.relpath(path, root).replace(os.sep, "/")
    for prefix in ("core/src/", "core/include/redpost/"):
        if rel.startswith(prefix):
            parts = rel[len(prefix):].split("/")
            return parts[0] if len(parts) > 1 else None
    return None


def check(root):
    rule, problems = read_rule(root)
    if rule is None:
        return problems
    concepts = set(rule)
    rel = lambda p: os.path.relpath(p, root).replace(os.sep, "/")

    # Folders: the same concepts in both core trees, all in the table, all mirrored in tests/unit.
    for top in ("core/src", "core/include/redpost"):
        folders = {d for d in os.listdir(os.path.join(root, top))
                   if os.path.isdir(os.path.join(root, top, d))}
        for d in sorted(folders - concepts):
            problems.append(f"{top}/{d}: a concept folder that docs/architecture.md does not name")
    unit = os.path.join(root, "tests", "unit")
    for c in sorted(concepts):
        for top in ("core/src", "core/include/redpost", "tests/unit"):
            if not os.path.isdir(os.path.join(root, top, c)):
                problems.append(f"{top}/{c}: missing (docs/architecture.md names the concept {c})")
    for top, limit in MAX_TOP_FILES.items():
        d = os.path.join(root, top)
        files = sorted(f for f in os.listdir(d) if os.path.isfile(os.path.join(d, f)))
        if len(files) > limit:
            problems.append(f"{top}: {len(files)} files directly in the folder (at most {limit}: "
                            f"{', '.join(files)}); put them in a concept folder")

    # Includes.
    for path in code_files(os.path.join(root, "core")):
        mine = concept_of(root, path)
        for number, inc in includes(path):
            where = f"{rel(path)}:{number}"
            if inc == "redpost.h" or inc.startswith("redpost/report/") or inc.startswith("tcl") \
                    or inc.startswith("CLI/"):
                problems.append(f"{where}: core includes <{inc}>, which belongs to plugin/")
                continue
            parts = inc.split("/")
            if parts[0] == "redpost" and len(parts) >= 3:
                target = parts[1]
            elif len(parts) >= 2 and parts[0] in concepts:
                target = parts[0]
            else:
                continue
            if target not in concepts:
                problems.append(f"{where}: includes \"{inc}\" of an unknown concept '{target}'")
            elif mine is not None and target != mine and target not in rule[mine]:
                allowed = ", ".join(sorted(rule[mine])) or "nothing of ours"
                problems.append(f"{where}: {mine} includes \"{inc}\" ({target}); {mine} may "
                                f"include only {allowed} (docs/architecture.md)")
    report_dir = os.path.join(root, "plugin", "report")
    if os.path.isdir(report_dir):
        for path in code_files(report_dir):
            for number, inc in includes(path):
                parts = inc.split("/")
                if parts[0] == "redpost" and len(parts) >= 3 and parts[1] in concepts:
                    problems.append(f"{rel(path)}:{number}: the report library includes \"{inc}\";"
                                    " it draws plain data and uses nothing of core/")

    # File sizes.
    for top in ("core", "plugin"):
        for path in code_files(os.path.join(root, top)):
            with open(path, encoding="utf-8", errors="replace") as f:
                n = sum(1 for _ in f)
            if n > MAX_FILE_LINES:
                problems.append(f"{rel(path)}: {n} lines (at most {MAX_FILE_LINES}); split it by "
                                "responsibility")
    return problems


def self_test():
    """A tree that breaks every rule once; each breach must be reported."""
    with tempfile.TemporaryDirectory() as root:
        def write(rel, text):
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        write("docs/architecture.md", "<!-- layers:begin -->\n| concept | job | may include |\n"
              "|---|---|---|\n| `io` | files | nothing of ours |\n"
              "| `kinematics` | FK | `io` |\n| `redundancy` | tracker | `kinematics`, `io` |\n"
              "<!-- layers:end -->\n")
        for c in ("io", "kinematics", "redundancy"):
            write(f"core/include/redpost/{c}/a.hpp", "#pragma once\n")
        for c in ("io", "kinematics"):  # no tests/unit/redundancy
            write(f"tests/unit/{c}/test_a.cpp", "\n")
        write("core/src/io/a.cpp", '#include "redpost/io/a.hpp"\n')
        write("core/src/redundancy/a.cpp", '#include "redpost/kinematics/a.hpp"\n')  # allowed
        write("core/src/kinematics/a.cpp",
              '#include "redpost/redundancy/a.hpp"\n'   # upward: refused
              '#include "io/private.hpp"\n'             # private, allowed
              '#include "redundancy/private.hpp"\n'     # private, upward: refused
              '#include "redpost.h"\n')                 # the plugin's header: refused
        write("core/src/io/b.cpp", '#include "redpost/kinematics/a.hpp"\n')  # io uses nothing
        write("core/src/extra/b.cpp", "\n")  # a folder the doc does not name
        for i in range(3):
            write(f"core/include/redpost/loose{i}.hpp", "\n")  # 3 > 2 at the top
        write("plugin/report/src/p.cpp", '#include "redpost/kinematics/a.hpp"\n')
        write("plugin/cli/long.cpp", "\n" * (MAX_FILE_LINES + 1))
        found = check(root)
        expected = [
            "core/src/kinematics/a.cpp:1: kinematics includes \"redpost/redundancy/a.hpp\"",
            "core/src/kinematics/a.cpp:3: kinematics includes \"redundancy/private.hpp\"",
            "core/src/kinematics/a.cpp:4: core includes <redpost.h>",
            "core/src/io/b.cpp:1: io includes \"redpost/kinematics/a.hpp\"",
            "core/src/extra: a concept folder",
            "tests/unit/redundancy: missing",
            "core/include/redpost: 3 files directly",
            "plugin/report/src/p.cpp:1: the report library includes",
            "plugin/cli/long.cpp: 801 lines",
        ]
        missing = [e for e in expected if not any(p.startswith(e) for p in found)]
        allowed_hits = [p for p in found if p.startswith("core/src/redundancy/a.cpp")
                        or p.startswith("core/src/kinematics/a.cpp:2")]
        for e in missing:
            print(f"self-test: the check did not report: {e}")
        for p in allowed_hits:
            print(f"self-test: the check refused an allowed include: {p}")
        if missing or allowed_hits:
            print("self-test: found instead:\n  " + "\n  ".join(found))
            return 1
        print(f"self-test: all {len(expected)} breaches reported, the allowed includes accepted")
        return 0


def main(argv):
    if len(argv) == 2 and argv[1] == "--self-test":
        return self_test()
    if len(argv) != 2:
        print(__doc__)
        return 2
    problems = check(argv[1])
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} layout problem(s); the rule is in docs/architecture.md")
        return 1
    print("layout: every include follows docs/architecture.md; folders and sizes within bounds")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
