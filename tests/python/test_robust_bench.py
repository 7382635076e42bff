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
  by a known offset after the best alignment is removed);
- robust.py --from-tsv --summary-json gives the report's tables from rows whose verdicts are known, and refuses a
  malformed row naming its line; certified_summary.py does the same for certified.sh's rows;
- robust_revisions.py finds the same answers when both sides are the same keel (KEEL), ignores a change of times and
  test statistics, and reports a changed kept flag with the input's key and exit code 1.
"""
import importlib.util
import json
import math
import os
import pathlib
import subprocess
import sys
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


    def test_revisions_same_and_changed_answers(self):
        keys = [k for k in sorted(self.lines) if k.startswith("intel.") and ".aliased.out20." in k]
        self.assertEqual({k.split(".")[1] for k in keys}, {"r1", "r2"})
        listing = os.path.join(self.dir, "revisions.txt")
        with open(listing, "w") as f:
            f.writelines(f"{k}={self.lines[k]}\n" for k in keys)
        exe = os.environ["KEEL"]

        # A stand-in for another build: runs keel, then edits its report as `edit` says.
        def wrapper(name, edit):
            path = os.path.join(self.dir, name)
            with open(path, "w") as f:
                f.write(f"#!{sys.executable}\nimport json, subprocess, sys\n"
                        f"p = subprocess.run([{exe!r}, *sys.argv[1:]], capture_output=True, text=True)\n"
                        f"d = json.loads(p.stdout)\n{edit}\nprint(json.dumps(d))\nsys.exit(p.returncode)\n")
            os.chmod(path, 0o755)
            return path

        def run(new):
            return subprocess.run([sys.executable, str(ROOT / "bench/side_by_side/robust_revisions.py"), exe, new,
                                   os.path.join(self.dir, "revisions.tsv"), listing], capture_output=True, text=True)

        same = run(exe)
        self.assertEqual(same.returncode, 0, same.stderr)
        self.assertIn(f"{len(keys)} inputs, answers identical on {len(keys)}", same.stdout)
        noise = run(wrapper("noise.py", "d['times_s'] = {k: v * 3 for k, v in d['times_s'].items()}\n"
                                        "for c in d['candidate_list']: c['residual_chi2'] = 1.0"))
        self.assertEqual(noise.returncode, 0, noise.stderr)
        flipped = run(wrapper("flip.py", "d['candidate_list'][0]['kept'] = not d['candidate_list'][0]['kept']"))
        self.assertEqual(flipped.returncode, 1)
        self.assertIn(f"{len(keys)} inputs, answers identical on 0", flipped.stdout)
        for k in keys:
            self.assertIn(f"the answers differ on {k}", flipped.stderr)


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


class RobustSummary(unittest.TestCase):
    """robust.py --from-tsv --summary-json: the tables the report renders, from rows whose answer is known."""

    HEADER = ("dataset\trate\ttrial\ttool\tkept_true\ttrue\tkept_wrong\twrong\tprecision\trecall\tprocess_s\t"
              "own_s\tcertified\tate\n")

    def rows(self):
        out = []
        # Cell (manhattan.random, 20 %), one robot: keel keeps a wrong closure in every trial (precision worse,
        # by 0.09–0.11), is as fast. Cell (manhattan.r2.random, 20 %), two robots: keel is faster (0.1 s
        # against 0.5 s), the same otherwise.
        for t, p in enumerate([0.9, 0.91, 0.89]):
            out.append(f"manhattan.random\t20.0\t{t}\tkeel\t9\t10\t1\t2\t{p}\t0.9\t0.20\t0.1\tyes\t0.05\n")
            out.append(f"manhattan.random\t20.0\t{t}\tkimera\t9\t10\t0\t2\t1.0\t0.9\t0.2{t}\t0.1\t\t0.05\n")
            out.append(f"manhattan.r2.random\t20.0\t{t}\tkeel\t8\t10\t0\t2\t1.0\t0.8\t0.1{t}\t0.05\tno\t0.07\n")
            out.append(f"manhattan.r2.random\t20.0\t{t}\tkimera\t8\t10\t0\t2\t1.0\t0.8\t0.5{t}\t0.4\t\t0.07\n")
        return out

    def run_robust(self, tsv, *extra):
        return subprocess.run([sys.executable, str(ROOT / "bench/side_by_side/robust.py"), "--from-tsv", tsv,
                               *extra], capture_output=True, text=True)

    def test_tables(self):
        d = tempfile.mkdtemp(prefix="keel_robust_summary_")
        tsv, js = os.path.join(d, "rows.tsv"), os.path.join(d, "summary.json")
        with open(tsv, "w") as f:
            f.write(self.HEADER + "".join(self.rows()))
        r = self.run_robust(tsv, "--summary-json", js, "--provenance", "keel_commit=abc1234")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(js) as f:
            doc = json.load(f)
        self.assertEqual(doc["provenance"], {"keel_commit": "abc1234"})
        by_robots, signs, totals, worse = doc["tables"]
        header = by_robots["header"]
        self.assertEqual(header[:3], ["robots", "cells", "no rule shows keel worse"])
        rows = {row[0]: dict(zip(header, row)) for row in by_robots["rows"]}
        self.assertEqual(rows["1"]["precision: better / same / worse"], "0 / 0 / 1")
        self.assertEqual(rows["1"]["no rule shows keel worse"], "0")
        self.assertEqual(rows["2"]["process time: better / same / worse"], "1 / 0 / 0")
        self.assertEqual(rows["2"]["no rule shows keel worse"], "1")
        self.assertEqual(rows["all"]["cells"], "2")
        self.assertEqual([w[:3] for w in worse["rows"]], [["precision", "manhattan.random", "20 %"]])
        self.assertTrue(worse["rows"][0][4].startswith("-0.100 ["))
        keel_1 = next(t for t in totals["rows"] if t[:2] == ["keel", "1"])
        self.assertEqual(keel_1[2:7], ["3", "3", "27 of 30", "0.05", "3 of 3"])
        for table in doc["tables"]:
            for row in table["rows"]:
                self.assertEqual(len(row), len(table["header"]))
                self.assertTrue(all(isinstance(c, str) for c in row))

    def test_bad_rows_are_refused_with_the_line(self):
        d = tempfile.mkdtemp(prefix="keel_robust_summary_")
        tsv = os.path.join(d, "rows.tsv")
        with open(tsv, "w") as f:
            f.write(self.HEADER + self.rows()[0] + "manhattan\tx\t0\tkeel\n")
        r = self.run_robust(tsv)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("rows.tsv:3: 4 fields, expected 14", r.stderr)
        r = self.run_robust(tsv, "--provenance", "novalue")
        self.assertIn("--provenance takes KEY=VALUE", r.stderr)


class CertifiedSummary(unittest.TestCase):
    """certified_summary.py: certified.sh's rows as the report's tables, with levels, ratios and cross-checks."""

    HEADER = ("dataset\tkeel_F\tkeel_lower\tkeel_gap\tkeel_status\tkeel_rank\tkeel_iterations\tkeel_own_s\t"
              "keel_process_s\tsesync_F\tsesync_SDPval\tsesync_status\tsesync_rank\tsesync_own_s\t"
              "sesync_process_s\tfaster_own\tfaster_process\n")
    ROWS = [
        # certified, faster by both rules
        "intel.rot0p1.d0\t10.0\t9.9999\t1e-05\tcertified\t2\t5\t0.03\t0.06\t10.0\t10.0\tGlobalOpt\t5\t0.02\t0.08\t\t\n",
        # not certified, 3× slower by process time, keel's F lower, bound below SE-Sync's SDP value
        "intel.rot2.d0\t50.0\t48.0\t0.04\tnot_certified\t5\t90\t1.5\t1.5\t51.0\t48.5\tGlobalOpt\t9\t0.4\t0.5\t\t\n",
        # keel's F above SE-Sync's (a failed cross-check), no proven bound
        "intel.out10.d1\t20.0\tnone\t\trank_limit\t10\t40\t1.0\t1.0\t19.0\t18.0\tMaxRank\t10\t0.5\t0.6\t\t\n",
    ]

    def run_summary(self, rows, *extra):
        d = tempfile.mkdtemp(prefix="keel_certified_summary_")
        tsv, js = os.path.join(d, "rows.tsv"), os.path.join(d, "summary.json")
        with open(tsv, "w") as f:
            f.write(self.HEADER + "".join(rows))
        r = subprocess.run([sys.executable, str(ROOT / "bench/side_by_side/certified_summary.py"), tsv, js, *extra],
                           capture_output=True, text=True)
        return r, js

    def test_tables(self):
        r, js = self.run_summary(self.ROWS, "--provenance", "keel_commit=abc1234")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(js) as f:
            doc = json.load(f)
        self.assertEqual(doc["provenance"], {"keel_commit": "abc1234"})
        levels, graphs = doc["tables"]
        rows = {row[0]: dict(zip(levels["header"], row)) for row in levels["rows"]}
        self.assertEqual(list(rows), ["σ = 0.1 rad", "σ = 2 rad", "10 % outliers", "all"])
        total = rows["all"]
        self.assertEqual(total["graphs"], "3")
        self.assertEqual(total["keel certified"], "1")
        self.assertEqual(total["SE-Sync GlobalOpt"], "2")
        self.assertEqual(total["within 2×"], "2")  # ratios 0.75, 3.0, 1.67
        self.assertEqual(total["keel faster"], "1")
        self.assertEqual(total["process ratio: median"], "1.67")
        self.assertEqual(total["process ratio: max"], "3.00")
        self.assertEqual(total["own-timer ratio: max"], "3.75")
        self.assertEqual(total["keel F ≤ SE-Sync F"], "2 of 3")
        self.assertEqual(total["keel bound ≤ SE-Sync SDPval (GlobalOpt)"], "2 of 2")
        self.assertEqual([g[0] for g in graphs["rows"]], ["intel.rot0p1.d0", "intel.rot2.d0", "intel.out10.d1"])
        self.assertEqual(graphs["rows"][1][-1], "3.00")

    def test_refuses_rows_without_se_sync_or_with_failures(self):
        no_sesync = self.ROWS[0].split("\t")
        no_sesync[9:15] = [""] * 6
        r, _ = self.run_summary(["\t".join(no_sesync)])
        self.assertIn("rows.tsv:2: no SE-Sync result", r.stderr)
        failed = self.ROWS[0].replace("\t0.03\t0.06\t", "\t\t\t")
        r, _ = self.run_summary([failed])
        self.assertIn("rows.tsv:2: keel_own_s is '', not a number", r.stderr)
