"""`keel robust` on one robot's graph with wrong loop closures (app::robust).

Run by CTest (cli.robust) with KEEL set to the binary; from this folder: KEEL=../../build/release/keel
/usr/bin/python3 -m unittest -v test_robust. The graph is written by the test: three laps of a 10 m square (40
poses a lap, exact odometry), true closures i -> i + 40 every other pose with small noise, and wrong closures
between random poses. What must hold: every candidate in the JSON report with its poses, kept or not and why; no
wrong closure kept; the answer certified; the solved graph written only with the odometry and the kept closures; a
broken odometry chain refused (exit 3) naming the pose, and no output written.
"""
import json
import math
import os
import subprocess
import tempfile
import unittest

import numpy as np

from cli_fixtures import KEEL

LAP = 40


def square_laps(laps, wrong, seed):
    """Poses of `laps` laps of a 10 m square and its g2o edges: odometry, true closures, then `wrong` closures."""
    rng = np.random.default_rng(seed)
    poses = []
    for k in range(LAP * laps):
        s, side = divmod(k % LAP, 10)[1], (k % LAP) // 10
        x, y = [(s, 0), (10, s), (10 - s, 10), (0, 10 - s)][side]
        poses.append((float(x), float(y), side * math.pi / 2))

    def between(a, b, noise):
        (xa, ya, ta), (xb, yb, tb) = a, b
        c, s = math.cos(ta), math.sin(ta)
        dx, dy = xb - xa, yb - ya
        z = [c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(tb - ta), math.cos(tb - ta))]
        return [v + noise * rng.standard_normal() for v in z]

    info = "100 0 0 100 0 10000"
    edges, truth = [], []
    for i in range(len(poses) - 1):
        edges.append((i, i + 1, between(poses[i], poses[i + 1], 0.0)))
    for i in range(0, len(poses) - LAP, 2):
        edges.append((i, i + LAP, between(poses[i], poses[i + LAP], 0.01)))
        truth.append(True)
    for _ in range(wrong):
        i, j = 0, 0
        while abs(i - j) <= 1:
            i, j = rng.integers(0, len(poses), 2)
        edges.append((int(i), int(j), [rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-math.pi, math.pi)]))
        truth.append(False)
    lines = [f"VERTEX_SE2 {k} {x} {y} {t}" for k, (x, y, t) in enumerate(poses)]
    lines += [f"EDGE_SE2 {i} {j} {z[0]:.9f} {z[1]:.9f} {z[2]:.9f} {info}" for i, j, z in edges]
    return "\n".join(lines) + "\n", truth


def run(*args):
    return subprocess.run([KEEL, *args], capture_output=True, text=True)


class RobustCommand(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.graph = os.path.join(self.dir.name, "laps.g2o")
        text, self.truth = square_laps(3, 12, 7)
        with open(self.graph, "w") as f:
            f.write(text)

    def tearDown(self):
        self.dir.cleanup()

    def test_report_keeps_no_wrong_closure_and_certifies(self):
        out = os.path.join(self.dir.name, "solved.g2o")
        report = os.path.join(self.dir.name, "report.json")
        r = run("robust", self.graph, "--p", "0.01", "--out", out, "--report", report, "--json", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        j = json.loads(r.stdout)
        with open(report) as f:
            self.assertEqual(json.load(f), j)
        self.assertEqual(j["poses"], 3 * LAP)
        self.assertEqual(j["odometry_edges"], 3 * LAP - 1)
        cands = j["candidate_list"]
        self.assertEqual(len(cands), len(self.truth))
        kept_true = sum(c["kept"] and t for c, t in zip(cands, self.truth))
        kept_wrong = sum(c["kept"] and not t for c, t in zip(cands, self.truth))
        self.assertEqual(kept_wrong, 0)
        self.assertGreaterEqual(kept_true, 0.8 * sum(self.truth))
        self.assertEqual(j["kept"], kept_true)
        for c in cands:
            if c["kept"]:  # the kept closures are pairwise consistent (a clique)
                self.assertEqual(c["inconsistent_with_kept"], 0)
            else:  # the clique is maximum, so a closure left out conflicts with a kept one
                self.assertGreaterEqual(c["inconsistent_with_kept"], 1)
        self.assertEqual(j["clique"]["status"], "optimal")
        self.assertEqual(j["clique"]["size"], kept_true)
        self.assertTrue(j["certificate"]["certified"])
        # The solved graph: the odometry and exactly the kept closures.
        with open(out) as f:
            edges = [ln.split() for ln in f if ln.startswith("EDGE_SE2")]
        self.assertEqual(len(edges), 3 * LAP - 1 + kept_true)
        kept_pairs = {(c["i"], c["j"]) for c in cands if c["kept"]}
        closures = {(int(e[1]), int(e[2])) for e in edges if abs(int(e[2]) - int(e[1])) != 1}
        self.assertEqual(closures, kept_pairs)

    def test_broken_chain_is_refused(self):
        with open(self.graph) as f:
            lines = [ln for ln in f if not ln.startswith("EDGE_SE2 7 8 ")]
        with open(self.graph, "w") as f:
            f.writelines(lines)
        out = os.path.join(self.dir.name, "solved.g2o")
        r = run("robust", self.graph, "--out", out, "--quiet")
        self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
        self.assertIn("pose 8 has no odometry edge from pose 7", r.stderr)
        self.assertFalse(os.path.exists(out))

    def test_bad_option_is_refused(self):
        r = run("robust", self.graph, "--p", "2", "--quiet")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--p", r.stderr)


if __name__ == "__main__":
    unittest.main()
