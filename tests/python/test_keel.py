"""Tests of the Python module keel (engine/python), run by CTest as `python.bindings`:

    PYTHONPATH=build/release/python KEEL_REFERENCE=build/release/tests/python/keel_python_reference \
        /usr/bin/python3 -m unittest -v test_keel        (from tests/python)

* group operations against numpy matrix algebra (SE2, SE3);
* first-order propagation of uncertain poses against Monte-Carlo estimates (fixed numpy seed);
* bit-for-bit agreement of solve / marginals / consistency_matrix with keel_python_reference, a C++ program
  that makes the same engine calls and prints every double with {:.17g};
* errors: ParseError with the engine's message, enum text, ids out of range.

Data: Manhattan3500 and Sphere2500 through keel.dataset_file (datasets/manifest.toml); tests that need them are
skipped with the resolver's message when the files are not available.
"""

import json
import math
import os
import re
import subprocess
import tempfile
import unittest

import numpy as np

import keel


def expm(A, terms=40):
    """Matrix exponential by its Taylor series (small arguments only; independent of keel)."""
    out = np.eye(A.shape[0])
    term = np.eye(A.shape[0])
    for k in range(1, terms):
        term = term @ A / k
        out = out + term
    return out


def hat2(xi):
    rho_x, rho_y, th = xi
    return np.array([[0.0, -th, rho_x], [th, 0.0, rho_y], [0.0, 0.0, 0.0]])


def skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def hat3(xi):
    out = np.zeros((4, 4))
    out[:3, :3] = skew(xi[3:])
    out[:3, 3] = xi[:3]
    return out


def dataset(name, path):
    try:
        return keel.dataset_file(name, path)
    except keel.DatasetError as e:
        raise unittest.SkipTest(str(e))


def subgraph(g, lo, hi):
    """Poses lo..hi-1 of g and the edges among them, re-indexed from 0 (same dimension as g)."""
    e = g.edges
    keep = (e >= lo).all(1) & (e < hi).all(1)
    cls = keel.Graph2D if isinstance(g, keel.Graph2D) else keel.Graph3D
    return cls(g.poses[lo:hi], e[keep] - lo, g.measurements[keep], g.information[keep])


def strip_times(x):
    """A record without its wall times (fields named *time_s or times_s), which differ between runs."""
    if isinstance(x, dict):
        return {k: strip_times(v) for k, v in x.items() if not k.endswith("time_s") and k != "times_s"}
    if isinstance(x, list):
        return [strip_times(v) for v in x]
    return x


def reference(*args):
    exe = os.environ.get("KEEL_REFERENCE")
    if not exe:
        raise unittest.SkipTest("KEEL_REFERENCE (path of keel_python_reference) is not set")
    out = subprocess.run([exe, *map(str, args)], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


class TestGroups(unittest.TestCase):
    def setUp(self):
        self.rng = np.random.default_rng(7)

    def test_se2_against_matrices(self):
        for _ in range(20):
            xa, xb = self.rng.normal(size=3), self.rng.normal(size=3)
            a, b = keel.SE2(*xa), keel.SE2(*xb)
            Ma, Mb = a.matrix(), b.matrix()
            np.testing.assert_allclose(Ma[:2, 2], xa[:2], atol=0)
            self.assertAlmostEqual(math.atan2(Ma[1, 0], Ma[0, 0]), a.theta, places=15)
            np.testing.assert_allclose((a * b).matrix(), Ma @ Mb, atol=1e-12)
            np.testing.assert_allclose(a.inverse().matrix(), np.linalg.inv(Ma), atol=1e-12)
            np.testing.assert_allclose(a.between(b).matrix(), np.linalg.inv(Ma) @ Mb, atol=1e-12)
            xi = self.rng.normal(size=3)
            xi[2] = math.remainder(xi[2], 2 * math.pi)
            np.testing.assert_allclose(keel.SE2.exp(xi).matrix(), expm(hat2(xi)), atol=1e-12)
            np.testing.assert_allclose(keel.SE2.exp(xi).log(), xi, atol=1e-12)
            np.testing.assert_allclose(keel.SE2.exp(a.log()).matrix(), Ma, atol=1e-12)
            np.testing.assert_allclose(keel.SE2.from_matrix(Ma).matrix(), Ma, atol=1e-15)
            np.testing.assert_allclose(a.act([1.0, 2.0]), Ma[:2, :2] @ [1.0, 2.0] + Ma[:2, 2], atol=1e-12)

    def test_se3_against_matrices(self):
        for _ in range(20):
            xa, xb = self.rng.normal(size=6), self.rng.normal(size=6)
            a, b = keel.SE3.exp(xa), keel.SE3.exp(xb)
            Ma, Mb = a.matrix(), b.matrix()
            # tangent order [rho; phi]: translation part first, rotation vector last
            np.testing.assert_allclose(Ma, expm(hat3(xa)), atol=1e-11)
            np.testing.assert_allclose((a * b).matrix(), Ma @ Mb, atol=1e-12)
            np.testing.assert_allclose(a.inverse().matrix(), np.linalg.inv(Ma), atol=1e-12)
            np.testing.assert_allclose(a.between(b).matrix(), np.linalg.inv(Ma) @ Mb, atol=1e-12)
            np.testing.assert_allclose(keel.SE3.exp(a.log()).matrix(), Ma, atol=1e-12)
            np.testing.assert_allclose(a.rotation(), Ma[:3, :3], atol=0)
            np.testing.assert_allclose(a.translation(), Ma[:3, 3], atol=0)
            q = a.quaternion()
            self.assertGreaterEqual(q[3], 0.0)
            np.testing.assert_allclose(keel.SE3.from_quaternion(a.translation(), q).matrix(), Ma, atol=1e-12)
            np.testing.assert_allclose(keel.SE3(Ma[:3, :3], Ma[:3, 3]).matrix(), Ma, atol=1e-12)
            np.testing.assert_allclose(keel.SE3.from_matrix(Ma).matrix(), Ma, atol=1e-12)
        # a quarter turn about z
        T = keel.SE3.from_quaternion([1, 2, 3], [0, 0, math.sqrt(0.5), math.sqrt(0.5)])
        np.testing.assert_allclose(T.rotation(), [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)

    def test_invalid_inputs(self):
        with self.assertRaises(ValueError):
            keel.SE2.from_matrix(np.diag([2.0, 1.0, 1.0]))
        with self.assertRaises(ValueError):
            keel.SE3.from_quaternion([0, 0, 0], [0, 0, 0, 2])
        with self.assertRaises(ValueError):
            keel.UncertainSE2(keel.SE2(), -np.eye(3))


def sample_covariance(rng, n, dim):
    A = rng.normal(size=(dim, dim)) * n
    return A @ A.T + 1e-4 * np.eye(dim)


class TestUncertain(unittest.TestCase):
    """First-order propagation (thesis eqs. 5.39, 5.43-5.45, 5.51) against Monte-Carlo estimates."""

    N = 40000

    def monte_carlo(self, group, means, cov, fn):
        """Covariance of log(f(samples) f(means)^-1) for xi ~ N(0, cov) stacked over the inputs."""
        rng = np.random.default_rng(2024)
        d = 3 if group is keel.SE2 else 6
        xs = rng.multivariate_normal(np.zeros(cov.shape[0]), cov, size=self.N)
        mean = fn(*means)
        mean_inv = mean.inverse()
        errs = np.empty((self.N, d))
        for k, x in enumerate(xs):
            samples = [group.exp(x[d * i : d * (i + 1)]) * m for i, m in enumerate(means)]
            errs[k] = (fn(*samples) * mean_inv).log()
        return mean, errs.T @ errs / self.N

    def check(self, got, mc):
        # Monte-Carlo error ~ sqrt(2/N) relative ~ 0.7 %, plus second-order terms of the small covariances.
        scale = np.sqrt(np.outer(np.diag(mc), np.diag(mc)))
        np.testing.assert_array_less(np.abs(got - mc) / scale, 0.04)

    def test_compose_se2_independent_and_correlated(self):
        rng = np.random.default_rng(1)
        a_mean, b_mean = keel.SE2(1.0, -2.0, 0.7), keel.SE2(3.0, 0.5, -1.2)
        joint = sample_covariance(rng, 0.02, 6)
        Sa, Sb, C = joint[:3, :3], joint[3:, 3:], joint[:3, 3:]
        a, b = keel.UncertainSE2(a_mean, Sa), keel.UncertainSE2(b_mean, Sb)
        mean, mc = self.monte_carlo(keel.SE2, [a_mean, b_mean], joint, lambda x, y: x * y)
        got = keel.compose(a, b, cross=C)
        self.assertTrue(got.mean.is_approx(mean, 1e-15))
        self.check(got.covariance, mc)
        indep = np.block([[Sa, np.zeros((3, 3))], [np.zeros((3, 3)), Sb]])
        _, mc_indep = self.monte_carlo(keel.SE2, [a_mean, b_mean], indep, lambda x, y: x * y)
        self.check(keel.compose(a, b).covariance, mc_indep)
        # the cross term matters here: the independent formula misses the correlated estimate
        self.assertGreater(np.abs(keel.compose(a, b).covariance - mc).max(), 10 * np.abs(got.covariance - mc).max())

    def test_between_and_inverse_se3(self):
        rng = np.random.default_rng(3)
        a_mean, b_mean = keel.SE3.exp(rng.normal(size=6)), keel.SE3.exp(rng.normal(size=6))
        joint = sample_covariance(rng, 0.01, 12)
        a = keel.UncertainSE3(a_mean, joint[:6, :6])
        b = keel.UncertainSE3(b_mean, joint[6:, 6:])
        mean, mc = self.monte_carlo(keel.SE3, [a_mean, b_mean], joint, lambda x, y: x.between(y))
        got = keel.between(a, b, cross=joint[:6, 6:])
        self.assertTrue(got.mean.is_approx(mean, 1e-12))
        self.check(got.covariance, mc)
        _, mc_inv = self.monte_carlo(keel.SE3, [a_mean], joint[:6, :6], lambda x: x.inverse())
        self.check(keel.inverse(a).covariance, mc_inv)

    def test_joint_poses(self):
        rng = np.random.default_rng(5)
        means = [keel.SE2(*rng.normal(size=3)) for _ in range(3)]
        joint = keel.JointPosesSE2(means, sample_covariance(rng, 0.05, 9))
        c = joint.compose(0, 2)
        ref = keel.compose(joint.marginal(0), joint.marginal(2), cross=joint.cross(0, 2))
        np.testing.assert_array_equal(c.covariance, ref.covariance)
        k = joint.append_relative(0, 1)
        self.assertEqual(k, 3)
        np.testing.assert_allclose(joint.marginal(3).covariance, joint.between(0, 1).covariance, atol=1e-14)
        with self.assertRaises(IndexError):
            joint.compose(0, 7)


class TestReference(unittest.TestCase):
    """The bindings against keel_python_reference (same engine calls in C++), compared with ==."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        man = keel.read_graph(dataset("manhattan3500", "isam/manhattanOlson3500.txt"))
        cls.file2d = os.path.join(cls.tmp.name, "manhattan200.g2o")
        keel.write_graph(subgraph(man, 0, 200), cls.file2d)
        sph = keel.read_graph(dataset("sphere2500", "isam/sphere2500.txt"))
        cls.file3d = os.path.join(cls.tmp.name, "sphere100.g2o")
        keel.write_graph(subgraph(sph, 0, 100), cls.file3d)
        # Two robots: Manhattan poses 0-99 (a) and 100-199 (b); the edges from a to b are the candidates, plus
        # three outliers.
        cls.file_a = os.path.join(cls.tmp.name, "a.g2o")
        cls.file_b = os.path.join(cls.tmp.name, "b.g2o")
        keel.write_graph(subgraph(man, 0, 100), cls.file_a)
        keel.write_graph(subgraph(man, 100, 200), cls.file_b)
        e = man.edges
        cross = (e[:, 0] < 100) & (e[:, 1] >= 100) & (e[:, 1] < 200)
        ids = np.vstack([e[cross] - [0, 100], [[10, 10], [50, 20], [90, 60]]])
        z = np.vstack([man.measurements[cross], [[5.0, -3.0, 1.0], [-7.0, 2.0, 2.5], [0.0, 9.0, -2.0]]])
        info = np.concatenate([man.information[cross], np.tile(np.eye(3) * 10, (3, 1, 1))])
        cls.num_inliers = int(cross.sum())
        cls.file_c = os.path.join(cls.tmp.name, "candidates.g2o")
        keel.write_candidates(keel.Candidates(ids, z, info), cls.file_c)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def compare_solve(self, path, pairs):
        ref = reference("solve", path, *[v for p in pairs for v in p])
        g = keel.read_graph(path)
        self.assertEqual(ref["dim"], 2 if isinstance(g, keel.Graph2D) else 3)
        r = keel.solve(g)
        self.assertEqual(r.termination, ref["termination"])
        self.assertEqual(r.iterations, ref["iterations"])
        self.assertEqual(r.cost, ref["cost"])
        self.assertEqual(r.normalized_chi2, ref["normalized_chi2"])
        np.testing.assert_array_equal(r.poses, np.array(ref["poses"]))
        np.testing.assert_array_equal(r.graph.poses, r.poses)
        # r.graph holds the solution as the solver left it; an (n, 3) / (n, 7) array of it does not give back
        # the same bits (theta -> cos/sin, quaternion -> matrix), so marginals at poses=r.poses agree to ~1e-10
        m = keel.marginals(r.graph, pairs=pairs)
        np.testing.assert_array_equal(m.reshape(len(pairs), -1), np.array(ref["marginals"]))
        np.testing.assert_array_equal(keel.marginals(g, poses=r.graph.poses, pairs=pairs), keel.marginals(g, poses=r.poses, pairs=pairs))
        np.testing.assert_allclose(keel.marginals(g, poses=r.poses, pairs=pairs), m, rtol=1e-8, atol=1e-14)
        # the same with an array of pairs and with the reusable factor on two threads
        np.testing.assert_array_equal(keel.marginals(r.graph, pairs=np.array(pairs)), m)
        np.testing.assert_array_equal(keel.MarginalCovariance(r.graph).pairs(pairs, threads=2), m)
        return r, m

    def test_solve_and_marginals_2d(self):
        r, m = self.compare_solve(self.file2d, [(0, 5), (3, 150), (10, 199), (198, 199)])
        self.assertEqual(m.shape, (4, 6, 6))
        np.testing.assert_array_equal(m[:, :3, :3][0], np.zeros((3, 3)))  # pose 0 is the gauge
        ids = keel.marginals(r.graph, ids=[5, 0])
        # joint() and pair_marginals_2d() take different extraction paths: equal to rounding only
        np.testing.assert_allclose(ids, m[0][np.ix_([3, 4, 5, 0, 1, 2], [3, 4, 5, 0, 1, 2])], rtol=1e-14, atol=1e-18)

    def test_solve_and_marginals_3d(self):
        _, m = self.compare_solve(self.file3d, [(1, 2), (7, 99)])
        self.assertEqual(m.shape, (2, 12, 12))

    def test_certified_solve(self):
        for path in (self.file2d, self.file3d):
            ref = reference("certify", path)
            g = keel.read_graph(path)
            r = keel.solve(g, certify=True)
            self.assertIsInstance(r, keel.CertifiedSolveResult)
            self.assertEqual(r.termination, ref["termination"])
            self.assertEqual(r.cost, ref["cost"])
            self.assertEqual(r.certificate["lower_bound"], ref["lower_bound"])
            self.assertEqual(r.rank, ref["rank"])
            self.assertEqual(r.iterations, ref["iterations"])
            np.testing.assert_array_equal(r.poses, np.array(ref["poses"]))
            c = r.certificate
            if c["lower_bound"] is not None:
                self.assertLessEqual(c["lower_bound"], r.cost)
                self.assertEqual(c["certified"], c["relative_gap"] <= 1e-6)
            self.assertEqual(r.certified, c["certified"])
            self.assertGreater(r.times["total"], 0.0)
            self.assertTrue(r.staircase and r.staircase[0]["rank"] == (2 if isinstance(g, keel.Graph2D) else 3))
            self.assertIn("isotropic", r.problem)
        with self.assertRaisesRegex(ValueError, "gap_tolerance"):
            keel.solve(keel.read_graph(self.file2d), certify=True, gap_tolerance=0.0)
        for bad in (0.0, -1.0, float("inf"), float("nan")):
            with self.assertRaisesRegex(ValueError, "time_limit_s must be a finite number of seconds > 0"):
                keel.solve(keel.read_graph(self.file2d), certify=True, time_limit_s=bad)
        # An argument of the other mode is refused, never ignored; its default passes.
        g2 = keel.read_graph(self.file2d)
        for kw in ({"init": "as-read"}, {"robust": "huber"}, {"robust_param": 2.0}, {"seed": 3}, {"threads": 2},
                   {"max_iterations": 5}):
            with self.subTest(**kw), self.assertRaisesRegex(ValueError, f"^solve: {next(iter(kw))} does not apply "
                                                                        "with certify=True"):
                keel.solve(g2, certify=True, **kw)
        for bad in (-1e-3, 1.0, float("nan")):
            with self.assertRaisesRegex(ValueError, "staircase_stationarity must be in"):
                keel.solve(keel.read_graph(self.file2d), certify=True, staircase_stationarity=bad)
            with self.assertRaisesRegex(ValueError, "staircase_relative_decrease must be in"):
                keel.solve(keel.read_graph(self.file2d), certify=True, staircase_relative_decrease=bad)
        with self.assertRaisesRegex(ValueError, "preconditioner: unknown pgo::TrustRegionPreconditioner 'schur'"):
            keel.solve(keel.read_graph(self.file2d), certify=True, preconditioner="schur")
        for kw in ({"gap_tolerance": 1e-5}, {"max_rank": 4}, {"time_limit_s": 10.0},
                   {"staircase_stationarity": 0.0}, {"staircase_relative_decrease": 1e-7},
                   {"preconditioner": "joint"}):
            with self.subTest(**kw), self.assertRaisesRegex(ValueError, f"^solve: {next(iter(kw))} applies only "
                                                                        "with certify=True"):
                keel.solve(g2, **kw)
        self.assertEqual(keel.solve(g2, certify=True, init="odometry", threads=1).cost,
                         keel.solve(g2, certify=True).cost)
        self.assertEqual(keel.solve(g2, gap_tolerance=1e-6, max_rank=10).cost, keel.solve(g2).cost)
        # A limit that passes before the first iteration: the chordal estimate, tested as it is, says so.
        r = keel.solve(keel.read_graph(self.file3d), certify=True, time_limit_s=1e-9)
        self.assertEqual(r.termination, "time_limit")
        self.assertEqual(r.iterations, 0)
        self.assertFalse(r.certified)
        self.assertIn("tcg_iterations", r.staircase[0])

    def test_records_match_the_command(self):
        """keel.solve's summary and certificate dicts and `keel solve --json` walk one field list
        (app/records.hpp): the same names, and the same values except wall times."""
        exe = os.environ.get("KEEL")
        if not exe:
            self.skipTest("KEEL (the keel command) not set")
        for path in (self.file2d, self.file3d):
            with self.subTest(path=path):
                g = keel.read_graph(path)
                cli = json.loads(subprocess.run([exe, "solve", path, "--certify", "--json", "-q"], check=True,
                                                capture_output=True, text=True).stdout)
                c = keel.solve(g, certify=True).certificate
                self.assertEqual(sorted(c), sorted(cli["certificate"]))
                self.assertEqual(sorted(c["times_s"]), sorted(cli["certificate"]["times_s"]))
                self.assertEqual(strip_times(c), strip_times(cli["certificate"]))
                cli = json.loads(subprocess.run([exe, "solve", path, "--json", "-q"], check=True,
                                                capture_output=True, text=True).stdout)
                s = keel.solve(g).summary
                self.assertEqual(sorted(s), sorted(cli["summary"]))
                self.assertEqual(strip_times(s), strip_times(cli["summary"]))
                self.assertIn("normalized_chi2", s)

    def test_robust_matches_the_command(self):
        """keel.robust and `keel robust --json` write one record (app/records.hpp): the same fields and the same
        values, wall times aside. Ten wrong closures (random pose pairs, measurements anywhere within 3 m and any
        heading) are added to Manhattan's first 200 poses."""
        exe = os.environ.get("KEEL")
        if not exe:
            self.skipTest("KEEL (the keel command) not set")
        g = keel.read_graph(self.file2d)
        rng = np.random.default_rng(3)
        n, extra = len(g.poses), 10
        pairs = []
        while len(pairs) < extra:
            i, j = (int(v) for v in rng.integers(0, n, 2))
            if abs(i - j) > 1:
                pairs.append((i, j))
        meas = np.column_stack([rng.uniform(-3, 3, extra), rng.uniform(-3, 3, extra),
                                rng.uniform(-np.pi, np.pi, extra)])
        wrong = keel.Graph2D(g.poses, np.vstack([g.edges, pairs]), np.vstack([g.measurements, meas]),
                             np.concatenate([g.information, np.repeat(g.information[-1:], extra, axis=0)]))
        path = os.path.join(self.tmp.name, "manhattan200_wrong.g2o")
        keel.write_graph(wrong, path)
        # The defaults, data snooping, and GNC after the selection and alone, each by the command and the module.
        for args, kwargs in (([], {}), (["--residual-test", "snooping"], {"residual_test": "snooping"}),
                             (["--residual-test", "groups", "--group-window", "3"],
                              {"residual_test": "groups", "group_window": 3}),
                             (["--first-solve", "rank-d"], {"first_solve": "rank-d"}),
                             (["--gnc", "after"], {"gnc": "after"}),
                             (["--gnc", "only", "--gnc-inner", "local"], {"gnc": "only", "gnc_inner": "local"})):
            with self.subTest(args=args):
                r = subprocess.run([exe, "robust", path, "--json", "-q", *args], capture_output=True, text=True)
                cli = json.loads(r.stdout)
                py = keel.robust(keel.read_graph(path), **kwargs)
                self.assertEqual(r.returncode, 0 if py["certificate"]["certified"] else 1, r.stderr)
                self.assertEqual(cli.pop("files"), [path])
                self.assertIsNone(cli.pop("candidates_file"))
                self.assertEqual(py.pop("solution").shape, (n, 3))
                self.assertIsInstance(py.pop("graph"), keel.Graph2D)
                self.assertEqual(sorted(py), sorted(cli))
                self.assertEqual(strip_times(py), strip_times(cli))
                self.assertEqual(py["candidates"], len(g.edges) - (n - 1) + extra)
                kept_wrong = [c for c in py["candidate_list"] if c["edge"] >= len(g.edges) and c["kept"]]
                self.assertEqual(kept_wrong, [])
        with self.assertRaisesRegex(ValueError, "gnc_inner must be"):
            keel.robust(g, gnc="after", gnc_inner="exact")
        with self.assertRaisesRegex(ValueError, "unknown merge::RobustGnc"):
            keel.robust(g, gnc="before")
        with self.assertRaisesRegex(ValueError, "p must be in"):
            keel.robust(g, p=1.5)
        with self.assertRaisesRegex(ValueError, "first_solve must be 'staircase' or 'rank-d'"):
            keel.robust(g, first_solve="rank-2")
        with self.assertRaisesRegex(ValueError, "group_window must be >= 1"):
            keel.robust(g, residual_test="groups", group_window=0)
        with self.assertRaisesRegex(ValueError, "unknown merge::RobustSelector"):
            keel.robust(g, selector="best")

    def test_refuses_non_integer_ids_and_non_finite_poses(self):
        g = keel.read_graph(self.file2d)
        with self.assertRaisesRegex(TypeError, "pairs must hold integer pose ids"):
            keel.marginals(g, pairs=np.array([[0.0, 5.7]]))
        with self.assertRaisesRegex(ValueError, "non-finite"):
            keel.SE2(float("nan"), 0.0, 0.0)
        with self.assertRaisesRegex(ValueError, "non-finite"):
            keel.SE3.exp(np.array([0, 0, 0, float("inf"), 0, 0]))

    def test_consistency_and_pcm(self):
        ref = reference("consistency", self.file_a, self.file_b, self.file_c)
        a, b = keel.read_graph(self.file_a), keel.read_graph(self.file_b)
        c = keel.read_candidates(self.file_c)
        Q = keel.consistency_matrix(a, b, c)
        np.testing.assert_array_equal(Q, np.array(ref["q"]))
        np.testing.assert_array_equal(keel.consistency_matrix(a, b, c, threads=2), Q)
        sel = keel.pcm_select(Q)
        self.assertEqual(sel.gamma, keel.consistency_threshold(0.11, 3))
        self.assertEqual(sel.status, "optimal")
        n = Q.shape[0]
        self.assertTrue(set(range(self.num_inliers, n)).isdisjoint(sel.selected))  # the outliers
        self.assertGreaterEqual(len(sel.selected), self.num_inliers - 2)
        adjacency = (Q <= sel.gamma) & (Q.T <= sel.gamma)
        clique = keel.max_clique(adjacency)
        self.assertEqual(clique.clique, sel.selected)
        self.assertEqual(clique.upper_bound, len(sel.selected))
        self.assertEqual(clique.gap, 0)
        self.assertEqual(sel.gap, 0)
        heur = keel.pcm_select(Q, algorithm="heuristic")
        self.assertEqual(heur.gap, heur.upper_bound - len(heur.selected))
        self.assertLessEqual(len(heur.selected), len(sel.selected))

    def test_round_trips(self):
        g = keel.read_graph(self.file2d)
        self.assertIsInstance(g, keel.Graph2D)
        self.assertIsInstance(keel.read_graph(self.file3d), keel.Graph3D)
        with self.assertRaises(keel.ParseError):
            keel.read_graph(self.file3d, dim=2)
        out = os.path.join(self.tmp.name, "copy.txt")  # iSAM text
        keel.write_graph(g, out, poses=g.poses + 1.0)
        h = keel.read_graph(out)
        np.testing.assert_array_equal(h.edges, g.edges)
        np.testing.assert_allclose(h.measurements, g.measurements, rtol=0, atol=1e-15)
        np.testing.assert_allclose(h.information, g.information, rtol=1e-12)
        c = keel.read_candidates(self.file_c)
        self.assertEqual(c.dim, 2)
        c2 = os.path.join(self.tmp.name, "c2.g2o")
        keel.write_candidates(c, c2)
        np.testing.assert_array_equal(keel.read_candidates(c2).information, c.information)
        g.poses = np.zeros((200, 3))
        np.testing.assert_array_equal(g.poses, np.zeros((200, 3)))
        with self.assertRaises(ValueError):
            g.poses = np.zeros((3, 3))


class TestAlign(unittest.TestCase):
    """keel.align on a survey pair built here with numpy: a smooth two-component field, a 30 m reference
    lawn-mower and a 12 m query rotated and translated by a known transform, no noise."""

    @staticmethod
    def field(x, y):
        return np.stack([np.sin(x / 3.0) + np.cos(y / 4.0), np.cos((x + y) / 5.0) * np.sin(y / 2.5)], axis=1)

    def survey(self):
        gx, gy = np.meshgrid(np.arange(0.0, 30.0 + 1e-9, 1.0), np.arange(0.0, 30.0 + 1e-9, 2.0))
        ref = np.stack([gx.ravel(), gy.ravel()], axis=1)
        qx, qy = np.meshgrid(np.arange(0.0, 12.0 + 1e-9, 1.0), np.arange(0.5, 12.0, 2.0))
        q_ref = np.stack([qx.ravel() + 9.0, qy.ravel() + 9.0], axis=1)  # the query's positions, reference frame
        theta, t = 0.6, np.array([4.0, -3.0])  # p_ref = R(theta) p_query + t
        c, s = math.cos(theta), math.sin(theta)
        R = np.array([[c, -s], [s, c]])
        q = (q_ref - t) @ R  # R^T (p_ref - t), row-wise
        return ref, self.field(ref[:, 0], ref[:, 1]), q, self.field(q_ref[:, 0], q_ref[:, 1]), theta, t

    def test_recovers_the_transform_and_reports_every_round(self):
        ref, fr, q, fq, theta, t = self.survey()
        r = keel.align(ref, fr, q, fq)
        self.assertEqual(r["A"].shape, (2, 2))
        self.assertLess(abs(math.remainder(r["theta"] - theta, 2 * math.pi)), 0.05)
        centroid = q.mean(axis=0)
        c, s = math.cos(theta), math.sin(theta)
        truth = np.array([[c, -s], [s, c]]) @ centroid + t
        self.assertLess(np.linalg.norm(r["A"] @ centroid + r["t"] - truth), 0.5)
        self.assertGreaterEqual(len(r["rounds"]), 2)
        np.testing.assert_array_equal(r["rounds"][-1]["A"], r["A"])
        self.assertIsNone(r["certificate"])
        # The answer does not depend on the thread count; the certificate brackets round 0's objective.
        r2 = keel.align(ref, fr, q, fq, threads=2, certify=True)
        np.testing.assert_array_equal(r2["A"], r["A"])
        self.assertEqual(r2["certificate"]["status"], "optimal")
        self.assertLessEqual(r2["certificate"]["lower_bound"], r2["certificate"]["upper_bound"])

    def test_bit_identical_to_keel_align(self):
        """A Table 3.1 world written by `keel align-world`: keel.align on its arrays and `keel align` on its files
        give the same transform, every digit (KEEL names the command, as CTest sets it)."""
        exe = os.environ.get("KEEL")
        if not exe:
            self.skipTest("KEEL (the keel command) not set")
        with tempfile.TemporaryDirectory() as d:
            subprocess.run([exe, "align-world", d, "--index", "2", "-q"], check=True, capture_output=True)
            ref = np.loadtxt(os.path.join(d, "reference.csv"), delimiter=",", skiprows=1)
            q = np.loadtxt(os.path.join(d, "query.csv"), delimiter=",", skiprows=1)
            for method in ("proposed", "so_conv_hull"):
                r = keel.align(ref[:, :2], ref[:, 2:], q[:, :2], q[:, 2:], method=method)
                cli = json.loads(subprocess.run(
                    [exe, "align", os.path.join(d, "reference.csv"), os.path.join(d, "query.csv"), "--method", method,
                     "--json", "-q"], check=True, capture_output=True, text=True).stdout)
                T = cli["transform"]
                np.testing.assert_array_equal(r["A"], [[T["a11"], T["a12"]], [T["a21"], T["a22"]]])
                np.testing.assert_array_equal(r["t"], [T["tx"], T["ty"]])
                self.assertEqual(r["cost"], cli["cost"])

    def test_bad_input(self):
        ref, fr, q, fq, _, _ = self.survey()
        with self.assertRaisesRegex(ValueError, "reference has 2 feature columns, query has 1"):
            keel.align(ref, fr, q, fq[:, 0])
        bad = fq.copy()
        bad[4, 1] = np.nan
        with self.assertRaisesRegex(ValueError, "query: feature of position 4 column 1 is not finite"):
            keel.align(ref, fr, q, bad)
        with self.assertRaisesRegex(ValueError, r"positions must be an \(n, 2\) or \(n, 3\) array"):
            keel.align(ref[:, 0], fr, q, fq)
        with self.assertRaisesRegex(ValueError, "unknown align::Method 'rigid'"):
            keel.align(ref, fr, q, fq, method="rigid")


class TestErrors(unittest.TestCase):
    def test_parse_error(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "bad.g2o")
            with open(path, "w") as f:
                f.write("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 abc\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n")
            with self.assertRaises(keel.ParseError) as cm:
                keel.read_graph(path)
            e = cm.exception
            self.assertIsInstance(e, ValueError)
            self.assertRegex(str(e), "^" + re.escape(path) + r":2: VERTEX_SE2 field 4 \(theta\): ")
            self.assertEqual((e.file, e.line), (path, 2))
            with self.assertRaises(keel.ParseError):
                keel.read_candidates(path)
            with self.assertRaises(keel.ParseError) as cm:
                keel.read_graph(os.path.join(d, "missing.g2o"))
            self.assertEqual(cm.exception.line, 0)

    def test_enum_and_range_errors(self):
        g = keel.Graph2D([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1], [1, 2]], [[1, 0, 0], [1, 0, 0]])
        with self.assertRaises(ValueError) as cm:
            keel.solve(g, init="lm")
        self.assertTrue(str(cm.exception).startswith("unknown pgo::InitialGuess 'lm' (valid: "), str(cm.exception))
        with self.assertRaisesRegex(ValueError, "unknown pgo::RobustKernel"):
            keel.solve(g, robust="tukey")
        for init in ("as_read", "as-read", "odometry", "random"):
            self.assertEqual(keel.solve(g, init=init).termination, "converged")
        # ids out of range are IndexError (the module checks pairs before the engine's pair_marginals_2d)
        with self.assertRaisesRegex(IndexError, r"marginals: pairs\[0, 1\] = 3 is not a pose id"):
            keel.marginals(g, pairs=[(0, 3)])
        with self.assertRaises(IndexError):
            keel.marginals(g, ids=[5])
        with self.assertRaises(ValueError):
            keel.marginals(g)
        with self.assertRaises(ValueError):
            keel.pcm_select(np.zeros((2, 3)))
        with self.assertRaisesRegex(ValueError, "unknown"):
            keel.max_clique(np.eye(3, dtype=bool), algorithm="fast")
        with self.assertRaises(ValueError):
            keel.max_clique(np.triu(np.ones((3, 3))))


class TestGauge(unittest.TestCase):
    """A graph's gauge_pose (g2o's FIX k): solve holds pose k at its given value, marginals report it fixed."""

    def graph(self):
        poses = [[0.0, 0.0, 0.0], [1.0, 0.1, 1.6], [1.1, 1.0, 3.1], [0.1, 1.1, -1.5]]
        edges = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]]
        meas = [[1.0, 0.05, 1.55], [1.02, -0.03, 1.6], [0.97, 0.02, 1.54], [1.01, 0.0, 1.58], [1.4, 1.38, 3.1]]
        return keel.Graph2D(poses, edges, meas)

    def test_gauge_pose(self):
        g = self.graph()
        self.assertEqual(g.gauge_pose, 0)
        with self.assertRaisesRegex(IndexError, r"Graph2D.gauge_pose: pose 4 is not in the graph \(4 poses"):
            g.gauge_pose = 4
        with self.assertRaises(TypeError):
            g.gauge_pose = 1.5
        g0 = g.copy()
        g.gauge_pose = 2
        self.assertEqual(g.copy().gauge_pose, 2)
        r0, r = keel.solve(g0), keel.solve(g)
        np.testing.assert_array_equal(r.poses[2], g.poses[2])  # held to the last bit
        self.assertGreater(np.abs(r.poses[0] - g.poses[0]).max(), 1e-6)
        # The same optimum up to the stopping rule (|cost change| / cost <= 1e-6 per step) of both runs.
        self.assertAlmostEqual(r.cost / r0.cost, 1.0, delta=1e-5)
        c0, c = keel.solve(g0, certify=True), keel.solve(g, certify=True)
        np.testing.assert_array_equal(c.poses[2], g.poses[2])
        self.assertEqual(c.certificate["lower_bound"], c0.certificate["lower_bound"])
        self.assertEqual(c.cost, c0.cost)
        cov = keel.marginals(g, r0.poses, ids=[2, 1])
        self.assertEqual(np.abs(cov[:3, :]).max(), 0.0)
        self.assertGreater(cov[3, 3], 0.0)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "fix.g2o")
            keel.write_graph(g, path)
            self.assertEqual(keel.read_graph(path).gauge_pose, 2)
            with self.assertRaisesRegex(ValueError, "iSAM text cannot record"):
                keel.write_graph(g, os.path.join(d, "fix.txt"))


class TestDocs(unittest.TestCase):
    def test_every_public_name_has_a_docstring(self):
        self.assertTrue(keel.__doc__.strip())
        missing = []
        for name in dir(keel):
            if name.startswith("_"):
                continue
            obj = getattr(keel, name)
            if not (obj.__doc__ or "").strip():
                missing.append(name)
            if isinstance(obj, type) and not issubclass(obj, Exception):
                for attr, value in vars(obj).items():
                    # pybind11 starts a method's docstring with its signature: ask for text after it
                    lines = [l for l in (getattr(value, "__doc__", None) or "").splitlines() if l.strip()]
                    if not attr.startswith("_") and len(lines) < (1 if isinstance(value, property) else 2):
                        missing.append(f"{name}.{attr}")
        self.assertEqual(missing, [])


if __name__ == "__main__":
    unittest.main()
