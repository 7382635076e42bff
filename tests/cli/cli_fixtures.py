"""What the tests of the `keel` command share (tests/cli/test_*.py): the binary under test and the small graphs
several of them write.

KEEL is the binary (CTest sets $KEEL; by hand, build/release/keel of this checkout).
"""
import itertools
import os

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
KEEL = os.path.abspath(os.environ.get("KEEL", os.path.join(REPO, "build", "release", "keel")))

# A synthetic 8-pose square: two laps, two loop closures, one information with cross terms.
SQUARE = (
    '# a synthetic 8-pose square (tests/cli): two laps, two loop closures\n'
    'VERTEX_SE2 0 0.000000 0.000000 0.000000\n'
    'VERTEX_SE2 1 2.100000 -0.050000 1.590796\n'
    'VERTEX_SE2 2 2.200000 1.900000 3.181593\n'
    'VERTEX_SE2 3 0.300000 1.850000 -1.510796\n'
    'VERTEX_SE2 4 0.450000 -0.180000 0.090000\n'
    'VERTEX_SE2 5 2.530000 -0.290000 1.690796\n'
    'VERTEX_SE2 6 2.580000 1.710000 3.251593\n'
    'VERTEX_SE2 7 0.720000 1.620000 -1.430796\n'
    'EDGE_SE2 0 1 2.010000 -0.020000 1.575796 100 0 0 100 0 400\n'
    'EDGE_SE2 1 2 1.985000 0.010000 1.566796 100 0 0 100 0 400\n'
    'EDGE_SE2 2 3 2.020000 0.000000 1.573796 100 0 0 100 0 400\n'
    'EDGE_SE2 3 4 1.980000 0.062000 1.574796 100 20 0 80 5 400\n'
    'EDGE_SE2 4 5 1.969301 -0.089797 1.582796 100 0 0 100 0 400\n'
    'EDGE_SE2 5 6 2.055590 0.028993 1.544796 100 0 0 100 0 400\n'
    'EDGE_SE2 6 7 1.969502 0.059598 1.577796 100 0 0 100 0 400\n'
    'EDGE_SE2 0 4 0.080000 0.010000 0.014000 50 0 0 50 0 200\n'
    'EDGE_SE2 2 6 0.000000 0.010000 -0.015000 50 0 0 50 0 200\n'
)

# The rotation angles of sos::exactness_counterexample (K4, rotation-only, unit weights), the counterexample to
# the exactness claim of Theorems 4.5.3-4.5.4: its SDP relaxation is not tight.
K4_ANGLES = [0.23, 0.43, 1.13, -1.81, 1.36, -1.35]


def complete_graph(n, angles):
    """g2o text of the complete graph on n poses (vertices at the origin), edge (i, j) in lexicographic order
    measuring rotation angles[k] and no translation, information diag(1, 1, 2) (κ = 2, τ = 1)."""
    lines = [f"VERTEX_SE2 {i} 0 0 0" for i in range(n)]
    for (i, j), t in zip(itertools.combinations(range(n), 2), angles):
        lines.append(f"EDGE_SE2 {i} {j} 0 0 {t!r} 1 0 0 1 0 2")
    return "\n".join(lines) + "\n"
