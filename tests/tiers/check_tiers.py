#!/usr/bin/env python3
"""Checks every #include and import of keel's sources against the tier table (docs/DESIGN.md "Tiers").

Usage: check_tiers.py TIERS_JSON SOURCE_ROOT

TIERS_JSON is build/<preset>/tiers.json, written by CMake from the table in engine/CMakeLists.txt: the tiers in order,
each with its areas in order and every area's declared library and unit-test dependencies. The rules:
  1. A source of engine/<area>/ uses (`#include "<other>/..."` or `import keel.<other>;`) only areas of lower tiers,
     or areas of its own tier listed before it, and only areas its library can link: the transitive closure of its
     declared dependencies.
  2. A unit test (*_test.cpp) may also use the data tier and its declared test dependencies, never reproduction,
     studies or faces unless its own area is there.
  3. The algorithms tier reads no TOML: no `core/config.hpp`, no toml++.
  4. An experiment driver (experiments/*/driver.cpp) imports keel.repro and keel.study only, and includes no engine
     header.
  5. The Python module (engine/python) uses neither the reproduction nor the studies tier.
  6. No area names another area's internals (`<other>::detail::`): what another area uses, its owner declares
     public.
bench/, tests/ and tests' fixtures are free: they may use anything.
Prints one line per violation and exits 1 when there is any, 0 otherwise (with a summary line).
"""
import json
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*"([A-Za-z0-9_]+)/[^"]*"', re.M)
IMPORT = re.compile(r'^\s*(?:export\s+)?import\s+keel\.([A-Za-z0-9_]+)\s*;', re.M)
DETAIL = re.compile(r"\b(\w+)::detail::")
TOML = re.compile(r'^\s*#\s*include\s*[<"](?:toml\+\+/[^>"]*|core/config\.hpp)[>"]', re.M)
SOURCE_SUFFIXES = (".hpp", ".cpp", ".cppm", ".h")


def load_table(path):
    with open(path, encoding="utf-8") as f:
        table = json.load(f)
    areas = {}
    position = 0
    for index, tier in enumerate(table["tiers"]):
        for area in tier["areas"]:
            areas[area["name"]] = {
                "tier": tier["name"],
                "index": index,
                "position": position,
                "depends": list(area.get("depends", [])),
                "test_depends": list(area.get("test_depends", [])),
            }
            position += 1
    return [t["name"] for t in table["tiers"]], areas


def closure(areas, start):
    seen = set()
    stack = list(areas[start]["depends"])
    while stack:
        a = stack.pop()
        if a in seen or a not in areas:
            continue
        seen.add(a)
        stack.extend(areas[a]["depends"])
    return seen


def uses(text, known):
    """(line number, used area, how) for every include or import of a keel area in text."""
    out = []
    for rx, how in ((INCLUDE, "#include"), (IMPORT, "import")):
        for m in rx.finditer(text):
            name = m.group(1)
            if name in known:
                out.append((text.count("\n", 0, m.start()) + 1, name, how))
    return out


def source_files(folder):
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames.sort()
        for name in sorted(filenames):
            if name.endswith(SOURCE_SUFFIXES):
                yield os.path.join(dirpath, name)


def check(table_path, root):
    tiers, areas = load_table(table_path)
    data_index = tiers.index("data") if "data" in tiers else -1
    violations = []
    checked = 0

    def report(path, line, msg):
        violations.append(f"{os.path.relpath(path, root)}:{line}: {msg}")

    engine = os.path.join(root, "engine")
    for area in sorted(areas):
        folder = os.path.join(engine, area)
        if not os.path.isdir(folder):
            continue
        me = areas[area]
        linkable = closure(areas, area)
        test_linkable = set(linkable)
        for t in me["test_depends"]:
            test_linkable.add(t)
            test_linkable |= closure(areas, t) if t in areas else set()
        for path in source_files(folder):
            checked += 1
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
            is_test = path.endswith("_test.cpp")
            for line, used, how in uses(text, areas):
                if used == area:
                    continue
                u = areas[used]
                lower = u["index"] < me["index"] or (u["index"] == me["index"] and u["position"] < me["position"])
                test_ok = is_test and u["index"] <= data_index
                if not lower and not test_ok:
                    report(path, line, f"{how} of '{used}' (tier {u['tier']}) from area '{area}' (tier {me['tier']}): "
                                       f"a tier uses only the tiers below it")
                elif used not in (test_linkable if is_test else linkable):
                    report(path, line, f"{how} of '{used}' from area '{area}', which does not declare it "
                                       f"(add it to DEPENDS{' or TEST_DEPENDS' if is_test else ''} in "
                                       f"engine/{area}/CMakeLists.txt)")
                if area == "python" and u["tier"] in ("reproduction", "studies"):
                    report(path, line, f"{how} of '{used}' from the Python module: it calls app and the algorithm "
                                       f"facades only")
            # An area's `detail` namespace is its own: another area uses what the owner declares public.
            for m in DETAIL.finditer(text):
                if m.group(1) in areas and m.group(1) != area:
                    report(path, text.count("\n", 0, m.start()) + 1,
                           f"'{m.group(0)}' from area '{area}': another area's internals (detail); use what "
                           f"'{m.group(1)}' declares public")
            if me["tier"] == "algorithms":
                for m in TOML.finditer(text):
                    report(path, text.count("\n", 0, m.start()) + 1,
                           f"area '{area}' (tier algorithms) reads TOML: options come from the caller")

    experiments = os.path.join(root, "experiments")
    if os.path.isdir(experiments):
        for name in sorted(os.listdir(experiments)):
            path = os.path.join(experiments, name, "driver.cpp")
            if not os.path.isfile(path):
                continue
            checked += 1
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
            for line, used, how in uses(text, areas):
                if how == "#include" or used not in ("repro", "study"):
                    report(path, line, f"{how} of '{used}' in a driver: a driver reads its toml and calls one "
                                       f"study (import keel.repro; import keel.study; only)")
    return checked, violations


def main(argv):
    if len(argv) != 3:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    checked, violations = check(argv[1], argv[2])
    for v in violations:
        print(v)
    if violations:
        print(f"check_tiers: {len(violations)} violation(s) in {checked} files", file=sys.stderr)
        return 1
    print(f"check_tiers: {checked} files follow the tiers")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
