"""The one-residual checker on made-up trees: a second definition, an inverse composed with an inverse or a
Ceres quaternion conversion outside graph/residuals must be flagged; the home files, unit tests, comments and
calls must pass (CTest tiers.residuals_checker)."""
import os
import tempfile
import unittest

import check_residuals


def tree(files):
    d = tempfile.mkdtemp(prefix="residuals-")
    for rel, text in files.items():
        path = os.path.join(d, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
    return d


HOME = ("lie::Vec3 edge_residual(const SE2& z, const SE2& T_i, const SE2& T_j) {\n"
        "  const SE2 E = z.inverse() * T_i.inverse() * T_j;\n}\n")


class Residuals(unittest.TestCase):
    def test_home_tests_comments_and_calls_pass(self):
        d = tree({"engine/graph/residuals.cpp": HOME,
                  "engine/cov/information_test.cpp": HOME,
                  "engine/pgo/internal.cpp": "  const auto r = edge_residual(e.measurement, Ti, Tj);\n"
                                             "  // r = ρ(z.inverse() * Ti.inverse() * Tj)\n"
                                             "  anchor = Db * Tj * z.inverse() * Ti.inverse();\n"})
        self.assertEqual(check_residuals.check(d), [])

    def test_a_second_definition_fails(self):
        d = tree({"engine/cov/information.cpp": "EdgeLinearization2 linearize_edge(const SE2& z, const SE2& T_i,\n"
                                                "                                  const SE2& T_j) {\n",
                  "engine/pgo/factors.hpp": "template <class T>\nvoid pose_edge2_residual(const double* z, const T* a) {\n"})
        problems = check_residuals.check(d)
        self.assertEqual(len(problems), 2)
        self.assertTrue(any("cov/information.cpp:1: defines linearize_edge" in p for p in problems))
        self.assertTrue(any("pgo/factors.hpp:2: defines pose_edge2_residual" in p for p in problems))

    def test_an_inverse_times_an_inverse_fails(self):
        d = tree({"engine/study/ch9/x.cpp": "  const SE2 E = z.inverse() * (T[i].inverse() * T[j]);\n"})
        problems = check_residuals.check(d)
        self.assertEqual(len(problems), 1)
        self.assertIn("x.cpp:1: composes z⁻¹ T_i⁻¹ T_j", problems[0])

    def test_a_ceres_quaternion_conversion_fails(self):
        d = tree({"engine/pgo/ceres_factors.hpp": "  ceres::QuaternionToAngleAxis(q, phi);\n"})
        self.assertIn("rotation vector", check_residuals.check(d)[0])


if __name__ == "__main__":
    unittest.main()
