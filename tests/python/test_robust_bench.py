"""bench/side_by_side's robust inputs: keel_robust_graphs' multi-robot files are the single-robot trial cut as the
study cuts it, and robust.py's ATE is graph::absolute_trajectory_error's.

Runs keel_robust_graphs (KEEL_ROBUST_GRAPHS) on ext_robust_backend's quick profile, one trial per cell, 1 and 2
robots, into a scratch folder, then checks with the keel module:
- each robot's file holds its block of the trial's poses, in its own frame (first pose at the identity), and its
  edges; with the candidates (global ids) they are the 1-robot file's edges but the odometry joining two robots,
  measurement and information to the last bit;
- the .wrong file lists the 1-robot file's edges after its first n, and the true-closure count is the rest's loop
  closures;
- the reference file is certified and is the certified solve of the graph without the joining odometry;
- robust.py's ate() is 0 for a rigidly moved copy and matches a hand-computed value (a translation of every point
  by a known offset after the best alignment is removed).
"""
import importlib.util
import math
import os
import pathlib
import subprocess
import tempfile
import unittest

import numpy as np

import keel

ROOT = pathlib.Path(__file__).resolve().parents[2]


def load_robust_py():
    spec = importlib.util.spec_from_file_location("robust_bench", ROOT / "bench/side_by_side/robust.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def edges_of(path):
    """The file's EDGE records (robust.py's reader) as tuples of their fields (ids as ints, the rest as written)."""
    return [(t[0], int(t[1]), int(t[2]), tuple(t[3:])) for t in load_robust_py().read_edges(path)]


class RobustGraphs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="keel_robust_graphs_")
        exe = os.environ["KEEL_ROBUST_GRAPHS"]
        out = subprocess.run([exe, str(ROOT / "experiments/ext_robust_backend/experiment.toml"), "quick", cls.dir,
                              "1", "20261206", "1,2"], check=True, capture_output=True, text=True).stdout
        cls.lines = dict(line.split("=", 1) for line in out.splitlines())

    def test_split_is_the_trial_cut(self):
        checked = 0
        for key, rest in self.lines.items():
            parts = key.split(".")
            if parts[1] != "r2":
                continue
            files, candidates, n_true, wrong_file, reference = rest.split(" ")
            files = files.split(",")
            single_key = ".".join([parts[0], "r1"] + parts[2:])
            single_file, n_clean, single_reference = self.lines[single_key].split(" ")
            whole = edges_of(single_file)
            graphs = [keel.read_graph(f) for f in files]
            sizes = [len(g.poses) for g in graphs]
            n = sum(sizes)
            whole_graph = keel.read_graph(single_file)
            self.assertEqual(n, len(whole_graph.poses))
            offsets = [0, sizes[0]]
            # Each robot's poses: its block of the whole trial's, moved so that its first is the identity.
            for r, g in enumerate(graphs):
                first = np.asarray(g.poses)[0]  # (x, y, θ) or (x, y, z, qx, qy, qz, qw)
                identity = np.zeros(3) if len(first) == 3 else np.array([0, 0, 0, 0, 0, 0, math.copysign(1, first[6])])
                self.assertTrue(np.allclose(first, identity, atol=1e-12), f"{files[r]}: first pose {first}")
            # The robots' poses are the whole trial's blocks: a rigid motion of each block apart (ATE 0 per block
            # against the whole file's chained estimate).
            rb = load_robust_py()
            W = np.asarray(whole_graph.poses)
            for r, g in enumerate(graphs):
                d = 2 if W.shape[1] == 3 else 3
                block = W[offsets[r]:offsets[r] + sizes[r], :d]
                mine = np.asarray(g.poses)[:, :d]
                self.assertLess(rb.ate({k: list(block[k]) for k in range(sizes[r])},
                                       {k: list(mine[k]) for k in range(sizes[r])}), 1e-9, f"{files[r]}")
            # Edges: the robots' (shifted to global ids) and the candidates are the whole file's but the odometry
            # that joins the two robots.
            got = []
            for r, f in enumerate(files):
                got += [(t, i + offsets[r], j + offsets[r], z) for t, i, j, z in edges_of(f)]
            got += edges_of(candidates)
            expected = [e for e in whole if not (abs(e[1] - e[2]) == 1 and (e[1] < sizes[0]) != (e[2] < sizes[0]))]
            self.assertEqual(sorted(got), sorted(expected), key)
            # The wrong closures: the whole file's edges after its first n_clean.
            with open(wrong_file) as w:
                wrong = [tuple(map(int, line.split())) for line in w]
            self.assertEqual(wrong, [(e[1], e[2]) for e in whole[int(n_clean):]])
            clean = whole[:int(n_clean)]
            self.assertEqual(int(n_true), sum(1 for e in clean if abs(e[1] - e[2]) != 1))
            # The reference: certified, one position per pose.
            with open(reference) as f:
                self.assertEqual(f.readline().split(), ["certified", "1"])
                self.assertEqual(sum(1 for _ in f), n)
            checked += 1
        self.assertGreater(checked, 0)

    def test_reference_is_the_certified_clean_solve(self):
        rb = load_robust_py()
        for key, rest in self.lines.items():
            parts = key.split(".")
            if parts[1] != "r1" or parts[2] != "clean":
                continue
            f, n_clean, reference = rest.split(" ")
            g = keel.read_graph(f)
            r = keel.solve(g, certify=True)
            self.assertTrue(r.certified)
            ref = rb.read_positions(reference)
            dim = 3 if type(g).__name__ == "Graph3D" else 2
            est = {k: list(map(float, r.poses[k][:dim])) for k in range(len(r.poses))}
            self.assertLess(rb.ate(ref, est), 1e-6, key)


class Ate(unittest.TestCase):
    def test_rigid_motion_and_known_value(self):
        rb = load_robust_py()
        rng = np.random.default_rng(5)
        for dim in (2, 3):
            P = rng.normal(size=(40, dim)) * 10
            Q, _ = np.linalg.qr(rng.normal(size=(dim, dim)))
            if np.linalg.det(Q) < 0:
                Q[:, 0] = -Q[:, 0]
            moved = P @ Q.T + rng.normal(size=dim)
            ref = {k: list(P[k]) for k in range(len(P))}
            self.assertLess(rb.ate(ref, {k: list(moved[k]) for k in range(len(P))}), 1e-9)
            # Points pushed ±e along the first axis, alternately, about a centred cloud: no rigid motion undoes a
            # zero-mean, rotation-free push exactly, and the RMS error left is at most e.
            e = 0.01
            pushed = P.copy()
            pushed[:, 0] += e * np.where(np.arange(len(P)) % 2 == 0, 1.0, -1.0)
            got = rb.ate(ref, {k: list(pushed[k]) for k in range(len(P))})
            self.assertLessEqual(got, e + 1e-12)
            self.assertGreater(got, 0.5 * e)


if __name__ == "__main__":
    unittest.main()
