#!/usr/bin/env python3
"""One study per file (docs/DESIGN.md "Studies"): every header and source under engine/study/ holds at most one
study. A study is a struct with the study shape of repro/run.hpp, found by its `record(repro::Results&` member in
a header and by its `X::record(` definition in a source. Usage: check_study_files.py REPO; exit 1 and one line per
file that holds more than one, naming them."""
import os
import re

from sources import run, study_sources

STRUCT = re.compile(r"^struct (\w+) \{")
RECORD_DECL = re.compile(r"^\s+static void record\(repro::Results&")
RECORD_DEF = re.compile(r"^void (\w+)::record\((?:repro::)?Results& \w+, const Outcome&")


def studies_in(path):
    names = []
    current = None
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = STRUCT.match(line)
            if m:
                current = m.group(1)
            if path.endswith(".hpp") and current and RECORD_DECL.match(line) and current not in names:
                names.append(current)
            m = RECORD_DEF.match(line)
            if m and m.group(1) not in names:
                names.append(m.group(1))
    return names


def check(repo):
    problems = []
    for path in study_sources(repo):
        found = studies_in(path)
        if len(found) > 1:
            problems.append(f"{os.path.relpath(path, repo)}: {len(found)} studies ({', '.join(found)}); "
                            "one study per file, named after its type")
    return problems

if __name__ == "__main__":
    run(check)
