"""The headers and sources of engine/study/ (unit tests aside) in a stable order: what the study checkers read
(check_study_files.py, check_results_keys.py)."""
import os


def study_sources(repo):
    root = os.path.join(repo, "engine", "study")
    for dirpath, _, files in sorted(os.walk(root)):
        for name in sorted(files):
            if name.endswith((".hpp", ".cpp")) and not name.endswith("_test.cpp"):
                yield os.path.join(dirpath, name)
