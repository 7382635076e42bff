"""Tests of the `keel` command on a user's files (check, solve, marginals, pcm, split, align, align-world).

Run by CTest (cli.tools) with KEEL set to the binary; from this folder: KEEL=../../build/release/keel
/usr/bin/python3 -m unittest -v test_cli. Golden outputs are in golden/; the small synthetic graphs are written by the test itself; the
City10000 and parking-garage files come from the data sets keel's experiments use (found like keel.graph finds
them: $KEEL_DATASETS, <repo>/datasets/cache, <repo>/../shared/datasets).
"""
import json
import math
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np

from cli_fixtures import HERE, KEEL, REPO, SQUARE

# Small synthetic graphs, written by setUpModule into data/ of a scratch folder where every command runs:
# square (8 poses, two laps, two loop closures, one information with cross terms), pair (two poses and one edge:
# the marginal of pose 1 has a closed form) and islands (two connected components, a duplicate edge).
FIXTURES = {
    "square": SQUARE,
    "pair": (
        '# two poses and one edge (tests/cli: closed-form marginal)\n'
        'EDGE_SE2 0 1 1.5 -0.5 0.7 40 3 1 25 -2 90\n'
    ),
    "islands": (
        '# two connected components (tests/cli)\n'
        'VERTEX_SE2 0 0 0 0\n'
        'VERTEX_SE2 1 1 0 0\n'
        'VERTEX_SE2 2 2 0 0\n'
        'VERTEX_SE2 3 5 0 0\n'
        'VERTEX_SE2 4 6 0 0\n'
        'EDGE_SE2 0 1 1 0 0 100 0 0 100 0 100\n'
        'EDGE_SE2 1 2 1 0 0 100 0 0 100 0 100\n'
        'EDGE_SE2 3 4 1 0 0 100 0 0 100 0 100\n'
        'EDGE_SE2 1 2 1.01 0 0 100 0 0 100 0 100\n'
    ),
}
WORK = None


def setUpModule():
    global WORK
    WORK = tempfile.mkdtemp(prefix="keel-cli-")
    os.makedirs(os.path.join(WORK, "data"))
    for name, text in FIXTURES.items():
        with open(os.path.join(WORK, "data", f"{name}.g2o"), "w") as f:
            f.write(text)


def tearDownModule():
    shutil.rmtree(WORK, ignore_errors=True)


def dataset(name, path):
    roots = [os.environ.get("KEEL_DATASETS"), os.path.join(REPO, "datasets", "cache"),
             os.path.join(REPO, "..", "shared", "datasets")]
    for root in roots:
        if root and os.path.exists(os.path.join(root, name, path)):
            return os.path.join(root, name, path)
    raise unittest.SkipTest(f"data set file {name}/{path} not found in {roots}")


def keel(*args, expect=0):
    """Runs keel in the scratch folder (data/ holds the fixtures); checks the exit code; returns (stdout, stderr)."""
    p = subprocess.run([KEEL, *args], cwd=WORK, capture_output=True, text=True, timeout=300)
    if p.returncode != expect:
        raise AssertionError(f"keel {' '.join(args)}: exit {p.returncode}, expected {expect}\n"
                             f"stdout:\n{p.stdout}\nstderr:\n{p.stderr}")
    return p.stdout, p.stderr


def keel_json(*args):
    out, _ = keel(*args, "--json", "--quiet")
    return json.loads(out)


def se2_matrix(x, y, th):
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s, x], [s, c, y], [0, 0, 1.0]])


class Check(unittest.TestCase):
    def test_golden_text(self):
        for name in ("square", "islands"):
            out, _ = keel("check", f"data/{name}.g2o")
            with open(os.path.join(HERE, "golden", f"check_{name}.txt")) as f:
                self.assertEqual(out, f.read(), name)

    def test_json_3d(self):
        s = keel_json("check", dataset("parking-garage", "se-sync/parking-garage.g2o"))
        self.assertEqual((s["dimension"], s["format"], s["poses"], s["components"]), (3, "g2o", 1661, 1))
        self.assertEqual(s["edges"], s["odometry"] + s["loop_closures"])


class Solve(unittest.TestCase):
    def test_summary_and_round_trip(self):
        s = keel_json("solve", "data/square.g2o")["summary"]
        self.assertEqual(s["termination"], "converged")
        self.assertAlmostEqual(s["final_chi2"], 2 * s["final_cost"], places=12)
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "solved.g2o")
            keel("solve", "data/square.g2o", "--out", out, "--quiet")
            # Started at its own solution, the solve has nothing left to do: the same cost, to rounding.
            again = keel_json("solve", out, "--init", "as-read")["summary"]
            self.assertAlmostEqual(again["initial_cost"], s["final_cost"], delta=1e-9 * s["final_cost"])
            self.assertLessEqual(again["final_cost"], s["final_cost"] * (1 + 1e-9))
            # The input's format for an unknown extension; iSAM text for .txt.
            keel("solve", "data/square.g2o", "--out", os.path.join(d, "solved.sol"), "--quiet")
            with open(os.path.join(d, "solved.sol")) as f:
                self.assertTrue(f.readline().startswith("VERTEX_SE2 0 "))
            keel("solve", "data/square.g2o", "--out", os.path.join(d, "solved.txt"), "--quiet")
            self.assertEqual(keel_json("check", os.path.join(d, "solved.txt"))["format"], "isam")

    def test_robust_and_init_options_reach_the_solver(self):
        plain = keel_json("solve", "data/square.g2o")["summary"]
        dcs = keel_json("solve", "data/square.g2o", "--robust", "dcs", "--robust-param", "0.01")["summary"]
        self.assertLess(dcs["final_cost"], plain["final_cost"])  # DCS down-weights the loop closures
        rnd = keel_json("solve", "data/square.g2o", "--init", "random", "--seed", "3")["summary"]
        self.assertNotEqual(rnd["initial_cost"], plain["initial_cost"])

    def test_3d(self):
        s = keel_json("solve", dataset("parking-garage", "se-sync/parking-garage.g2o"))["summary"]
        self.assertEqual(s["termination"], "converged")

    def test_certify(self):
        j = keel_json("solve", "data/square.g2o", "--certify")
        c = j["certificate"]
        self.assertEqual(c["termination"], "certified")
        self.assertTrue(c["certified"])
        self.assertLessEqual(c["lower_bound"], c["final_cost"])
        self.assertLessEqual(c["relative_gap"], 1e-6)
        self.assertEqual(c["final_rank"], 2)
        self.assertIn("isotropic", c["problem"])
        self.assertGreater(j["anisotropic_cost"], 0.0)
        out, _ = keel("solve", "data/square.g2o", "--certify")
        for line in ("problem", "termination  certified", "certificate  F* ≥", "staircase    rank 2"):
            self.assertIn(line, out)
        with tempfile.TemporaryDirectory() as d:
            # The certified estimate written out, then certified again from the file: the same cost.
            path = os.path.join(d, "certified.g2o")
            keel("solve", "data/square.g2o", "--certify", "--out", path, "--quiet")
            again = keel_json("solve", path, "--certify")["certificate"]
            self.assertAlmostEqual(again["final_cost"], c["final_cost"], delta=1e-9 * c["final_cost"])
        _, err = keel("solve", "data/square.g2o", "--certify", "--gap-tolerance", "0", expect=2)
        self.assertIn("gap_tolerance", err)

    def test_indefinite_information(self):
        # One edge whose 3 x 3 information couples x and theta beyond positive definiteness (|I13| > sqrt(I11 I33)).
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "coupled.g2o")
            with open(path, "w") as f:
                f.write("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
                        "EDGE_SE2 0 1 1 0 0 1 0 3 1 0 1\nEDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n"
                        "EDGE_SE2 0 2 2 0 0 1 0 0 1 0 1\n")
            _, err = keel("solve", path, expect=3)
            self.assertIn("not positive definite", err)
            self.assertIn("keel solve --certify", err)
            j = keel_json("solve", path, "--certify")
            self.assertEqual(j["indefinite_information"], 1)
            self.assertIsNone(j["anisotropic_cost"])
            _, err = keel("solve", path, "--certify", "--quiet")
            self.assertIn("1 of 3 information matrices are not positive definite", err)

    def test_certify_3d(self):
        c = keel_json("solve", dataset("se-sync-benchmarks", "tinyGrid3D.g2o"), "--certify")["certificate"]
        self.assertEqual(c["termination"], "certified")
        self.assertEqual(c["final_rank"], 3)


class Marginals(unittest.TestCase):
    def test_closed_form_of_one_edge(self):
        # Pose 0 fixed at the identity, one edge z with residual information Ω: T1 = z exp(r) with r ~ N(0, Ω⁻¹),
        # so the left-perturbation covariance of T1 is Ad(z) Ω⁻¹ Ad(z)ᵀ.
        m = keel_json("marginals", "data/pair.g2o", "--poses", "1")
        x, y, th = 1.5, -0.5, 0.7
        W = np.array([[40, 3, 1], [3, 25, -2], [1, -2, 90.0]])
        R = se2_matrix(0, 0, th)[:2, :2]
        Ad = np.eye(3)
        Ad[:2, :2] = R
        Ad[:2, 2] = [y, -x]
        expected = Ad @ np.linalg.inv(W) @ Ad.T
        np.testing.assert_allclose(np.array(m["covariance"]), expected, rtol=1e-9, atol=1e-15)

    def test_pairs_agree_with_the_joint_of_their_poses(self):
        m_pairs = keel_json("marginals", "data/square.g2o", "--pairs", "2:6,7:3")
        m_joint = keel_json("marginals", "data/square.g2o", "--poses", "2,6")
        a = np.array(m_pairs["pairs"][0]["covariance"])
        np.testing.assert_allclose(a, np.array(m_joint["covariance"]), rtol=1e-10, atol=1e-16)
        np.testing.assert_allclose(a, a.T, rtol=0, atol=1e-16)
        self.assertGreater(np.linalg.eigvalsh(a).min(), 0)
        # The gauge pose has no uncertainty.
        g = np.array(keel_json("marginals", "data/square.g2o", "--pairs", "0:5")["pairs"][0]["covariance"])
        self.assertEqual(np.abs(g[:3, :]).max(), 0.0)

    def test_pair_file_and_out(self):
        with tempfile.TemporaryDirectory() as d:
            pairs = os.path.join(d, "pairs.txt")
            with open(pairs, "w") as f:
                f.write("# i j\n1 2\n3 7\n")
            out = os.path.join(d, "m.json")
            keel("marginals", "data/square.g2o", "--pairs", pairs, "--out", out, "--quiet")
            with open(out) as f:
                m = json.load(f)
            self.assertEqual([(p["i"], p["j"]) for p in m["pairs"]], [(1, 2), (3, 7)])
            self.assertEqual(np.array(m["pairs"][1]["covariance"]).shape, (6, 6))

    def test_3d_pairs(self):
        garage = dataset("parking-garage", "se-sync/parking-garage.g2o")
        m = keel_json("marginals", garage, "--pairs", "10:500")
        a = np.array(m["pairs"][0]["covariance"])
        self.assertEqual(a.shape, (12, 12))
        self.assertGreater(np.linalg.eigvalsh(a).min(), 0)


class Pcm(unittest.TestCase):
    def test_city_split_golden(self):
        city = dataset("city10000", "isam/city10000.txt")
        truth = dataset("city10000", "derived/city10000_groundtruth_poses.txt")
        with tempfile.TemporaryDirectory() as d:
            split = keel_json("split", city, "--ground-truth", truth, "--out-dir", d, "--seed", "1")
            self.assertEqual((split["candidates"], split["inliers"]), (115, 15))
            merged = os.path.join(d, "merged.g2o")
            r = keel_json("pcm", "--a", f"{d}/a.g2o", "--b", f"{d}/b.g2o", "--candidates", f"{d}/candidates.g2o",
                          "--labels", f"{d}/labels.txt", "--merged", merged, "--out", f"{d}/pcm.json")
            with open(os.path.join(HERE, "golden", "pcm_city_seed1.json")) as f:
                golden = json.load(f)
            for key in ("candidates", "selected", "status", "upper_bound", "consistent_pairs", "true_positives",
                        "false_positives"):
                self.assertEqual(r[key], golden[key], key)
            self.assertAlmostEqual(r["gamma"], 6.033327, places=5)  # F⁻¹_χ²(3)(0.89)
            # Every selected pair is consistent (eq. 2.3), read back from Q in --out.
            with open(f"{d}/pcm.json") as f:
                full = json.load(f)
            q = np.array(full["q"]).reshape(r["candidates"], r["candidates"])
            sel = [s["candidate"] for s in r["selected"]]
            for u in sel:
                for v in sel:
                    if u != v:
                        self.assertLessEqual(q[u, v], r["gamma"])
            # The merged map holds both robots and is connected through the selected candidates.
            c = keel_json("check", merged)
            self.assertEqual((c["poses"], c["components"]), (1500, 1))
            # Independent composition (the ablation of Table 2.1) runs on the same files.
            ind = keel_json("pcm", "--a", f"{d}/a.g2o", "--b", f"{d}/b.g2o", "--candidates",
                            f"{d}/candidates.g2o", "--composition", "independent")
            self.assertEqual(ind["composition"], "independent")


class Align(unittest.TestCase):
    def test_a_written_table_world_reproduces_the_experiment(self):
        """World 0 of ch3_table3_1_alignment written by `keel align-world` and aligned by `keel align` gives the
        costs ch3_fig3_4_example (that world, the four methods) records in its committed baseline."""
        with open(os.path.join(REPO, "results", "ch3_fig3_4_example", "baseline.full.json")) as f:
            base = json.load(f)["metrics"]
        with tempfile.TemporaryDirectory() as d:
            world = keel_json("align-world", d, "--index", "0")
            with open(os.path.join(d, "truth.csv")) as f:
                self.assertEqual(world["truth"]["theta"], float(f.read().split("\n")[1].split(",")[0]))
            self.assertAlmostEqual(world["truth"]["theta"], base["world.theta"], delta=1e-10)
            for method in ("proposed", "so_conv_hull", "symmetric", "affine"):
                r = keel_json("align", os.path.join(d, "reference.csv"), os.path.join(d, "query.csv"),
                              "--dissimilarity", "euclidean", "--method", method)
                # The results files keep 12 significant digits.
                self.assertAlmostEqual(r["cost"], base[f"{method}.cost"], delta=1e-9 * abs(base[f"{method}.cost"]))
                self.assertEqual(len(r["rounds"]), 7)
                self.assertEqual(r["rounds"][-1]["transform"], r["transform"])
            text, _ = keel("align", os.path.join(d, "reference.csv"), os.path.join(d, "query.csv"), "--certify")
            self.assertIn("certificate  optimal over SO(2)", text)

    def test_a_terrain_world_over_a_real_grid(self):
        """`keel align-world --terrain` writes a survey pair over a real elevation grid (the worlds of
        ch3_table3_1_terrain_jacksboro: Table 3.1's geometry times --scale, positions in units of it), and
        `keel align` recovers its rotation; a malformed grid is refused at its line."""
        grid = os.path.join(REPO, "datasets", "cache", "matplotlib-terrain", "grids", "jacksboro_fault_dem.grid")
        with tempfile.TemporaryDirectory() as d:
            world = keel_json("align-world", d, "--terrain", grid, "--index", "0")
            self.assertEqual(world["length_unit_m"], 50)
            self.assertGreater(world["roughness_m"], 0)
            ref = np.loadtxt(os.path.join(d, "reference.csv"), delimiter=",", skiprows=1)
            self.assertEqual(ref.shape, (1891, 5))  # x, y and elevation, slope, curvature
            self.assertEqual((ref[:, 0].min(), ref[:, 0].max()), (-30, 30))  # 3 km in units of 50 m
            # standardised over the reference before the noise (std 0.3, so its mean is within ~0.03 of 0)
            self.assertAlmostEqual(float(ref[:, 2].mean()), 0, delta=0.05)
            r = keel_json("align", os.path.join(d, "reference.csv"), os.path.join(d, "query.csv"))
            error = math.remainder(r["rigid"]["theta"] - world["truth"]["theta"], 2 * math.pi)
            self.assertLess(abs(error), 0.05)
            bad = os.path.join(d, "bad.grid")
            with open(bad, "w") as f:
                f.write("keel-grid 1\nsource x\nrows 3\ncols 3\nlon 1 2\n")
            _, err = keel("align-world", os.path.join(d, "w"), "--terrain", bad, expect=3)
            self.assertIn(f"{bad}:5: lon values: 2 where 3 were expected", err)
            _, err = keel("align-world", os.path.join(d, "w"), "--terrain", grid, "--scale", "0", expect=2)
            self.assertIn("--scale: 0: must be a length > 0", err)
            _, err = keel("align-world", os.path.join(d, "w"), "--terrain", grid, "--scale", "2000", expect=3)
            self.assertIn("does not fit", err)

    def test_bad_surveys_give_located_errors(self):
        with tempfile.TemporaryDirectory() as d:
            ref, query = os.path.join(d, "ref.csv"), os.path.join(d, "query.csv")
            with open(ref, "w") as f:
                f.write("x,y,f\n0,0,1\n10,0,2\n0,10,3\n10,10,4\n")
            with open(query, "w") as f:
                f.write("x,y,f\n1,1,1\n2,nan,2\n")
            _, err = keel("align", ref, query, expect=3)
            self.assertIn(f"{query}:3: column 2: 'nan' is not a finite number", err)
            with open(query, "w") as f:
                f.write("0,0,1\n40,0,2\n")
            _, err = keel("align", ref, query, expect=3)
            self.assertIn("the query spans 40 m but the reference's bounding box only 14.1 m", err)
            with open(query, "w") as f:
                f.write("0,0,1,5\n")
            _, err = keel("align", ref, query, expect=3)
            self.assertIn("has 1 feature columns", err)
            _, err = keel("align", ref, ref, "--method", "rigid", expect=2)
            self.assertIn("unknown align::Method 'rigid'", err)


class BadInput(unittest.TestCase):
    def error(self, code, text, *args):
        _, err = keel(*args, expect=code)
        self.assertIn(text, err)

    def test_every_class_gives_a_located_error(self):
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "bad.g2o")
            with open(bad, "w") as f:
                f.write("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 abc 1 0 0 1 0 1\n")
            self.error(3, f"{bad}:2: EDGE_SE2 field 5 (dtheta): 'abc' is not a number", "check", bad)
            self.error(3, f"{bad}:2: EDGE_SE2 field 5 (dtheta)", "solve", bad)
            self.error(3, "cannot open file", "solve", os.path.join(d, "missing.g2o"))
            self.error(2, "unknown pgo::InitialGuess 'lm'", "solve", "data/square.g2o", "--init", "lm")
            self.error(2, "unknown pgo::RobustKernel 'tukey'", "solve", "data/square.g2o", "--robust", "tukey")
            self.error(2, "--bogus", "solve", "data/square.g2o", "--bogus")
            self.error(2, "file is required", "solve")
            self.error(2, "give exactly one of --pairs and --poses", "marginals", "data/square.g2o")
            self.error(3, "--pairs: pair '1:8': '8' is too large: expected a pose id of the graph (8 poses) in 0 … 7",
                       "marginals",
                       "data/square.g2o", "--pairs", "1:8")
            self.error(3, "--pairs: '1-2' is not a pair 'i:j'", "marginals", "data/square.g2o", "--pairs", "1-2")
            self.error(3, "pose 3 of 'data/islands.g2o' is not connected to pose 0", "marginals", "data/islands.g2o",
                       "--poses", "1")
            self.error(1, "not positive definite", "marginals", "data/islands.g2o", "--poses", "1", "--init",
                       "as-read")
            cand = os.path.join(d, "cand.g2o")
            with open(cand, "w") as f:
                f.write("EDGE_SE2 0 9 1 0 0 1 0 0 1 0 1\n")
            self.error(3, "candidate 0 (line 1): robot b has no pose 9 (it has 8 poses: 0 … 7)", "pcm", "--a",
                       "data/square.g2o", "--b", "data/square.g2o", "--candidates", cand)
            with open(cand, "w") as f:
                f.write("VERTEX_SE2 0 0 0 0\n")
            self.error(3, f"{cand}:1: unexpected tag 'VERTEX_SE2'", "pcm", "--a", "data/square.g2o", "--b",
                       "data/square.g2o", "--candidates", cand)
            with open(cand, "w") as f:
                f.write("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 2 3 1 0 0 1 0 0 1 0 1\n")
            self.error(2, "--p: app::PcmOptions: p must be in (0, 1) (got 1.5)", "pcm", "--a", "data/square.g2o",
                       "--b", "data/square.g2o", "--candidates", cand, "--p", "1.5")
            labels = os.path.join(d, "labels.txt")
            with open(labels, "w") as f:
                f.write("0 inlier -1\n1 outlier -1\n")
            self.error(3, f"{labels}:2: label field 2 (kind)", "pcm", "--a", "data/square.g2o", "--b",
                       "data/square.g2o", "--candidates", cand, "--labels", labels)
            self.error(3, "keel split supports 2D graphs", "split",
                       dataset("parking-garage", "se-sync/parking-garage.g2o"), "--ground-truth", bad, "--out-dir",
                       os.path.join(d, "split"))


class ProseCheck(unittest.TestCase):
    TOML = (
        'id = "x_prose"\ntitle = "prose fixture"\nreproduces = "Table 9.9"\ndescription = "d"\n'
        'discussion = """{}"""\nseed = 1\n[params]\nlevel = 0.95\n[profiles.quick]\n[profiles.full]\n'
        '[thesis]\nsource = "Table 9.9"\nclaim = "a TPR of 0.997"\n')

    def check(self, discussion, expect):
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "experiments", "x_prose"))
            with open(os.path.join(d, "experiments", "x_prose", "experiment.toml"), "w") as f:
                f.write(self.TOML.format(discussion))
            p = subprocess.run([KEEL, "prose-check"], cwd=d, capture_output=True, text=True, timeout=60)
            self.assertEqual(p.returncode, expect, p.stdout + p.stderr)
            return p.stdout + p.stderr

    def test_a_hand_typed_number_fails_with_its_context(self):
        out = self.check("PCM keeps TPR 0.941 and an MSE of 0.45 m².", 1)
        self.assertIn("'0.941'", out)
        self.assertIn("'0.45'", out)
        self.assertIn("2 number(s) typed by hand", out)

    def test_placeholders_thesis_numbers_settings_and_references_pass(self):
        self.check("TPR {metric:tpr|.3f} (thesis 0.997) at level = 0.95, as in Table 9.9 and SE(3).", 0)


if __name__ == "__main__":
    unittest.main()
