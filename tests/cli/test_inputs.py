"""Inputs the `keel` command refuses, and the inputs it must not refuse: ids, ranges and numbers through one parser
(engine/core/parse.hpp), survey CSV's header rule, files read once (pipes work), directories named, g2o's FIX
(the gauge pose every solve holds),
and graphs whose cost double precision cannot evaluate (check refuses what solve cannot use).

Run by CTest (cli.inputs) with KEEL set to the binary; from this folder: KEEL=../../build/release/keel
/usr/bin/python3 -m unittest -v test_inputs. Every case writes its small files into a scratch folder.
Exit codes: 0 done, 2 bad command line, 3 bad input (docs/USING.md's table).
"""
import json
import math
import os
import shutil
import subprocess
import tempfile
import threading
import unittest

from cli_fixtures import KEEL, SQUARE

INFO = " 1 0 0 1 0 1\n"
# Three poses in a triangle (3 poses: valid ids 0 … 2).
TRIANGLE = ("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
            "EDGE_SE2 0 1 1 0 0" + INFO + "EDGE_SE2 1 2 1 0 0" + INFO + "EDGE_SE2 0 2 2 0 0" + INFO)
WORK = None


def setUpModule():
    global WORK
    WORK = tempfile.mkdtemp(prefix="keel-inputs-")


def tearDownModule():
    shutil.rmtree(WORK, ignore_errors=True)


def write(name, text, mode="w"):
    path = os.path.join(WORK, name)
    with open(path, mode) as f:
        f.write(text)
    return path


def keel(*args, expect=0, stdin=None):
    """Runs keel in the scratch folder; checks the exit code; returns (stdout, stderr)."""
    p = subprocess.run([KEEL, *args], cwd=WORK, capture_output=True, text=True, timeout=300, input=stdin)
    if p.returncode != expect:
        raise AssertionError(f"keel {' '.join(args)}: exit {p.returncode}, expected {expect}\n"
                             f"stdout:\n{p.stdout}\nstderr:\n{p.stderr}")
    return p.stdout, p.stderr


class Ids(unittest.TestCase):
    """`--pairs` and `--poses` ids beyond int wrapped through sscanf %d (4294967297 became 1) and a range was
    expanded before it was checked (bad_alloc): now one parser, against the graph's pose count."""

    def refused(self, text, *args):
        _, err = keel(*args, expect=3)
        self.assertIn(text, err)

    def test_pairs_and_poses_beyond_int_are_refused(self):
        g = write("tri.g2o", TRIANGLE)
        expected = "expected a pose id of the graph (3 poses) in 0 … 2"
        self.refused(f"--pairs: pair '4294967297:1': '4294967297' is too large: {expected}",
                     "marginals", g, "--pairs", "4294967297:1")
        self.refused(f"--poses: '4294967296' is too large: {expected}", "marginals", g, "--poses", "4294967296")
        self.refused(f"--pairs: pair '99999999999:1': '99999999999' is too large: {expected}",
                     "marginals", g, "--pairs", "99999999999:1")
        self.refused(f"--poses: range '0-2147483647': '2147483647' is too large: {expected}",
                     "marginals", g, "--poses", "0-2147483647")
        self.refused("--poses: range '2-1': the end 1 is below the start 2", "marginals", g, "--poses", "2-1")
        self.refused("--pairs: pair '0:1x': '1x' is not a pose id", "marginals", g, "--pairs", "0:1x")
        self.refused("--poses: '-1' is negative", "marginals", g, "--poses", "-1")

    def test_pairs_file_through_the_same_parser(self):
        g = write("tri.g2o", TRIANGLE)
        pairs = write("pairs.txt", "# i j\n0 1\n4294967297 1\n")
        self.refused(f"{pairs}:3: field 1: '4294967297' is too large", "marginals", g, "--pairs", pairs)
        pairs = write("pairs3.txt", "0 1 2\n")
        self.refused(f"{pairs}:1: expected two pose ids 'i j', got 3 fields", "marginals", g, "--pairs", pairs)

    def test_valid_ids_still_work(self):
        g = write("tri.g2o", TRIANGLE)
        out, _ = keel("marginals", g, "--poses", "0-2", "--json", "-q")
        self.assertEqual(json.loads(out)["poses"], [0, 1, 2])
        pairs = write("ok_pairs.txt", "0 1\n1\t2\r\n")
        out, _ = keel("marginals", g, "--pairs", pairs, "--json", "-q")
        self.assertEqual([(p["i"], p["j"]) for p in json.loads(out)["pairs"]], [(0, 1), (1, 2)])


class Surveys(unittest.TestCase):
    """A headerless survey whose first row starts with `nan,`, a BOM or a typo (`1O,`) lost that row as a
    header; 1e-310 was refused as "not a finite number"."""

    REF = "x,y,f\n0,0,1\n10,0,2\n0,10,3\n10,10,4\n"

    def align(self, query_text, expect=0, mode="w"):
        ref = write("ref.csv", self.REF)
        query = write("query.csv", query_text, mode)
        out, err = keel("align", ref, query, "--json", "-q", expect=expect)
        return (json.loads(out) if expect == 0 else None), err, query

    def test_a_bad_first_row_is_a_located_error_not_a_header(self):
        _, err, q = self.align("nan,1,1\n2,2,2\n3,3,3\n", expect=3)
        self.assertIn(f"{q}:1: column 1: 'nan' is not a finite number", err)
        _, err, q = self.align("1O,1,1\n2,2,2\n3,3,3\n", expect=3)
        self.assertIn(f"{q}:1: column 1: '1O' is not a number", err)

    def test_a_bom_is_dropped_and_the_row_kept(self):
        r, _, _ = self.align(b"\xef\xbb\xbf1,1,1\n2,2,2\n3,3,3\n", mode="wb")
        self.assertEqual(r["query_points"], 3)
        r, _, _ = self.align(b"\xef\xbb\xbfx,y,f\n2,2,2\n3,3,3\n", mode="wb")
        self.assertEqual(r["query_points"], 2)

    def test_a_subnormal_is_a_number(self):
        r, _, _ = self.align("1,1,1e-310\n2,2,2\n3,3,3\n")
        self.assertEqual(r["query_points"], 3)

    def test_a_directory_is_named(self):
        ref = write("ref.csv", self.REF)
        _, err = keel("align", ref, WORK, expect=3)
        self.assertIn(f"{WORK}: the survey file: cannot read: is a directory, not a file", err)


class Files(unittest.TestCase):
    def test_a_pipe_is_read_once(self):
        out, _ = keel("check", "/dev/stdin", "--json", "-q", stdin=TRIANGLE)
        self.assertEqual(json.loads(out)["poses"], 3)
        out, _ = keel("solve", "/dev/stdin", "--json", "-q", stdin=TRIANGLE)
        self.assertEqual(json.loads(out)["poses"], 3)

    def test_solve_from_a_pipe_writes_in_the_inputs_format(self):
        # --out without an extension takes the input's format, found in the one reading of the input.
        isam = "EDGE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE2 1 2 1 0 0 1 0 0 1 0 1\nEDGE2 0 2 2 0 0 1 0 0 1 0 1\n"
        for text, first in ((TRIANGLE, "VERTEX_SE2"), (isam, "EDGE2")):
            out = os.path.join(WORK, "solution")
            keel("solve", "/dev/stdin", "--out", out, "-q", stdin=text)
            with open(out) as f:
                self.assertEqual(f.read().split()[0], first)
            os.remove(out)

    def test_pcm_reads_robot_a_once(self):
        b = write("b.g2o", TRIANGLE)
        cand = write("cand.g2o", "EDGE_SE2 2 0 1 0 0" + INFO + "EDGE_SE2 1 1 2 0 0" + INFO)
        out, _ = keel("pcm", "--a", "/dev/stdin", "--b", b, "--candidates", cand, "--json", "-q", stdin=TRIANGLE)
        self.assertEqual(json.loads(out)["candidates"], 2)

    def test_a_fifo_works(self):
        fifo = os.path.join(WORK, "g.fifo")
        os.mkfifo(fifo)
        def feed():
            with open(fifo, "w") as f:
                f.write(TRIANGLE)

        writer = threading.Thread(target=feed)
        writer.start()
        out, _ = keel("check", fifo, "--json", "-q")
        writer.join()
        self.assertEqual(json.loads(out)["edges"], 3)
        os.remove(fifo)

    def test_a_directory_or_missing_file_is_bad_input_with_a_reason(self):
        for command in ("check", "solve", "marginals"):
            extra = ["--poses", "0"] if command == "marginals" else []
            _, err = keel(command, WORK, *extra, expect=3)
            self.assertIn(f"{WORK}: cannot read: is a directory, not a file", err)
            self.assertNotIn("basic_filebuf", err)
        _, err = keel("check", os.path.join(WORK, "missing.g2o"), expect=3)
        self.assertIn("missing.g2o: cannot open file (No such file or directory)", err)

    def test_g2o_fix_names_the_gauge_pose(self):
        g = write("fix.g2o", "FIX 0\n" + TRIANGLE)
        out, _ = keel("solve", g, "--json", "-q")
        self.assertEqual(json.loads(out)["poses"], 3)
        g = write("fix3.g2o", TRIANGLE + "FIX 3\n")
        _, err = keel("check", g, expect=3)
        self.assertIn(f"{g}:7: FIX field 1: '3': no pose 3 in the graph (its 3 poses have ids 0 to 2)", err)
        g = write("fix12.g2o", "FIX 1\n" + TRIANGLE + "FIX 2\n")
        _, err = keel("solve", g, expect=3)
        self.assertIn(f"{g}:8: FIX field 1: '2': keel holds one pose fixed (the gauge), and FIX field 1 on line 1 "
                      "already fixes pose 1; this one names pose 2", err)


def vertices(path):
    """{id: (x, y, theta)} of a 2D g2o file's VERTEX_SE2 lines."""
    out = {}
    with open(path) as f:
        for line in f:
            t = line.split()
            if t and t[0] == "VERTEX_SE2":
                out[int(t[1])] = tuple(float(v) for v in t[2:5])
    return out


class Fix(unittest.TestCase):
    """g2o's `FIX k` was refused for k != 0; now every solve holds pose k at its value in the file, and marginals
    are reported with pose k fixed."""

    def setUp(self):
        self.g = write("square_fix2.g2o", SQUARE + "FIX 2\n")
        self.given = vertices(self.g)

    def same_pose(self, got, want):
        self.assertEqual(got[:2], want[:2])  # x, y to the last bit
        self.assertAlmostEqual(math.remainder(got[2] - want[2], 2 * math.pi), 0.0, delta=1e-12)

    def test_solve_holds_pose_2(self):
        for extra in ([], ["--init", "as-read"], ["--certify"]):
            with self.subTest(extra=extra):
                out = os.path.join(WORK, "solved.g2o")
                keel("solve", self.g, "--out", out, "-q", *extra)
                got = vertices(out)
                self.same_pose(got[2], self.given[2])
                self.assertGreater(abs(got[0][0]) + abs(got[0][1]) + abs(got[0][2]), 1e-6)  # pose 0 moved
                with open(out) as f:
                    self.assertIn("FIX 2\n", f.read().splitlines(keepends=True))
                os.remove(out)

    def test_costs_do_not_depend_on_the_gauge(self):
        g0 = write("square_fix0.g2o", SQUARE)
        a = json.loads(keel("solve", g0, "--json", "-q")[0])["summary"]
        b = json.loads(keel("solve", self.g, "--json", "-q")[0])["summary"]
        # The same optimum up to the stopping rule (|cost change| / cost <= 1e-6 per step) of both runs.
        self.assertAlmostEqual(b["final_cost"] / a["final_cost"], 1.0, delta=1e-6)
        a = json.loads(keel("solve", g0, "--json", "-q", "--certify")[0])["certificate"]
        b = json.loads(keel("solve", self.g, "--json", "-q", "--certify")[0])["certificate"]
        self.assertTrue(b["certified"])
        for key in ("final_cost", "lower_bound", "upper_bound"):
            self.assertEqual(b[key], a[key], key)  # the certificate does not depend on the gauge

    def test_marginals_in_the_gauge_at_pose_2(self):
        out = os.path.join(WORK, "m.json")
        keel("marginals", self.g, "--poses", "2,5", "--out", out, "-q")
        with open(out) as f:
            m = json.load(f)
        self.assertEqual(m["gauge"], "pose 2 fixed")
        cov = m["covariance"]
        self.assertTrue(all(cov[r][c] == 0.0 for r in range(3) for c in range(6)))
        self.assertGreater(cov[3][3], 0.0)


class Range(unittest.TestCase):
    """An information or measurement of 1e308 passed check; solve failed or printed "final_cost": null / 5e170.
    Now both refuse λ_max(Ω)·(ε·M)² > 1 before anything is solved."""

    def test_huge_measurements_on_a_tree_are_refused_by_check_and_solve(self):
        for z in ("1e100", "1e200", "1e300"):
            g = write("tree.g2o", f"EDGE_SE2 0 1 {z} 0 0{INFO}EDGE_SE2 1 2 1 0 0{INFO}")
            for args in (["check", g], ["solve", g], ["solve", "--certify", g], ["marginals", g, "--poses", "1"]):
                out, err = keel(*args, "--json", "-q", expect=3)
                self.assertIn(f"{g}:1: EDGE_SE2: information of largest eigenvalue 1 at coordinates up to M = ", err)
                self.assertIn("keel refuses λ_max(Ω)·(ε·M)² > 1", err)
                self.assertNotIn("null", out)

    def test_huge_information_is_refused_by_check_and_solve(self):
        g = write("w.g2o", "EDGE_SE2 0 1 1 0 0 1e308 0 0 1 0 1\nEDGE_SE2 1 2 1 0 0" + INFO +
                  "EDGE_SE2 0 2 2 0 0" + INFO)
        for args in (["check", g], ["solve", g], ["solve", "--certify", g]):
            _, err = keel(*args, expect=3)
            self.assertIn(f"{g}:1: EDGE_SE2: information of largest eigenvalue 1e+308", err)

    def test_sigma_comes_from_a_factorization(self):
        g = write("tiny.g2o", "EDGE_SE2 0 1 1 0 0 1e-110 0 0 1e-110 0 1e-110\n")
        out, _ = keel("check", g, "--json", "-q")
        s = json.loads(out)
        for key in ("sigma_translation", "sigma_rotation"):
            for v in s[key]:
                self.assertTrue(math.isclose(v, 1e55, rel_tol=1e-12), (key, v))


class OptionValues(unittest.TestCase):
    """An option value keel refuses is a bad command line (exit 2) naming the option, refused before any input
    is read: every case below names a file that does not exist (reading it would be exit 3). Numbers go through
    the one parser (overflow, a negative unsigned, trailing junk, inf and nan refused), the rest through the
    engine's own checks (validate(), from_string)."""

    SOLVE = ("solve", "missing.g2o")
    PCM = ("pcm", "--a", "missing.g2o", "--b", "missing.g2o", "--candidates", "missing.g2o")
    ALIGN = ("align", "missing.csv", "missing.csv")

    def usage(self, args, *texts):
        _, err = keel(*args, expect=2)
        for text in texts:
            self.assertIn(text, err, args)
        self.assertNotIn("missing", err, args)

    def test_solve_options(self):
        self.usage(self.SOLVE + ("--max-iterations", "-1"), "--max-iterations:", "max_iterations must be >= 0")
        self.usage(self.SOLVE + ("--init", "bogus"), "--init:", "unknown pgo::InitialGuess 'bogus'")
        self.usage(self.SOLVE + ("--robust", "bogus"), "--robust:", "unknown pgo::RobustKernel 'bogus'")
        self.usage(self.SOLVE + ("--robust", "huber", "--robust-param", "nan"), "--robust-param:",
                   "'nan' is not a finite number")
        self.usage(self.SOLVE + ("--robust-param", "-1"), "--robust-param:", "robust_parameter must be finite and > 0")
        self.usage(self.SOLVE + ("--certify", "--gap-tolerance", "-1"), "--gap-tolerance:",
                   "gap_tolerance must be in (0, 1)")
        self.usage(self.SOLVE + ("--certify", "--max-rank", "0"), "--max-rank:", "max_rank must be >= 2")
        for s in ("-0.001", "1", "nan"):
            self.usage(self.SOLVE + ("--certify", "--staircase-stationarity", s), "--staircase-stationarity:")
            self.usage(self.SOLVE + ("--certify", "--staircase-relative-decrease", s),
                       "--staircase-relative-decrease:",
                       "not a finite number" if s == "nan" else "staircase_relative_decrease must be in [0, 1)")
        self.usage(self.SOLVE + ("--certify", "--preconditioner", "schur"), "--preconditioner:",
                   "unknown pgo::TrustRegionPreconditioner 'schur'")
        # An option of the other mode is refused, never ignored.
        for option, value in (("--init", "as-read"), ("--seed", "3"), ("--robust", "huber"), ("--robust-param", "2"),
                              ("--threads", "2"), ("--max-iterations", "5")):
            self.usage(self.SOLVE + ("--certify", option, value), f"{option}: does not apply with --certify")
        for option, value in (("--gap-tolerance", "1e-5"), ("--max-rank", "4"), ("--time-limit", "10"),
                              ("--staircase-stationarity", "0"), ("--staircase-relative-decrease", "0"),
                              ("--preconditioner", "joint")):
            self.usage(self.SOLVE + (option, value), f"{option}: applies only with --certify")
        for t in ("0", "-1", "nan"):
            self.usage(self.SOLVE + ("--certify", "--time-limit", t), "--time-limit:")
        self.usage(("marginals", "missing.g2o", "--poses", "1", "--robust", "bogus"), "--robust:")

    def test_pcm_options(self):
        for p in ("0", "1.5", "nan"):
            self.usage(self.PCM + ("--p", p), "--p:")
        self.usage(self.PCM + ("--algorithm", "bogus"), "--algorithm:", "bogus")
        self.usage(self.PCM + ("--composition", "bogus"), "--composition:", "bogus")
        for t in ("-1", "0", "nan"):
            self.usage(self.PCM + ("--time-limit", t), "--time-limit:")

    def test_align_options(self):
        self.usage(self.ALIGN + ("--method", "bogus"), "--method:", "unknown align::Method 'bogus'")
        self.usage(self.ALIGN + ("--shrink", "1.5"), "--shrink:", "must be in (0, 1)")
        self.usage(self.ALIGN + ("--rounds", "-1"), "--rounds:", "must be >= 0")
        self.usage(self.ALIGN + ("--dissimilarity", "bogus"), "--dissimilarity:")
        for scale in ("0", "-1", "inf", "nan"):
            self.usage(("align-world", "w", "--terrain", "missing.grid", "--scale", scale), "--scale:")
            self.assertFalse(os.path.exists(os.path.join(WORK, "w")))
        self.usage(("align-world", "w", "--bumps", "0"), "--bumps:")

    def test_split_options(self):
        split = ("split", "missing.g2o", "--ground-truth", "missing.txt", "--out-dir", "s")
        self.usage(split + ("--inliers", "-1"), "--inliers:", "num_inliers must be >= 0")
        self.usage(split + ("--random-outliers", "-2"), "--random-outliers:")
        self.usage(split + ("--aliased-groups", "1", "--aliased-size", "0"), "--aliased-groups/--aliased-size:")
        self.usage(split + ("--first", "5", "--split", "6"), "--first/--split/--last:", "at least 2 poses")
        self.assertFalse(os.path.exists(os.path.join(WORK, "s")))

    def test_integers_through_the_one_parser(self):
        # Overflow of 64 bits was accepted (a seed of 10^23 ran), -1 of an unsigned wrapped to 2^64 - 1.
        self.usage(self.SOLVE + ("--init", "random", "--seed", "99999999999999999999999"), "--seed:", "too large")
        self.usage(("align-world", "w", "--index", "-1"), "--index:", "is negative")
        self.usage(("align-world", "w", "--seed", "18446744073709551616"), "--seed:", "too large")
        self.usage(self.SOLVE + ("--threads", "-1"), "--threads:")
        self.usage(self.SOLVE + ("--threads", "1x"), "--threads:")
        self.usage(self.SOLVE + ("--max-iterations", "1e3"), "--max-iterations:")
        self.usage(("split", "missing.g2o", "--ground-truth", "missing.txt", "--out-dir", "s", "--seed", "-1"),
                   "--seed:")
        self.usage(self.PCM + ("--threads", "4294967296"), "--threads")
        self.assertFalse(os.path.exists(os.path.join(WORK, "w")))
        # The whole unsigned 64-bit range is a seed.
        write("t.g2o", TRIANGLE)
        keel("solve", "t.g2o", "-q", "--init", "random", "--seed", "18446744073709551615")

    def test_robust_parameters_keel_can_represent(self):
        # A Cauchy a of 1e-300 squared to 0 and Ceres aborted (rho'(s) = 0); the range is stated, its ends run.
        write("t.g2o", TRIANGLE)
        for kernel in ("huber", "cauchy", "dcs"):
            for a in ("1e-300", "5e-324", "1e300", "1e-151"):
                self.usage(("solve", "t.g2o", "--robust", kernel, "--robust-param", a), "--robust-param:",
                           "robust_parameter must be in [1e-150, 1e+150]")
            for a in ("1e-150", "1e150"):
                p = subprocess.run([KEEL, "solve", "t.g2o", "-q", "--init", "random", "--robust", kernel,
                                    "--robust-param", a], cwd=WORK, capture_output=True, text=True, timeout=300)
                self.assertIn(p.returncode, (0, 1), (kernel, a, p.stderr))
                self.assertNotIn("Check failed", p.stderr)
        # A far outlier (χ² 1e10) under Cauchy a = 1e-150: s/a² is beyond the largest double; the cost stays finite
        # (it was inf with exit 0) and the weight positive.
        write("far.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\nEDGE_SE2 0 1 1 0 0" + INFO +
              "EDGE_SE2 1 2 1 0 0" + INFO + "EDGE_SE2 0 2 100000 0 0" + INFO)
        for kernel in ("huber", "cauchy", "dcs"):
            out, _ = keel("solve", "far.g2o", "-q", "--json", "--robust", kernel, "--robust-param", "1e-150")
            summary = json.loads(out)["summary"]
            for key in ("initial_cost", "final_cost"):
                self.assertIsNotNone(summary[key], (kernel, key))
                self.assertTrue(math.isfinite(summary[key]) and summary[key] > 0, (kernel, key, summary[key]))


if __name__ == "__main__":
    unittest.main()
