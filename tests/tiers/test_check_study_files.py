"""The one-study-per-file checker on made-up trees: it must flag a header or a source with two studies and pass
one study per file (CTest tiers.study_files_checker)."""
import os
import tempfile
import unittest

import check_study_files

STUDY = """struct {name} {{
  struct Options {{ static Options read(const core::ConfigTable& p); }};
  static void record(repro::Results& results, const Outcome& outcome);
}};
"""


def tree(files):
    d = tempfile.mkdtemp(prefix="study-files-")
    for rel, text in files.items():
        path = os.path.join(d, "engine", "study", rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
    return d


class StudyFiles(unittest.TestCase):
    def test_one_study_per_file_passes(self):
        d = tree({"ch9/a.hpp": STUDY.format(name="A"), "ch9/a.cpp": "void A::record(Results& r, const Outcome& o) {}\n",
                  "ch9/b.hpp": STUDY.format(name="B")})
        self.assertEqual(check_study_files.check(d), [])

    def test_two_studies_in_a_header_fail(self):
        d = tree({"ch9/ab.hpp": STUDY.format(name="A") + STUDY.format(name="B")})
        problems = check_study_files.check(d)
        self.assertEqual(len(problems), 1)
        self.assertIn("ch9/ab.hpp: 2 studies (A, B)", problems[0])

    def test_two_studies_in_a_source_fail(self):
        d = tree({"ch9/ab.cpp": "void A::record(Results& r, const Outcome& o) {}\n"
                                "void B::record(repro::Results& r, const Outcome& out) {}\n"})
        self.assertIn("ch9/ab.cpp: 2 studies (A, B)", check_study_files.check(d)[0])

    def test_a_helper_struct_is_not_a_study(self):
        d = tree({"ch9/a.hpp": "struct Tally {\n  void record(repro::Results& r, int n) const;\n};\n" +
                               STUDY.format(name="A"),
                  "ch9/a.cpp": "void Tally::record(repro::Results& r, int n) const {}\n"
                               "void A::record(repro::Results& r, const Outcome& o) {}\n"})
        self.assertEqual(check_study_files.check(d), [])


if __name__ == "__main__":
    unittest.main()
