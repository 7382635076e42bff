"""What the source checkers share: the engine's sources (unit tests aside) in a stable order, and the command-line
runner (check_study_files.py, check_results_keys.py, check_residuals.py)."""
import os
import sys


def engine_sources(repo, area=None, suffixes=(".hpp", ".cpp", ".cppm")):
    """engine/ (or engine/<area>/) files ending in one of `suffixes`, unit tests aside, sorted by folder and name."""
    root = os.path.join(repo, "engine", *([area] if area else []))
    for dirpath, _, files in sorted(os.walk(root)):
        for name in sorted(files):
            if name.endswith(suffixes) and not name.endswith("_test.cpp"):
                yield os.path.join(dirpath, name)


def study_sources(repo):
    """The headers and sources of engine/study/: what the study checkers read."""
    return engine_sources(repo, "study", (".hpp", ".cpp"))


def run(check):
    """Usage: CHECKER [REPO]. Prints one line per problem that check(REPO) returns; exit 1 if there is any."""
    problems = check(sys.argv[1] if len(sys.argv) > 1 else ".")
    for p in problems:
        print(p)
    sys.exit(1 if problems else 0)
