#!/usr/bin/env python3
"""Results keys are not joined by hand in a study (docs/DESIGN.md "Results keys"): a key's shape is written once, at
its call, and the part that comes from the data (a data set, a method, a level) is a segment given to
`Results::under` (repro/results.hpp), which refuses dots in it. Every header and source under engine/study/ (tests
aside) is read for three things:
  * a string literal joined to something by `+` at a dot: `n + ".cost"`, `"match_rate." + name`, `a + "." + b`;
  * an fmt::format string whose fields are joined by dots: "{}.{}.median", "offset{}.{}" (file names such as
    "{}.png" aside);
  (a literal with white space in it is a message, not a key part, and is not read for these two);
  * a key argument of .metric( / .series( / .timing( / .note( / .under( / .key( that joins strings with `+`.
A data part may still be formatted into one segment (`fmt::format("pair_fail_{}", tag)`): it adds no level.
Usage: check_results_keys.py REPO; exit 1 and one line per finding (file:line: what)."""
import os
import re

from sources import run, study_sources

LITERAL = r'"(?:[^"\\\n]|\\.)*"'
KEYLIKE = r'(?:[^"\\\s]|\\.)*'  # a literal without white space: a key part, not a message
JOIN_BEFORE = re.compile(r'"' + KEYLIKE + r'\."\s*\+')  # "a." + x
FILE_SUFFIX = r'(?:png|json|csv|g2o|txt|svg|pdf|toml|tsv)'
JOIN_AFTER = re.compile(r'\+\s*"\.(?!' + FILE_SUFFIX + '")' + KEYLIKE + '"')  # x + ".a" (not x + ".png")
FORMAT = re.compile(r'fmt::format\(\s*(' + LITERAL + ')')
DOTTED_FIELD = re.compile(r'\}\.(?!' + FILE_SUFFIX + r'\b)[A-Za-z_{]|[A-Za-z0-9_}]\.\{')
KEY_CALL = re.compile(r'(?:\.(metric|series|timing|note|under|key)|\b(path))\(\s*')


def first_argument(text, start):
    """The first argument of a call whose '(' ends just before `start`."""
    depth, i, in_string = 0, start, False
    while i < len(text):
        c = text[i]
        if in_string:
            if c == "\\":
                i += 2
                continue
            if c == '"':
                in_string = False
        elif c == '"':
            in_string = True
        elif c in "([{":
            depth += 1
        elif c in ")]}":
            if depth == 0:
                return text[start:i]
            depth -= 1
        elif c == "," and depth == 0:
            return text[start:i]
        i += 1
    return text[start:]


def findings(text):
    """(line, message) for each hand-joined key in one file's text."""
    out = []

    def line_of(pos):
        return text.count("\n", 0, pos) + 1

    for m in JOIN_BEFORE.finditer(text):
        out.append((line_of(m.start()), "a key joined with + after a dotted literal; use Results::under"))
    for m in JOIN_AFTER.finditer(text):
        out.append((line_of(m.start()), "a key joined with + before a dotted literal; use Results::under"))
    for m in FORMAT.finditer(text):
        if DOTTED_FIELD.search(m.group(1)) and not re.search(r"\s", m.group(1)):
            out.append((line_of(m.start()), f"fmt::format({m.group(1)}) joins key parts with dots; use "
                                            "Results::under"))
    for m in KEY_CALL.finditer(text):
        arg = " ".join(first_argument(text, m.end()).split())
        if "+" in re.sub(LITERAL, '""', arg):
            out.append((line_of(m.start()), f"{m.group(1) or m.group(2)}({arg}, …): a key joined with + in the call; "
                                            "give each data part to Results::under"))
    return sorted(set(out))


def check(repo):
    problems = []
    for path in study_sources(repo):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        rel = os.path.relpath(path, repo)
        problems += [f"{rel}:{line}: {what}" for line, what in findings(text)]
    return problems

if __name__ == "__main__":
    run(check)
