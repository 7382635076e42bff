"""The results-key checker on made-up sources: it must flag each way of joining a key by hand and pass keys written
with Results::under and literal fields (CTest tiers.results_keys_checker)."""
import os
import tempfile
import unittest

import check_results_keys


def problems_in(source, name="ch9/a.cpp"):
    d = tempfile.mkdtemp(prefix="results-keys-")
    path = os.path.join(d, "engine", "study", name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(source)
    return check_results_keys.check(d)


class ResultsKeys(unittest.TestCase):
    def test_keys_through_under_pass(self):
        self.assertEqual(problems_in(
            'void A::record(Results& r, const Outcome& o) {\n'
            '  const auto m = r.under(o.name);\n'
            '  m.metric("rot_se.median", 1);\n'
            '  r.under(fmt::format("pair_fail_{}", tag)).series(kColumn[c], v);\n'
            '  names.push_back(repro::path("time").under(curve.name).key(fmt::format("m{:04d}", k)));\n'
            '  f.file = o.figure + ".png";\n'
            '  r.check(fmt::format("{}: the bound holds.", n), ok, fmt::format("gap {:.3g}. Done", g));\n'
            '}\n'), [])

    def test_plus_before_a_dotted_literal_fails(self):
        p = problems_in('void f(Results& r) {\n  r.metric(n + ".cost", 1);\n}\n')
        self.assertTrue(any("ch9/a.cpp:2:" in x and "before a dotted literal" in x for x in p), p)

    def test_plus_after_a_dotted_literal_fails(self):
        p = problems_in('void f(Results& r) {\n  const std::string k = "match_rate." + name;\n}\n')
        self.assertIn("after a dotted literal", p[0])

    def test_dotted_format_fails(self):
        p = problems_in('void f(Results& r) {\n  r.series(fmt::format("{}.{}.median", a, b), v);\n}\n')
        self.assertTrue(any("joins key parts with dots" in x for x in p), p)

    def test_plus_inside_a_key_call_fails(self):
        p = problems_in('void f(Results& r) {\n  r.under(a + b).metric("x", 1);\n}\n')
        self.assertTrue(any("under(a + b" in x for x in p), p)

    def test_tests_are_not_read(self):
        self.assertEqual(problems_in('void f(Results& r) { r.metric(n + ".cost", 1); }\n', "ch9/a_test.cpp"), [])


if __name__ == "__main__":
    unittest.main()
