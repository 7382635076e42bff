"""`keel robust` on one robot's graph with wrong loop closures (app::robust).

Run by CTest (cli.robust) with KEEL set to the binary; from this folder: KEEL=../../build/release/keel
/usr/bin/python3 -m unittest -v test_robust. The graph is written by the test: three laps of a 10 m square (40
poses a lap, exact odometry), true closures i -> i + 40 every other pose with small noise, and wrong closures
between random poses. What must hold: every candidate in the JSON report with its poses, kept or not and why; no
wrong closure kept; the answer certified; the solved graph written only with the odometry and the kept closures; a
broken odometry chain refused (exit 3) naming the pose, and no output written; GNC alone (--gnc only) and data
snooping (--residual-test snooping) reported field by field; bad values of their options refused (exit 2).
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
        self.assertEqual(j["robots"], 1)
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
        self.assertEqual(len(j["groups"]), 1)
        self.assertEqual(j["groups"][0]["clique"]["status"], "optimal")
        self.assertEqual(j["groups"][0]["clique"]["size"], kept_true)
        self.assertEqual(j["files"], [self.graph])
        self.assertTrue(j["certificate"]["certified"])
        # The solved graph: the odometry and exactly the kept closures.
        with open(out) as f:
            edges = [ln.split() for ln in f if ln.startswith("EDGE_SE2")]
        self.assertEqual(len(edges), 3 * LAP - 1 + kept_true)
        kept_pairs = {(c["i"], c["j"]) for c in cands if c["kept"]}
        closures = {(int(e[1]), int(e[2])) for e in edges if abs(int(e[2]) - int(e[1])) != 1}
        self.assertEqual(closures, kept_pairs)

    def test_two_robots_with_global_ids(self):
        """The laps as two robots (poses 0-59 and 60-119) and the edges between them as inter-robot candidates with
        global ids: the same closures are candidates, none wrong kept, the answer certified."""
        half = 3 * LAP // 2
        with open(self.graph) as f:
            lines = f.read().splitlines()
        verts = [ln for ln in lines if ln.startswith("VERTEX_SE2")]
        edges = [ln.split() for ln in lines if ln.startswith("EDGE_SE2")]
        a, b, inter = [], [], []
        for e in edges:
            i, j = int(e[1]), int(e[2])
            if i < half and j < half:
                a.append(" ".join(e))
            elif i >= half and j >= half:
                b.append(" ".join([e[0], str(i - half), str(j - half)] + e[3:]))
            else:
                inter.append(" ".join(e))
        shifted = []
        for v in verts[half:]:
            f = v.split()
            shifted.append(" ".join([f[0], str(int(f[1]) - half)] + f[2:]))
        files = []
        for name, vs, es in (("a.g2o", verts[:half], a), ("b.g2o", shifted, b), ("c.g2o", [], inter)):
            files.append(os.path.join(self.dir.name, name))
            with open(files[-1], "w") as f:
                f.write("\n".join(vs + es) + "\n")
        r = run("robust", files[0], files[1], "--candidates", files[2], "--p", "0.01", "--json", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        j = json.loads(r.stdout)
        self.assertEqual(j["robots"], 2)
        self.assertEqual(j["poses"], 3 * LAP)
        self.assertEqual([(g["robot_a"], g["robot_b"]) for g in j["groups"]], [(0, 0), (1, 1), (0, 1)])
        self.assertEqual(j["candidates"], len(self.truth) + 1)  # the odometry edge between the halves as well
        self.assertTrue(j["certificate"]["certified"])
        by_pair = {}
        for c in j["candidate_list"]:
            gi = c["i"] + (half if c["robot_a"] == 1 else 0)
            gj = c["j"] + (half if c["robot_b"] == 1 else 0)
            by_pair[(gi, gj)] = c["kept"]
        # The wrong closures (random pose pairs, appended last in the single-robot file) are not kept.
        wrong = [(int(e[1]), int(e[2])) for e, t in zip(edges[3 * LAP - 1:], self.truth) if not t]
        for i, j_ in wrong:
            self.assertFalse(by_pair.get((min(i, j_), max(i, j_)), by_pair.get((i, j_), False)))

    def test_broken_chain_is_refused(self):
        with open(self.graph) as f:
            lines = [ln for ln in f if not ln.startswith("EDGE_SE2 7 8 ")]
        with open(self.graph, "w") as f:
            f.writelines(lines)
        out = os.path.join(self.dir.name, "solved.g2o")
        r = run("robust", self.graph, "--out", out, "--quiet")
        self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
        self.assertIn("pose 8 has no odometry edge from pose 7", r.stderr)
        self.assertIn("keel robust: the robot: pose 8", r.stderr)  # the command's name once, not "robust: robust:"
        self.assertFalse(os.path.exists(out))

    def test_bad_option_is_refused(self):
        r = run("robust", self.graph, "--p", "2", "--quiet")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--p", r.stderr)
        for option, value in (("--gnc", "before"), ("--gnc-p", "1"), ("--gnc-inner", "exact"),
                              ("--residual-test", "w")):
            r = run("robust", self.graph, option, value, "--quiet")
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn(option, r.stderr)

    def test_gnc_alone_weighs_out_the_wrong_closures(self):
        """--gnc only: no consistency check; GNC's rounds in the report, its weights settled at 0 or 1, no wrong
        closure kept, the answer certified; the text summary names the rounds and the weighted solves."""
        r = run("robust", self.graph, "--gnc", "only", "--json", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        j = json.loads(r.stdout)
        g = j["gnc"]
        self.assertEqual(g["mode"], "only")
        self.assertEqual(g["inner"], "certified")
        self.assertEqual(g["weighed"], len(self.truth))
        self.assertTrue(g["converged"])
        self.assertGreater(len(g["rounds"]), 0)
        self.assertEqual(j["groups"][0]["clique"]["status"], "not run")
        cands = j["candidate_list"]
        self.assertTrue(all(c["gnc_weight"] in (0.0, 1.0) for c in cands))
        self.assertTrue(all(c["kept"] == (c["gnc_weight"] == 1.0) for c in cands))
        self.assertEqual(sum(c["kept"] and not t for c, t in zip(cands, self.truth)), 0)
        self.assertTrue(j["certificate"]["certified"])
        text = run("robust", self.graph, "--gnc", "only", "--quiet")
        self.assertEqual(text.returncode, 0, text.stderr)
        self.assertIn(f"{len(g['rounds'])} rounds (converged)", text.stdout)
        self.assertIn("weighted solves certified", text.stdout)
        self.assertIn("no consistency check", text.stdout)

    def test_data_snooping_is_reported(self):
        r = run("robust", self.graph, "--p", "0.01", "--residual-test", "snooping", "--json", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        j = json.loads(r.stdout)
        self.assertEqual(j["residual_test"], "snooping")
        kept = sum(c["kept"] or c["removed_in_round"] > 0 for c in j["candidate_list"])
        # The first round's threshold carries the Bonferroni correction over the closures tested.
        self.assertGreater(j["residual_threshold"], 11.3449)
        for c in j["candidate_list"]:
            if c["removed_in_round"] > 0:
                self.assertGreaterEqual(c["snooping_t"], c["residual_chi2"])
            else:
                self.assertIsNone(c["snooping_t"])
        self.assertGreater(kept, 0)

    def test_group_test_is_reported_and_its_window_checked(self):
        r = run("robust", self.graph, "--p", "0.01", "--residual-test", "groups", "--group-window", "3", "--json",
                "--quiet")
        self.assertIn(r.returncode, (0, 1), r.stderr)
        j = json.loads(r.stdout)
        self.assertEqual(j["residual_test"], "groups")
        self.assertEqual(j["group_window"], 3)
        for c in j["candidate_list"]:
            if c["residual_group_t"] is None:
                self.assertEqual((c["residual_group_dof"], c["residual_group_size"]), (0, 0))
            else:  # removed by its group's test: the group's T over 3 dof per closure
                self.assertGreater(c["removed_in_round"], 0)
                self.assertGreaterEqual(c["residual_group_size"], 2)
                self.assertEqual(c["residual_group_dof"], 3 * c["residual_group_size"])
        self.assertEqual(sum(c["kept"] and not t for c, t in zip(j["candidate_list"], self.truth)), 0)
        r = run("robust", self.graph, "--residual-test", "groups", "--group-window", "0")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--group-window", r.stderr)
        self.assertIn("group_window must be >= 1", r.stderr)

    def test_first_solve_is_reported_and_checked(self):
        for value in ("staircase", "rank-d"):
            r = run("robust", self.graph, "--p", "0.01", "--first-solve", value, "--json", "--quiet")
            self.assertIn(r.returncode, (0, 1), r.stderr)
            self.assertEqual(json.loads(r.stdout)["first_solve"], value)
        r = run("robust", self.graph, "--first-solve", "rank-2")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--first-solve must be staircase or rank-d (got 'rank-2')", r.stderr)


class SplitRobots(unittest.TestCase):
    """keel split GRAPH --robots N: the laps cut into robots with wrong closures added, every loop closure listed in
    closures.txt with the file and edge it went to, and keel robust run on the files it wrote."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.graph = os.path.join(self.dir.name, "laps.g2o")
        text, self.truth = square_laps(3, 0, 7)
        with open(self.graph, "w") as f:
            f.write(text)
        self.out = os.path.join(self.dir.name, "robots")

    def tearDown(self):
        self.dir.cleanup()

    def test_files_and_closures_list(self):
        r = run("split", self.graph, "--robots", "3", "--wrong-rate", "0.25", "--seed", "4", "--out-dir", self.out,
                "--json", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        j = json.loads(r.stdout)
        true_closures = len(self.truth)
        self.assertEqual(j["wrong_closures"], round(0.25 / 0.75 * true_closures))
        with open(os.path.join(self.out, "closures.txt")) as f:
            rows = [ln.split() for ln in f if not ln.startswith("#")]
        self.assertEqual(sum(r_[4] == "wrong" for r_ in rows), j["wrong_closures"])
        self.assertEqual(sum(r_[4] == "true" for r_ in rows), true_closures)
        edges = {}
        for name in ("robot0.g2o", "robot1.g2o", "robot2.g2o", "candidates.g2o"):
            with open(os.path.join(self.out, name)) as f:
                edges[name] = [ln.split() for ln in f if ln.startswith("EDGE_SE2")]
        poses = 3 * LAP
        offsets = [0, poses // 3, 2 * poses // 3]
        for i, j_, name, k, _ in rows:
            e = edges[name][int(k)]
            off = 0 if name == "candidates.g2o" else offsets[int(name[5])]
            self.assertEqual((int(e[1]) + off, int(e[2]) + off), (int(i), int(j_)))
        # keel robust reads the files as they are meant: its candidates are exactly the listed loop closures.
        files = [os.path.join(self.out, f"robot{r_}.g2o") for r_ in range(3)]
        r = run("robust", *files, "--candidates", os.path.join(self.out, "candidates.g2o"), "--p", "0.01",
                "--json", "--quiet")
        self.assertIn(r.returncode, (0, 1), r.stderr)
        rj = json.loads(r.stdout)
        self.assertEqual(rj["robots"], 3)
        self.assertEqual(rj["poses"], poses)
        listed = sorted(tuple(sorted((int(i), int(j_)))) for i, j_, _, _, _ in rows)
        seen = sorted(tuple(sorted((c["i"] + offsets[c["robot_a"]], c["j"] + offsets[c["robot_b"]])))
                      for c in rj["candidate_list"])
        self.assertEqual(seen, listed)

    def test_mode_options_and_stale_files_are_refused(self):
        r = run("split", self.graph, "--robots", "2", "--ground-truth", self.graph, "--out-dir", self.out)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--ground-truth", r.stderr)
        r = run("split", self.graph, "--wrong-rate", "0.2", "--out-dir", self.out)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--wrong-rate", r.stderr)
        r = run("split", self.graph, "--robots", "2", "--wrong-rate", "1", "--out-dir", self.out)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--wrong-rate", r.stderr)
        r = run("split", self.graph, "--robots", "2", "--wrong-kind", "odd", "--out-dir", self.out)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--wrong-kind", r.stderr)
        r = run("split", self.graph, "--robots", "4", "--out-dir", self.out, "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        # Two robots now would leave robot2.g2o and robot3.g2o of the four-robot split beside the new files.
        r = run("split", self.graph, "--robots", "2", "--out-dir", self.out, "--quiet")
        self.assertEqual(r.returncode, 4, r.stdout + r.stderr)
        self.assertIn("robot2.g2o", r.stderr)
        r = run("split", self.graph, "--robots", "4", "--wrong-rate", "0.1", "--out-dir", self.out, "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)  # the same set is replaced


if __name__ == "__main__":
    unittest.main()
