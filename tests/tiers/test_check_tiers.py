#!/usr/bin/env python3
"""Unit tests of check_tiers.py on small trees made up for each rule: every violation class is reported, with its
file and line, and a tree that follows the rules passes."""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_tiers  # noqa: E402

TABLE = {
    "tiers": [
        {"name": "foundation", "areas": [{"name": "core", "depends": [], "test_depends": []}]},
        {"name": "algorithms", "areas": [
            {"name": "lie", "depends": ["core"], "test_depends": []},
            {"name": "pcm", "depends": ["lie", "core"], "test_depends": ["sim"]},
            {"name": "align", "depends": ["core"], "test_depends": []}]},
        {"name": "data", "areas": [{"name": "sim", "depends": ["pcm"], "test_depends": []}]},
        {"name": "reproduction", "areas": [{"name": "repro", "depends": ["core"], "test_depends": []}]},
        {"name": "studies", "areas": [{"name": "study", "depends": ["repro", "sim"], "test_depends": []}]},
        {"name": "faces", "areas": [
            {"name": "app", "depends": ["pcm"], "test_depends": []},
            {"name": "python", "depends": ["app"], "test_depends": []}]},
    ]
}

CLEAN = {
    "engine/core/random.hpp": "#include <random>\n",
    "engine/lie/so3.hpp": '#include "core/random.hpp"\n',
    "engine/pcm/clique.cpp": '#include "lie/so3.hpp"\n#include "core/random.hpp"\n',
    "engine/pcm/clique_test.cpp": '#include "sim/world.hpp"\n#include "kit/test_kit.hpp"\n',
    "engine/sim/world.hpp": '#include "pcm/clique.hpp"\n',
    "engine/study/ch2.cpp": '#include "repro/results.hpp"\n#include "sim/world.hpp"\n#include "lie/so3.hpp"\n',
    "engine/app/app.cppm": "export module keel.app;\nimport keel.pcm;\n",
    "engine/python/module.cpp": '#include "app/solve.hpp"\n',
    "experiments/ch2_x/driver.cpp": "import keel.repro;\nimport keel.study;\n",
    "bench/bench_x.cpp": "import keel.repro;\nimport keel.study;\nimport keel.pcm;\n",
}


class CheckTiers(unittest.TestCase):
    def run_tree(self, extra):
        with tempfile.TemporaryDirectory() as root:
            files = dict(CLEAN)
            files.update(extra)
            for rel, text in files.items():
                path = os.path.join(root, rel)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                with open(path, "w", encoding="utf-8") as f:
                    f.write(text)
            table = os.path.join(root, "tiers.json")
            with open(table, "w", encoding="utf-8") as f:
                json.dump(TABLE, f)
            return check_tiers.check(table, root)

    def assert_one(self, extra, *fragments):
        _, violations = self.run_tree(extra)
        self.assertEqual(len(violations), 1, violations)
        for fragment in fragments:
            self.assertIn(fragment, violations[0])

    def test_clean_tree_passes(self):
        checked, violations = self.run_tree({})
        self.assertEqual(violations, [])
        self.assertEqual(checked, 9)  # engine sources and the driver; bench/ is not checked

    def test_algorithm_importing_reproduction(self):
        self.assert_one({"engine/lie/so3.hpp": '#include "core/random.hpp"\n#include "repro/results.hpp"\n'},
                        "engine/lie/so3.hpp:2", "'repro' (tier reproduction)", "area 'lie' (tier algorithms)")

    def test_algorithm_importing_studies_by_module(self):
        self.assert_one({"engine/pcm/clique.cpp": "import keel.study;\n"}, "engine/pcm/clique.cpp:1", "import of 'study'")

    def test_same_tier_later_area(self):
        self.assert_one({"engine/lie/exp.cpp": '#include "pcm/clique.hpp"\n'}, "'pcm' (tier algorithms)")

    def test_undeclared_lower_area(self):
        self.assert_one({"engine/align/hull.cpp": '#include "lie/so3.hpp"\n'}, "does not declare it",
                        "engine/align/CMakeLists.txt")

    def test_library_may_not_use_data_tier(self):
        self.assert_one({"engine/pcm/graph.cpp": '#include "sim/world.hpp"\n'}, "'sim' (tier data)")

    def test_unit_test_may_use_data_but_not_reproduction(self):
        self.assert_one({"engine/pcm/x_test.cpp": '#include "sim/world.hpp"\n#include "repro/results.hpp"\n'},
                        "engine/pcm/x_test.cpp:2", "'repro'")

    def test_algorithm_reading_toml(self):
        self.assert_one({"engine/align/config.cpp": "#include <toml++/toml.hpp>\n"}, "reads TOML")
        self.assert_one({"engine/align/config.cpp": '#include "core/config.hpp"\n'}, "reads TOML")

    def test_driver_imports_only_repro_and_study(self):
        self.assert_one({"experiments/ch2_x/driver.cpp": "import keel.repro;\nimport keel.study;\nimport keel.pcm;\n"},
                        "experiments/ch2_x/driver.cpp:3", "in a driver")
        self.assert_one({"experiments/ch2_y/driver.cpp": '#include "study/ch2.hpp"\n'}, "#include of 'study'")

    def test_another_areas_detail_is_refused(self):
        self.assert_one({"engine/study/ch2.cpp": '#include "repro/results.hpp"\n#include "sim/world.hpp"\n'
                                                 '#include "lie/so3.hpp"\nauto x = pcm::detail::bits();\n'},
                        "engine/study/ch2.cpp:4", "'pcm::detail::' from area 'study'", "internals")
        # Its own detail, and a library's (pybind11's py::detail), are fine.
        self.assertEqual(self.run_tree({"engine/pcm/clique.cpp": '#include "lie/so3.hpp"\nauto y = pcm::detail::b();\n',
                                        "engine/python/module.cpp": '#include "app/solve.hpp"\npy::detail::c();\n'})[1],
                         [])

    def test_python_uses_no_reproduction(self):
        _, violations = self.run_tree({"engine/python/module.cpp": '#include "repro/results.hpp"\n'})
        self.assertTrue(any("from the Python module" in v for v in violations), violations)


if __name__ == "__main__":
    unittest.main()
