"""Bad input to the Python module keel is refused with the documented exception, and a message that names the
function and the argument; run by CTest as `python.errors`:

    PYTHONPATH=build/release/python /usr/bin/python3 -m unittest -v test_errors      (from tests/python)

The exception types (keel.__doc__, docs/USING.md): TypeError for a wrong type (ids are integers: a float array
is refused even when its values are integral, so nothing is truncated), ValueError for a refused value,
IndexError for an id out of range, OverflowError for an integer beyond the engine's int range, ParseError (a
ValueError) for a malformed file, DatasetError (a RuntimeError) for a missing data set, FloatingPointError (an
ArithmeticError) for a result that would hold NaN or infinity, RuntimeError for other numerical failures.
"""

import math
import os
import re
import tempfile
import unittest

import numpy as np

import keel

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

POSES = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
Z = [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]


def chain(poses=POSES, edges=((0, 1), (1, 2)), z=Z, information=None):
    return keel.Graph2D(poses, np.array(edges, dtype=np.int64), z, information)


def chain3():
    poses = [[float(k), 0.0, 0.0, 0.0, 0.0, 0.0, 1.0] for k in range(3)]
    z = [[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]] * 2
    return poses, z


class FloatIds(unittest.TestCase):
    """Ids are never truncated: [[0.0, 1.7]] was edge 0-1."""

    def test_graph_edges(self):
        with self.assertRaisesRegex(TypeError, r"^Graph2D: edges must hold integer pose ids \(got an array of "
                                               r"dtype float64"):
            keel.Graph2D(POSES, [[0.0, 1.7], [1.0, 2.0]], Z)
        # integral floats are refused too (one rule: ids have an integer dtype)
        with self.assertRaisesRegex(TypeError, "Graph2D: edges must hold integer pose ids"):
            keel.Graph2D(POSES, np.array([[0.0, 1.0], [1.0, 2.0]]), Z)
        poses3, z3 = chain3()
        with self.assertRaisesRegex(TypeError, "Graph3D: edges must hold integer pose ids"):
            keel.Graph3D(poses3, [[0.0, 1.7], [1.0, 2.0]], z3)

    def test_candidates(self):
        with self.assertRaisesRegex(TypeError, "Candidates: edges must hold integer pose ids"):
            keel.Candidates([[0.0, 1.7]], [[1.0, 0.0, 0.0]])
        with self.assertRaisesRegex(TypeError, "Candidates: edges must hold integer pose ids"):
            keel.Candidates([[True, False]], [[1.0, 0.0, 0.0]])

    def test_marginal_pairs_and_ids(self):
        g = chain()
        with self.assertRaisesRegex(TypeError, r"^marginals: pairs must hold integer pose ids"):
            keel.marginals(g, pairs=[[0.0, 1.7]])
        with self.assertRaisesRegex(TypeError, r"^marginals: ids must hold integer variable ids \(got an array of "
                                               r"dtype float64"):
            keel.marginals(g, ids=[1, 0.5])
        with self.assertRaisesRegex(TypeError, r"^MarginalCovariance.joint: ids must hold integer variable ids"):
            keel.MarginalCovariance(g).joint(np.array([1.0, 2.0]))

    def test_integer_arrays_of_every_width_still_work(self):
        for dtype in (np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64):
            g = keel.Graph2D(POSES, np.array([[0, 1], [1, 2]], dtype=dtype), Z)
            np.testing.assert_array_equal(g.edges, [[0, 1], [1, 2]])
            c = keel.Candidates(np.array([[4, 4]], dtype=dtype), [[1.0, 0.0, 0.0]])
            np.testing.assert_array_equal(c.edges, [[4, 4]])
            m = keel.marginals(g, pairs=np.array([[1, 2]], dtype=dtype))
            self.assertEqual(m.shape, (1, 6, 6))
            self.assertEqual(keel.marginals(g, ids=np.array([2], dtype=dtype)).shape, (3, 3))
        # Python ints, lists and numpy integer scalars
        self.assertEqual(keel.marginals(chain(), ids=[np.int64(1), 2]).shape, (6, 6))
        self.assertEqual(len(keel.Candidates([], np.zeros((0, 3)))), 0)


class WrongTypes(unittest.TestCase):
    """A TypeError naming the argument and the expected type, never pybind11's "Unable to cast"."""

    def assertTypeError(self, pattern, f, *args, **kwargs):
        with self.assertRaises(TypeError) as cm:
            f(*args, **kwargs)
        self.assertRegex(str(cm.exception), pattern)
        self.assertNotIn("Unable to cast", str(cm.exception))

    def test_scalars(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "g.g2o")
            keel.write_graph(chain(), path)
            self.assertTypeError(r"^read_graph: dim must be an integer \(got str '3'\)", keel.read_graph, path,
                                 dim="3")
            self.assertTypeError(r"^read_graph: dim must be an integer \(got float 2.0\)", keel.read_graph, path,
                                 dim=2.0)
            self.assertTypeError(r"^read_candidates: dim must be an integer", keel.read_candidates, path, dim=True)
            self.assertTypeError(r"^read_poses: dim must be an integer", keel.read_poses, path, dim=2.5)
        self.assertTypeError(r"^pcm_select: dof must be an integer \(got float", keel.pcm_select, np.zeros((2, 2)),
                             dof=3.0)
        self.assertTypeError(r"^consistency_threshold: dof must be an integer \(got bool True\)",
                             keel.consistency_threshold, 0.1, True)

    def test_counts_seeds_and_threads(self):
        g = chain()
        self.assertTypeError(r"^solve: max_iterations must be an integer \(got float 2.5\)", keel.solve, g,
                             max_iterations=2.5)
        self.assertTypeError(r"^solve: max_rank must be an integer \(got bool True\)", keel.solve, g, certify=True,
                             max_rank=True)
        self.assertTypeError(r"^solve: seed must be an integer >= 0 \(got float", keel.solve, g, seed=1.0)
        self.assertTypeError(r"^marginals: threads must be an integer >= 0 \(got float 1.0\)", keel.marginals, g,
                             ids=[1], threads=1.0)
        self.assertTypeError(r"^MarginalCovariance.pairs: threads must be an integer >= 0 \(got str",
                             keel.MarginalCovariance(g).pairs, [(1, 2)], threads="2")
        self.assertTypeError(r"^consistency_matrix: threads must be an integer >= 0 \(got NoneType",
                             keel.consistency_matrix, g, g, keel.Candidates([[0, 1]], [[1.0, 0.0, 0.0]]),
                             threads=None)
        self.assertTypeError(r"^align: rounds must be an integer \(got float 2.0\)", keel.align,
                             np.zeros((5, 2)), np.zeros(5), np.zeros((3, 2)), np.zeros(3), rounds=2.0)
        with self.assertRaisesRegex(OverflowError, r"^solve: threads = -1 is outside 0 … 4294967295"):
            keel.solve(g, threads=-1)
        with self.assertRaisesRegex(OverflowError, r"^solve: seed = 18446744073709551616 is outside 0 … "
                                                   r"18446744073709551615"):
            keel.solve(g, seed=2**64)
        self.assertEqual(keel.solve(g, seed=np.uint64(2**64 - 1), init="random").termination, "converged")

    def test_arrays(self):
        self.assertTypeError(r"^Graph2D: 2D poses must be a float array \(got str", keel.Graph2D, "abc",
                             [[0, 1]], [[1, 0, 0]])
        self.assertTypeError(r"^Graph2D \(measurements\): 2D poses must be a float array \(got list of dtype "
                             r"object", keel.Graph2D, POSES, [[0, 1]], [[1, 0, None]])
        self.assertTypeError(r"^Graph2D: information must be a float array", keel.Graph2D, POSES, [[0, 1]],
                             [[1, 0, 0]], [[["a"] * 3] * 3])
        self.assertTypeError(r"^marginals: ids must hold integer variable ids \(got an array of dtype <U1",
                             keel.marginals, chain(), ids=["a"])
        self.assertTypeError(r"^marginals: ids\[1\] must be an integer variable id \(got NoneType", keel.marginals,
                             chain(), ids=[1, None])
        self.assertTypeError(r"^marginals: pairs must be an integer array or a sequence of integers \(got "
                             r"|^marginals: pairs\[0, 0\] must be an integer pose id", keel.marginals, chain(),
                             pairs=[[None, 1]])
        self.assertTypeError(r"^SE3: rotation must be a float array of shape \(3, 3\) \(got str", keel.SE3,
                             rotation="x")
        self.assertTypeError(r"^SE3: translation must be a float array of shape \(3,\)", keel.SE3,
                             translation=[1, 2])
        self.assertTypeError(r"^pcm_select: Q must be a float array \(got str", keel.pcm_select, "abc")
        self.assertTypeError(r"^max_clique: adjacency must be an \(n, n\) array of bool or 0/1 \(got str",
                             keel.max_clique, "ab")
        self.assertTypeError(r"^reference: positions must be a float array", keel.align, "xy", [1.0], [[0, 0]],
                             [1.0])
        joint = keel.JointPosesSE2.independent([keel.UncertainSE2.known(keel.SE2())] * 2)
        self.assertTypeError(r"^JointPosesSE2.marginal: i must be an integer \(got float", joint.marginal, 1.0)
        self.assertTypeError(r"^solve: graph must be a keel.Graph2D or keel.Graph3D", keel.solve, "g.g2o")
        self.assertTypeError(r"^solve \(init\): 2D poses must be a float array \(got NoneType", keel.solve,
                             chain(), init=None)


class IdsOutOfRange(unittest.TestCase):
    """IndexError, as docs/USING.md says (a pair beyond the graph was a ValueError)."""

    def test_marginal_pairs(self):
        g = chain()
        with self.assertRaisesRegex(IndexError, re.escape("marginals: pairs[0, 1] = 3 is not a pose id (the graph "
                                                          "has 3 poses: 0 … 2)")):
            keel.marginals(g, pairs=[(0, 3)])
        with self.assertRaisesRegex(IndexError, re.escape("marginals: pairs[1, 0] = -1 is not a pose id")):
            keel.marginals(g, pairs=[(0, 1), (-1, 1)])
        with self.assertRaises(IndexError):
            keel.MarginalCovariance(g).pairs([(2, 7)])
        with self.assertRaisesRegex(IndexError, re.escape("marginals: ids[0] = -2 is not a variable id")):
            keel.marginals(g, ids=[-2])
        with self.assertRaises(IndexError):
            keel.marginals(g, ids=[5])

    def test_candidates_beyond_the_graphs(self):
        g = chain()
        with self.assertRaisesRegex(IndexError, re.escape("consistency_matrix: candidates.edges[0, 1] = 5 is not a "
                                                          "pose of graph_b (it has 3 poses)")):
            keel.consistency_matrix(g, g, keel.Candidates([[0, 5]], [[1.0, 0.0, 0.0]]))

    def test_graph_edges_and_joint_poses(self):
        with self.assertRaisesRegex(IndexError, re.escape("Graph2D: edges[1, 1] = 3 is not a pose id (the graph "
                                                          "has 3 poses: 0 … 2)")):
            chain(edges=((0, 1), (1, 3)))
        with self.assertRaisesRegex(IndexError, re.escape("Candidates: edges[0, 0] = -1 is not a pose id")):
            keel.Candidates([[-1, 0]], [[1.0, 0.0, 0.0]])
        joint = keel.JointPosesSE2.independent([keel.UncertainSE2.known(keel.SE2())] * 2)
        with self.assertRaisesRegex(IndexError, re.escape("JointPosesSE2.marginal: i = 2 is out of range (0 … 1)")):
            joint.marginal(2)
        with self.assertRaisesRegex(IndexError, "JointPosesSE2.between: k = -1 is out of range"):
            joint.between(0, -1)


class IdsBeyondTheEngine(unittest.TestCase):
    """OverflowError naming the argument; the number printed as given (2**63 printed as a negative number)."""

    def test_uint64_and_big_ints(self):
        big = np.array([[2**63, 1], [1, 2]], dtype=np.uint64)
        with self.assertRaises(OverflowError) as cm:
            keel.Graph2D(POSES, big, Z)
        self.assertEqual(str(cm.exception), "Graph2D: edges[0, 0] = 9223372036854775808 is beyond the largest "
                                            "pose id the engine holds (2147483647)")
        with self.assertRaisesRegex(OverflowError, r"^Candidates: edges\[0, 1\] = 18446744073709551615 is beyond"):
            keel.Candidates(np.array([[0, 2**64 - 1]], dtype=np.uint64), [[1.0, 0.0, 0.0]])
        with self.assertRaisesRegex(OverflowError, r"^marginals: pairs\[0, 0\] = 1180591620717411303424 is beyond"):
            keel.marginals(chain(), pairs=[[2**70, 1]])
        with self.assertRaisesRegex(OverflowError, r"^marginals: pairs\[0, 1\] = 2147483648 is beyond"):
            keel.marginals(chain(), pairs=np.array([[0, 2**31]]))
        with self.assertRaisesRegex(OverflowError, r"^marginals: pairs\[0, 1\] = -2147483649 is beyond"):
            keel.marginals(chain(), pairs=np.array([[0, -2**31 - 1]]))
        with self.assertRaisesRegex(OverflowError, r"^read_graph: dim = 4294967298 is beyond the C\+\+ int range"):
            keel.read_graph("g.g2o", dim=2**32 + 2)
        joint = keel.JointPosesSE2.independent([keel.UncertainSE2.known(keel.SE2())] * 2)
        with self.assertRaisesRegex(OverflowError, "JointPosesSE2.cross: j = 18446744073709551616 is beyond"):
            joint.cross(0, 2**64)

    def test_printing_never_goes_negative(self):
        for ids in (np.array([[2**63, 0]], dtype=np.uint64), np.array([[2**64 - 1, 0]], dtype=np.uint64)):
            with self.assertRaises(OverflowError) as cm:
                keel.Candidates(ids, [[1.0, 0.0, 0.0]])
            self.assertNotIn("-", str(cm.exception).split("=")[1])


class WriteGraph(unittest.TestCase):
    def test_more_poses_than_the_graph_is_refused_before_writing(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "g.g2o")
            with self.assertRaisesRegex(ValueError, re.escape("write_graph: poses has 4 rows but the graph has 3 "
                                                              "poses")):
                keel.write_graph(chain(), path, poses=POSES + [[3.0, 0.0, 0.0]])
            self.assertFalse(os.path.exists(path))
            with self.assertRaisesRegex(ValueError, "write_graph: poses has 2 rows but the graph has 3 poses"):
                keel.write_graph(chain(), path, poses=POSES[:2])
            self.assertFalse(os.path.exists(path))
            # the same number of poses is written and read back
            keel.write_graph(chain(), path, poses=np.array(POSES) + 0.5)
            np.testing.assert_array_equal(keel.read_graph(path).poses[:, :2], np.array(POSES)[:, :2] + 0.5)


class NonFiniteResults(unittest.TestCase):
    """A result holding NaN or infinity raises FloatingPointError (an ArithmeticError) instead of returning."""

    def test_marginals_at_huge_poses(self):
        g = chain()
        huge = np.array([[0.0, 0.0, 0.0], [1e308, 1e308, 0.0], [-1e308, 1e308, 1.0]])
        with self.assertRaises(ArithmeticError) as cm:
            keel.marginals(g, poses=huge, pairs=[(1, 2)])
        self.assertIsInstance(cm.exception, FloatingPointError)
        self.assertRegex(str(cm.exception), r"^marginals: the covariance of pairs\[0\] holds a non-finite number")
        with self.assertRaisesRegex(FloatingPointError, "^marginals: the joint covariance of ids holds a non-finite"):
            keel.marginals(g, poses=huge, ids=[1, 2])

    def test_pose_arithmetic(self):
        far = keel.SE2(1e308, 0.0, 0.0)
        with self.assertRaisesRegex(FloatingPointError, r"^SE2.__mul__: the result holds a non-finite number"):
            far * far
        with self.assertRaisesRegex(FloatingPointError, r"^SE2.compose: the result holds a non-finite number"):
            far.compose(far)
        with self.assertRaisesRegex(FloatingPointError, r"^SE2.act: the result holds a non-finite number"):
            far.act([1e308, 0.0])
        far3 = keel.SE3(translation=[1e308, 0.0, 0.0])
        with self.assertRaisesRegex(FloatingPointError, r"^SE3.between: the result holds a non-finite number"):
            far3.inverse().between(far3)
        with self.assertRaisesRegex(ValueError, "SE2.act: the input holds a non-finite number"):
            keel.SE2().act([float("nan"), 0.0])
        with self.assertRaisesRegex(ValueError, r"SE3.from_quaternion \(translation\): the input holds a non-finite"):
            keel.SE3.from_quaternion([float("nan"), 0.0, 0.0], [0.0, 0.0, 0.0, 1.0])
        with self.assertRaisesRegex(ValueError, "SE2.is_approx: tol must be a finite number >= 0 \(got nan\)"):
            keel.SE2().is_approx(keel.SE2(), tol=float("nan"))

    def test_marginals_poses_of_another_count(self):
        with self.assertRaisesRegex(ValueError, "marginals: poses has 2 rows but the graph has 3 poses"):
            keel.marginals(chain(), poses=POSES[:2], ids=[1])


class InformationMatrices(unittest.TestCase):
    """What read_graph refuses (an information matrix that is not positive definite) is refused here too."""

    def test_zero_information(self):
        with self.assertRaisesRegex(ValueError, re.escape("Graph2D: information[1] (edge 1 -> 2) is not positive "
                                                          "definite: diagonal entry (1,1) = 0 is not positive")):
            chain(information=[np.eye(3), np.zeros((3, 3))])
        poses3, z3 = chain3()
        with self.assertRaisesRegex(ValueError, r"Graph3D: information\[0\] \(edge 0 -> 1\) is not positive "
                                                r"definite"):
            keel.Graph3D(poses3, [[0, 1], [1, 2]], z3, np.zeros((2, 6, 6)))
        with self.assertRaisesRegex(ValueError, r"Candidates: information\[0\] \(edge 0 -> 0\) is not positive"):
            keel.Candidates([[0, 0]], [[1.0, 0.0, 0.0]], -np.eye(3)[None])
        singular = np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        with self.assertRaisesRegex(ValueError, r"information\[0\] \(edge 0 -> 1\) is not positive definite "
                                                r"\(smallest eigenvalue"):
            chain(information=[singular, np.eye(3)])
        with self.assertRaisesRegex(ValueError, r"Graph2D: information\[0\] \(edge 0 -> 1\) is not symmetric"):
            chain(information=[np.triu(np.ones((3, 3))) + np.eye(3), np.eye(3)])
        # what the reader accepts is accepted: a positive definite matrix, read back as written
        w = np.array([[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]])
        g = chain(information=[w, w])
        self.assertEqual(keel.solve(g).termination, "converged")

    def test_self_loop(self):
        with self.assertRaisesRegex(ValueError, re.escape("Graph2D: edges[1] = (1, 1) connects a pose to itself")):
            chain(edges=((0, 1), (1, 1)))


class Adjacency(unittest.TestCase):
    def test_nan_and_non_binary_entries(self):
        a = np.ones((3, 3))
        a[0, 1] = a[1, 0] = float("nan")
        with self.assertRaisesRegex(ValueError, re.escape("max_clique: adjacency[0, 1] = nan is neither 0 nor 1")):
            keel.max_clique(a)
        a[0, 1] = a[1, 0] = 0.5
        with self.assertRaisesRegex(ValueError, re.escape("max_clique: adjacency[0, 1] = 0.5 is neither 0 nor 1")):
            keel.max_clique(a)
        with self.assertRaisesRegex(ValueError, re.escape("max_clique: adjacency[0, 2] = 2 is neither 0 nor 1")):
            keel.max_clique(np.array([[0, 1, 2], [1, 0, 1], [2, 1, 0]]))
        with self.assertRaisesRegex(ValueError, "max_clique: adjacency must be a square"):
            keel.max_clique(np.ones((2, 3), dtype=bool))
        # bools, 0/1 integers and 0.0/1.0 floats are the same graph
        for m in (np.ones((3, 3), dtype=bool), np.ones((3, 3), dtype=np.int8), np.ones((3, 3))):
            self.assertEqual(keel.max_clique(m).clique, [0, 1, 2])

    def test_time_limit(self):
        for t in (float("nan"), 0.0, -1.0):
            with self.assertRaisesRegex(ValueError, "max_clique: time_limit_s must be > 0 seconds"):
                keel.max_clique(np.ones((3, 3), dtype=bool), time_limit_s=t)
            with self.assertRaisesRegex(ValueError, "pcm_select: time_limit_s must be > 0 seconds"):
                keel.pcm_select(np.zeros((2, 2)), time_limit_s=t)


class Version(unittest.TestCase):
    def test_version_and_commit(self):
        with open(os.path.join(REPO, "CMakeLists.txt")) as f:
            version = re.search(r"project\(keel VERSION ([0-9.]+)", f.read()).group(1)
        self.assertEqual(keel.__version__, version)
        self.assertRegex(keel.__git_commit__, r"^([0-9a-f]{12}(\+dirty)?|unknown)$")
        self.assertIn("__version__", keel.__doc__)


class DocumentedExceptions(unittest.TestCase):
    """One case per exception type that keel.__doc__ and docs/USING.md document, raised as documented."""

    def test_the_documentation_names_these_types(self):
        with open(os.path.join(REPO, "docs", "USING.md")) as f:
            text = f.read()
        python = text[text.index("## Python"):]
        for name in ("TypeError", "ValueError", "IndexError", "OverflowError", "keel.ParseError",
                     "keel.DatasetError", "FloatingPointError", "OSError", "RuntimeError"):
            self.assertIn(f"`{name}`", python)
            self.assertIn(name.replace("keel.", ""), keel.__doc__)

    def test_type_error(self):
        self.assertRaises(TypeError, keel.Graph2D, POSES, [[0.0, 1.0]], [[1, 0, 0]])

    def test_value_error(self):
        self.assertRaises(ValueError, keel.solve, chain(), init="lm")

    def test_index_error(self):
        self.assertRaises(IndexError, keel.marginals, chain(), pairs=[(0, 3)])

    def test_overflow_error(self):
        self.assertRaises(OverflowError, keel.marginals, chain(), pairs=[(0, 2**40)])

    def test_parse_error(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "bad.g2o")
            with open(path, "w") as f:
                f.write("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 abc\n")
            with self.assertRaises(keel.ParseError) as cm:
                keel.read_graph(path)
            self.assertIsInstance(cm.exception, ValueError)
            self.assertEqual((cm.exception.file, cm.exception.line), (path, 2))

    def test_dataset_error(self):
        with self.assertRaises(keel.DatasetError) as cm:
            keel.dataset_file("manhattan3500", "no/such/file.txt")
        self.assertIsInstance(cm.exception, RuntimeError)

    def test_floating_point_error(self):
        huge = np.array([[0.0, 0.0, 0.0], [1e308, 1e308, 0.0], [-1e308, 1e308, 1.0]])
        self.assertRaises(FloatingPointError, keel.marginals, chain(), poses=huge, ids=[1])

    def test_the_functions_docstrings(self):
        # what each function's docstring says it raises
        with self.assertRaisesRegex(ValueError, r"q\[0\]\[1\] = nan is NaN"):
            keel.pcm_select(np.array([[0.0, float("nan")], [float("nan"), 0.0]]))
        disconnected = keel.Graph2D(POSES, [[0, 1]], [[1.0, 0.0, 0.0]])
        with self.assertRaisesRegex(ValueError, "pose 2 .*not connected to pose 0"):
            keel.solve(disconnected)
        with self.assertRaisesRegex(ValueError, "pose 2 .*not connected to pose 0"):
            keel.solve(disconnected, certify=True)
        with self.assertRaisesRegex(ValueError, "unknown extension"):
            keel.write_graph(chain(), os.path.join(tempfile.gettempdir(), "keel-test.xyz"))
        with self.assertRaises(keel.ParseError) as cm:
            keel.read_graph(os.path.join(tempfile.gettempdir(), "keel-no-such-file.g2o"))
        self.assertEqual(cm.exception.line, 0)

    def test_os_error(self):
        with tempfile.TemporaryDirectory() as d:
            folder = os.path.join(d, "a.g2o")  # a folder where the file should go
            os.mkdir(folder)
            with self.assertRaisesRegex(OSError, re.escape(folder)):
                keel.write_graph(chain(), folder)
            with self.assertRaisesRegex(OSError, "cannot"):
                keel.write_candidates(keel.Candidates([[0, 1]], [[1.0, 0.0, 0.0]]),
                                      os.path.join(d, "no", "such", "folder", "c.g2o"))

    def test_runtime_error(self):
        # pose 2 is connected to nothing: the information matrix is singular there
        g = keel.Graph2D(POSES, [[0, 1]], [[1.0, 0.0, 0.0]])
        with self.assertRaises(RuntimeError) as cm:
            keel.marginals(g, ids=[2])
        self.assertNotIsInstance(cm.exception, keel.DatasetError)


if __name__ == "__main__":
    unittest.main()
