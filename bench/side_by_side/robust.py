#!/usr/bin/env python3
"""keel robust and Kimera-RPGO side by side on graphs with wrong loop closures added (bench/side_by_side/robust.sh).

For each data set, outlier rate and trial this writes one corrupted g2o file and runs both tools on it, one thread
each, timing each whole process (file reading and set-up included, the same for both) beside each tool's own timer:

  corruption  the file's odometry (edges i -> i+1) and loop closures kept as they are; wrong closures appended so that
              they are `rate` % of all loop closures: between random pose pairs 2 or more apart that no edge joins,
              measurements uniform within WRONG_T m (each axis) and a uniform rotation, information copied from a
              random true loop closure (as confident as the true ones). VERTEX lines are the odometry chained from
              pose 0 at the identity, so both tools start from the same estimate.
  keel        `keel robust FILE --json --p P` (PCM per group, exact clique, the certified solve), once per variant
              (--variants "LABEL=EXTRA ARGS;...": each its own tool row, labelled LABEL);
  Kimera-RPGO kimera_measure (keel's driver, Kimera-RPGO's Mahalanobis PCM with its threshold set to sqrt(gamma) of
              keel's gamma, the norm it compares, then GNC unless NO_GNC=1).
  GTSAM GNC   with --gtsam-gnc: gtsam_gnc_measure (keel's driver, GTSAM's GncOptimizer with truncated least squares
              at probability 0.99, odometry and a prior on pose 0 known inliers, no PCM), labelled gtsam_gnc.

A kept closure is scored against the truth: precision = true kept / kept, recall = true kept / true closures.
With --prepared lists that name a reference (keel_robust_graphs: the certified optimum of the graph without wrong
closures, ext_robust_backend's ATE reference) and --keel-python, each tool's ATE against it is scored too (the
root mean square position error after the best rigid motion, graph/trajectory_error.hpp's definition): Kimera-RPGO's
estimate from kimera_measure --poses, keel's from its Python module (keel.robust, the same run as the command, bit for
bit, which the CLI's own outputs cannot give for answers that are not certified; the kept closures of the two are
checked to be the same). The Python run is not timed.
Writes one TSV row per run and prints a summary per data set and rate (medians over trials), then each keel variant
paired with Kimera-RPGO file by file: per cell the mean difference of precision, recall and process time with a 95 %
t interval over the trials, and the cells where the interval lies above, straddles or lies below zero.

  robust.py --keel K --kimera M --out OUT.tsv [--rates 0,10,20,40] [--trials 3] [--seed 1] [--p 0.11]
            NAME=FILE.g2o ...
  robust.py --from-tsv OUT.tsv [--summary-json FILE ...]   scores an earlier run's rows again, running nothing

--summary-json FILE writes the comparison of the first keel variant with Kimera-RPGO as the tables the report
renders beside ext_robust_backend (results/ext_robust_backend/side_by_side.json; repro/report.hpp gives the format):
per robot count the cells where each rule shows keel better, no different or worse, the sign tests over the cells,
the totals per tool, and the cells where keel is worse. --provenance KEY=VALUE (repeatable) names what made the rows
(keel_commit, peers, machine, date, command, record): text the rows cannot carry, shown as given; --stamp fills in
the keel commit, the date and the machine from this checkout (side_by_side.py).
"""
import argparse
import importlib
import json
import math
import os
import random
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import side_by_side  # noqa: E402  (beside this file)


def qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def qrot(q, v):
    w, x, y, z = qmul(qmul(q, (0.0, *v)), (q[0], -q[1], -q[2], -q[3]))
    return (x, y, z)


def read_edges(path):
    edges = []
    with open(path) as f:
        for line in f:
            t = line.split()
            if t and t[0].startswith("EDGE_SE"):
                edges.append(t)
    if not edges:
        sys.exit(f"robust.py: {path} has no EDGE_SE2 / EDGE_SE3:QUAT lines")
    return edges


def chain_vertices(edges, three_d):
    """VERTEX lines: the odometry (edges i -> i+1) chained from pose 0 at the identity."""
    odo = {int(t[1]): t for t in edges if int(t[2]) == int(t[1]) + 1}
    n = 1 + max(max(int(t[1]), int(t[2])) for t in edges)
    out = []
    if three_d:
        p, q = (0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0)
        for k in range(n):
            out.append(f"VERTEX_SE3:QUAT {k} {p[0]:.9g} {p[1]:.9g} {p[2]:.9g} {q[1]:.9g} {q[2]:.9g} {q[3]:.9g} {q[0]:.9g}")
            if k + 1 < n:
                t = odo.get(k)
                if t is None:
                    sys.exit(f"robust.py: no odometry edge {k} -> {k + 1}")
                d = tuple(map(float, t[3:6]))
                dq = (float(t[9]), float(t[6]), float(t[7]), float(t[8]))
                r = qrot(q, d)
                p = (p[0] + r[0], p[1] + r[1], p[2] + r[2])
                q = qmul(q, dq)
                s = math.sqrt(sum(c * c for c in q))
                q = tuple(c / s for c in q)
    else:
        x = y = th = 0.0
        for k in range(n):
            out.append(f"VERTEX_SE2 {k} {x:.9g} {y:.9g} {th:.9g}")
            if k + 1 < n:
                t = odo.get(k)
                if t is None:
                    sys.exit(f"robust.py: no odometry edge {k} -> {k + 1}")
                dx, dy, dth = map(float, t[3:6])
                x, y = x + math.cos(th) * dx - math.sin(th) * dy, y + math.sin(th) * dx + math.cos(th) * dy
                th = math.atan2(math.sin(th + dth), math.cos(th + dth))
    return out, n


def corrupt(edges, n, rate, rng, three_d, wrong_t):
    closures = [t for t in edges if abs(int(t[2]) - int(t[1])) != 1]
    n_wrong = round(rate / (100.0 - rate) * len(closures)) if rate > 0 else 0
    joined = {(int(t[1]), int(t[2])) for t in edges} | {(int(t[2]), int(t[1])) for t in edges}
    wrong = []
    while len(wrong) < n_wrong:
        i, j = rng.randrange(n), rng.randrange(n)
        if abs(i - j) <= 1 or (i, j) in joined:
            continue
        joined |= {(i, j), (j, i)}
        info = rng.choice(closures)
        if three_d:
            u1, u2, u3 = rng.random(), rng.random(), rng.random()  # uniform rotation (Shoemake)
            q = (math.sqrt(1 - u1) * math.sin(2 * math.pi * u2), math.sqrt(1 - u1) * math.cos(2 * math.pi * u2),
                 math.sqrt(u1) * math.sin(2 * math.pi * u3), math.sqrt(u1) * math.cos(2 * math.pi * u3))
            t = [rng.uniform(-wrong_t, wrong_t) for _ in range(3)]
            wrong.append([info[0], str(i), str(j)] + [f"{v:.9g}" for v in t + [q[1], q[2], q[3], q[0]]] + info[10:])
        else:
            z = [rng.uniform(-wrong_t, wrong_t), rng.uniform(-wrong_t, wrong_t), rng.uniform(-math.pi, math.pi)]
            wrong.append([info[0], str(i), str(j)] + [f"{v:.9g}" for v in z] + info[6:])
    return len(closures), wrong


def timed(cmd, limit):
    """The completed process (None past `limit` seconds) and its wall time."""
    t0 = time.monotonic()
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=limit,
                           env={**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"})
    except subprocess.TimeoutExpired:
        r = None
    return r, time.monotonic() - t0


def read_positions(path):
    """{id: position} of a positions file ("id x y [z]" lines; a first "certified" line is skipped)."""
    out = {}
    with open(path) as f:
        for line in f:
            t = line.split()
            if t and t[0] != "certified":
                out[int(t[0])] = [float(v) for v in t[1:]]
    return out


def ate(reference, estimate):
    """The root mean square of ‖p_k − (R p̂_k + t)‖ after the rigid motion (R, t) that minimizes it (Umeyama 1991
    without scale, det R = +1), as graph::absolute_trajectory_error."""
    import numpy as np
    ids = sorted(reference)
    if sorted(estimate) != ids:
        sys.exit("robust.py: an estimate's poses are not the reference's")
    P = np.array([reference[k] for k in ids])
    Q = np.array([estimate[k] for k in ids])
    mp, mq = P.mean(axis=0), Q.mean(axis=0)
    U, _, Vt = np.linalg.svd((P - mp).T @ (Q - mq))
    D = np.eye(P.shape[1])
    D[-1, -1] = np.sign(np.linalg.det(U @ Vt)) or 1.0
    R = U @ D @ Vt
    E = P - (Q - mq) @ R.T - mp
    return float(np.sqrt((E * E).sum(axis=1).mean()))


def python_kwargs(extra):
    """keel robust's extra command-line arguments ("--residual-test edge") as keel.robust's keywords."""
    out = {}
    for k in range(0, len(extra), 2):
        if not extra[k].startswith("--") or k + 1 >= len(extra):
            sys.exit(f"robust.py: cannot pass {' '.join(extra)} to keel.robust (pairs '--name value' only)")
        v = extra[k + 1]
        try:
            v = int(v)
        except ValueError:
            try:
                v = float(v)
            except ValueError:
                pass
        out[extra[k][2:].replace("-", "_")] = v
    return out


def keel_estimate(a, files, candidates, extra):
    """keel.robust on the same inputs: {global id: position} of its answer and its kept pairs (global ids)."""
    keel = a.keel_module
    graphs = [keel.read_graph(f) for f in files]
    dim = 3 if type(graphs[0]).__name__ == "Graph3D" else 2
    cands = keel.read_candidates(candidates, dim=dim) if candidates else None
    r = keel.robust(graphs if len(graphs) > 1 else graphs[0], cands, p=a.p, **python_kwargs(extra))
    sol = r["solution"]
    offsets = [0]
    for g in graphs[:-1]:
        offsets.append(offsets[-1] + len(g.poses))
    kept = sorted((offsets[c["robot_a"]] + c["i"], offsets[c["robot_b"]] + c["j"])
                  for c in r["candidate_list"] if c["kept"])
    return {k: [float(v) for v in sol[k][:dim]] for k in range(len(sol))}, kept


def vertex_count(path):
    with open(path) as f:
        return sum(1 for line in f if line.startswith("VERTEX_SE"))


def run_file(a, name, rate, trial, f, n_true, wrong_pairs, gammas, rows, out, candidates=None, reference=None):
    """Runs keel robust and Kimera-RPGO on the graph f (a file, or a list of one file per robot with the
    inter-robot candidates in `candidates`, global ids), scores both and appends their rows to rows and out.
    Kept closures are scored in global ids: robot r's pose k is k plus the poses of the robots before it."""
    result = []
    gamma = gammas.get(name)
    files = f if isinstance(f, list) else [f]
    inputs = files + (["--candidates", candidates] if candidates else [])
    offsets = [0]
    for g in files[:-1]:
        offsets.append(offsets[-1] + vertex_count(g))
    f = files[0] if len(files) == 1 else " ".join(inputs)  # for messages
    for label, extra in a.variants:
        r, keel_s = timed([a.keel, "robust", *inputs, "--json", "-q", "--p", str(a.p), *extra], a.timeout)
        if r is not None and r.returncode not in (0, 1):
            sys.exit(f"robust.py: keel robust {f} {' '.join(extra)} exited {r.returncode}: {r.stderr}")
        if r is None:
            result.append((label, None, keel_s, float("nan"), "timeout", float("nan")))
        else:
            j = json.loads(r.stdout)
            gamma = gammas.setdefault(name, j["gamma"])
            kept = [(offsets[c["robot_a"]] + c["i"], offsets[c["robot_b"]] + c["j"])
                    for c in j["candidate_list"] if c["kept"]]
            own = sum(v for v in j["times_s"].values())
            err = float("nan")
            if reference is not None:
                est, kept_py = keel_estimate(a, files, candidates, extra)
                if kept_py != sorted(kept):
                    sys.exit(f"robust.py: keel.robust kept other closures than keel robust on {f}")
                err = ate(reference, est)
            result.append((label, kept, keel_s, own, "yes" if j["certificate"]["certified"] else "no", err))
    if gamma is None:
        sys.exit(f"robust.py: keel timed out on {name}'s first file, so there is no gamma for "
                 "Kimera-RPGO's threshold")
    def peer(tool, driver, command, timer, poses=None):
        """A peer's driver on f: its key=value lines, kept_edges as "i-j" and its own timer `timer`; with `poses`
        (a file its command writes the estimate to) the ATE against the reference."""
        r, seconds = timed(command, a.timeout)
        if r is None:
            result.append((tool, None, seconds, float("nan"), "timeout", float("nan")))
            return
        if r.returncode != 0:
            sys.exit(f"robust.py: {driver} {f} exited {r.returncode}: {r.stderr}")
        kv = dict(line.split("=", 1) for line in r.stdout.splitlines() if "=" in line)
        kept_p = [tuple(map(int, e.split("-"))) for e in kv["kept_edges"].split()]
        err = ate(reference, read_positions(poses)) if poses else float("nan")
        result.append((tool, kept_p, seconds, float(kv[timer]), "", err))

    kimera_poses = None
    if reference is not None:
        kimera_poses = os.path.join(a.work, "kimera_poses.txt")
    peer("kimera", "kimera_measure", [a.kimera, "--threshold", f"{math.sqrt(gamma):.12g}",
                                      *(["--poses", kimera_poses] if kimera_poses else []), *inputs]
         + (["--no-gnc"] if os.environ.get("NO_GNC") == "1" else []), "rpgo_s", kimera_poses)
    if a.gtsam_gnc:
        if len(files) > 1:
            sys.exit("robust.py: gtsam_gnc_measure takes one robot's graph; leave --gtsam-gnc out for several")
        peer("gtsam_gnc", "gtsam_gnc_measure", [a.gtsam_gnc, files[0]], "gnc_s")
    for tool, kept_pairs, proc, own_s, cert, err in result:
        if kept_pairs is None:  # timed out
            row = (name, rate, trial, tool, "", n_true, "", len(wrong_pairs), float("nan"), float("nan"),
                   proc, own_s, cert, float("nan"))
            rows.append(row)
            out.write("\t".join(str(v) for v in row) + "\n")
            continue
        # Pairs unordered: keel reports an inter-robot candidate from the lower robot's side.
        wrong_set = {(min(p), max(p)) for p in wrong_pairs}
        kw = sum(1 for p in kept_pairs if (min(p), max(p)) in wrong_set)
        kt = len(kept_pairs) - kw
        prec = kt / len(kept_pairs) if kept_pairs else 1.0
        rec = kt / n_true if n_true else 1.0
        row = (name, rate, trial, tool, kt, n_true, kw, len(wrong_pairs), prec, rec, proc, own_s, cert, err)
        rows.append(row)
        out.write("\t".join(str(v) for v in row) + "\n")
        out.flush()
    print(f"{name} {rate:g}% trial {trial}: " + "; ".join(
        f"{row[3]} P {row[8]:.3f} R {row[9]:.3f} ATE {row[13]:.3g} {row[10]:.2f} s {row[12]}"
        for row in rows[-len(result):]),
          file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keel", default=None)
    ap.add_argument("--kimera", default=None)
    ap.add_argument("--gtsam-gnc", default=None, help="gtsam_gnc_measure, run as a further tool (gtsam_gnc)")
    ap.add_argument("--out", default=None)
    ap.add_argument("--from-tsv", default=None, help="score the rows of an earlier run's TSV; run nothing")
    ap.add_argument("--summary-json", default=None, help="write the tables the report renders (see above)")
    ap.add_argument("--provenance", action="append", default=[], help="KEY=VALUE for --summary-json")
    ap.add_argument("--stamp", action="store_true", help="--summary-json's provenance also names the keel commit, "
                    "the date and the machine (side_by_side.py)")
    ap.add_argument("--rates", default="0,10,20,40")
    ap.add_argument("--trials", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--p", type=float, default=0.11)
    ap.add_argument("--variants", default="keel=", help="keel robust's runs per file: 'LABEL=EXTRA ARGS' separated "
                    "by ';' (default: one run labelled keel, no extra arguments)")
    ap.add_argument("--wrong-t", type=float, default=5.0)
    ap.add_argument("--workdir", default=None)
    ap.add_argument("--keel-python", default=None, help="the folder holding keel's Python module (build/release/"
                    "python): with a --prepared list naming references, each tool's ATE is scored")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per tool and file (a run past it is "
                    "recorded as 'timeout', its time as the limit)")
    ap.add_argument("--prepared", default=None, help="a list written by keel_robust_graphs (lines 'KEY=FILE "
                    "TRUE_EDGES'): run on those files instead of corrupting data sets; the edges after the first "
                    "TRUE_EDGES are the wrong closures")
    ap.add_argument("datasets", nargs="*", help="NAME=FILE.g2o")
    a = ap.parse_args()
    a.variants = [(v.split("=", 1)[0], v.split("=", 1)[1].split()) for v in a.variants.split(";") if v.strip()]
    if not a.variants or any(not label or label == "kimera" for label, _ in a.variants):
        sys.exit("robust.py: --variants needs 'LABEL=ARGS' entries with labels other than kimera")
    if any(label == "gtsam_gnc" for label, _ in a.variants):
        sys.exit("robust.py: gtsam_gnc is the label of --gtsam-gnc's runs")
    provenance = side_by_side.provenance(a.provenance, "robust.py", a.stamp)
    if a.from_tsv:
        if a.prepared or a.datasets:
            sys.exit("robust.py: --from-tsv scores an earlier run; give no data sets or --prepared with it")
        report(a, read_tsv(a.from_tsv), provenance)
        return
    if not (a.keel and a.kimera and a.out):
        sys.exit("robust.py: --keel, --kimera and --out are needed to run (or --from-tsv to score a run)")
    if bool(a.prepared) == bool(a.datasets):
        sys.exit("robust.py: give data sets or --prepared LIST, not both or neither")
    work = a.workdir or tempfile.mkdtemp(prefix="keel_robust_")
    a.work = work
    a.keel_module = None
    if a.keel_python:
        sys.path.insert(0, a.keel_python)
        a.keel_module = importlib.import_module("keel")
    references = {}  # path: {id: position}, read once
    rates = [float(r) for r in a.rates.split(",")]
    rows = []
    gammas = {}  # γ(p) of a data set's dimension, from its first keel run (Kimera-RPGO's threshold is √γ)
    with open(a.out, "w") as out:
        out.write("dataset\trate\ttrial\ttool\tkept_true\ttrue\tkept_wrong\twrong\tprecision\trecall\tprocess_s\t"
                  "own_s\tcertified\tate\n")
        for line in open(a.prepared) if a.prepared else []:
            # <graph>.r<R>.<kind>.out<percent>.t<trial> or <graph>.r<R>.clean.t<trial> (ext_robust_backend's
            # cells); a data set's name carries its robot count when it is above one (manhattan.r2.random)
            key, rest = line.strip().split("=", 1)
            parts = key.split(".")
            robots = int(parts[1][1:])
            graph = parts[0] if robots == 1 else f"{parts[0]}.{parts[1]}"
            name = graph if parts[2] == "clean" else f"{graph}.{parts[2]}"
            rate = 0.0 if parts[2] == "clean" else float(parts[3][3:])
            trial = int(parts[-1][1:])
            fields = rest.split(" ")
            reference = None  # the positions of the ATE reference, when the list names one and ATE is scored
            if a.keel_module and len(fields) == (5 if robots > 1 else 3):
                if fields[-1] not in references:
                    with open(fields[-1]) as r:
                        if r.readline().split() != ["certified", "1"]:
                            sys.exit(f"robust.py: the reference {fields[-1]} is not certified")
                    references[fields[-1]] = read_positions(fields[-1])
                reference = references[fields[-1]]
            if robots > 1:  # "F0,F1,... CANDIDATES TRUE WRONG_FILE [REFERENCE]" (keel_robust_graphs)
                files, candidates, n_true, wrong_file = fields[:4]
                with open(wrong_file) as w:
                    wrong_pairs = {tuple(map(int, l.split())) for l in w if l.strip()}
                run_file(a, name, rate, trial, files.split(","), int(n_true), wrong_pairs, gammas, rows, out,
                         candidates, reference)
                continue
            f, true_edges = fields[:2]
            edges = read_edges(f)
            clean, wrong = edges[:int(true_edges)], edges[int(true_edges):]
            n_true = sum(1 for t in clean if abs(int(t[2]) - int(t[1])) != 1)
            run_file(a, name, rate, trial, f, n_true, {(int(t[1]), int(t[2])) for t in wrong}, gammas, rows, out,
                     None, reference)
        for spec in a.datasets:
            name, path = spec.split("=", 1)
            edges = read_edges(path)
            three_d = edges[0][0].startswith("EDGE_SE3")
            verts, n = chain_vertices(edges, three_d)
            for rate in rates:
                for trial in range(a.trials):
                    rng = random.Random(f"{a.seed}/{name}/{rate}/{trial}")
                    n_true, wrong = corrupt(edges, n, rate, rng, three_d, a.wrong_t)
                    f = os.path.join(work, f"{name}_r{rate:g}_t{trial}.g2o")
                    with open(f, "w") as g:
                        g.write("\n".join(verts + [" ".join(t) for t in edges + wrong]) + "\n")
                    wrong_pairs = {(int(t[1]), int(t[2])) for t in wrong}
                    run_file(a, name, rate, trial, f, n_true, wrong_pairs, gammas, rows, out)
    report(a, rows, provenance)


def read_tsv(path):
    """The rows of a TSV this script wrote, typed as run_file makes them."""
    rows = []
    with open(path) as f:
        header = f.readline().rstrip("\n").split("\t")
        if header[:4] != ["dataset", "rate", "trial", "tool"] or len(header) != 14:
            sys.exit(f"robust.py: {path} is not a TSV of robust.py (header {header})")
        for n, line in enumerate(f, start=2):
            v = line.rstrip("\n").split("\t")
            if len(v) != 14:
                sys.exit(f"robust.py: {path}:{n}: {len(v)} fields, expected 14")
            try:
                rows.append((v[0], float(v[1]), int(v[2]), v[3], int(v[4]) if v[4] else "", int(v[5]),
                             int(v[6]) if v[6] else "", int(v[7]), float(v[8]), float(v[9]), float(v[10]),
                             float(v[11]), v[12], float(v[13])))
            except ValueError as e:
                sys.exit(f"robust.py: {path}:{n}: {e}")
    return rows


def report(a, rows, provenance):
    """The summary table, each keel variant paired with the peers, and the --summary-json tables."""
    print("| data set | outliers | tool | precision (median) | recall (median) | wrong kept (median) | "
          "ATE (median) | process s (median) | keel certified |")
    print("|---|---|---|---|---|---|---|---|---|")
    peers = ("kimera", "gtsam_gnc")
    keys = sorted({(r[0], r[1], r[3]) for r in rows}, key=lambda k: (k[0], k[1], k[2] in peers, k[2]))
    for name, rate, tool in keys:
        sel = [r for r in rows if (r[0], r[1], r[3]) == (name, rate, tool)]
        cert = f"{sum(r[12] == 'yes' for r in sel)} of {len(sel)}" if tool not in peers else ""
        done = [r for r in sel if r[12] != "timeout"]
        late = len(sel) - len(done)
        if not done:
            print(f"| {name} | {rate:g} % | {tool} | — | — | — | — | > {a.timeout:g} (all {late} timed out) | "
                  f"{cert} |")
            continue
        errs = [r[13] for r in done if not math.isnan(r[13])]
        print(f"| {name} | {rate:g} % | {tool} | {statistics.median(r[8] for r in done):.3f} | "
              f"{statistics.median(r[9] for r in done):.3f} | {statistics.median(r[6] for r in done):g} | "
              f"{f'{statistics.median(errs):.3g}' if errs else '—'} | "
              f"{statistics.median(r[10] for r in done):.2f}{f' ({late} timed out)' if late else ''} | {cert} |")
    tools = {r[3] for r in rows}
    labels = [label for label, _ in a.variants] if not a.from_tsv else sorted(tools - set(peers))
    first = {}
    for label in labels:
        first.setdefault(label, paired(rows, label, "kimera"))
        if "gtsam_gnc" in tools:
            paired(rows, label, "gtsam_gnc")
    for label in labels[1:]:  # each further variant against the first
        paired(rows, label, labels[0])
    if a.summary_json:
        if not labels or "kimera" not in tools:
            sys.exit("robust.py: --summary-json needs keel's rows and Kimera-RPGO's")
        write_summary(a.summary_json, rows, labels[0], first[labels[0]], provenance)


def robots_of(name):
    """A data set's robot count: its name carries .r<R> after the graph when R is above one."""
    parts = name.split(".")
    return int(parts[1][1:]) if len(parts) > 1 and re.fullmatch(r"r[0-9]+", parts[1]) else 1


def write_summary(path, rows, label, cmp, provenance):
    """The tables of keel (tool `label`) against Kimera-RPGO that the report shows beside the experiment
    (repro/report.hpp, the side-by-side file): every number in them comes from the rows."""
    metrics = cmp["metrics"]
    names = {"precision": "precision", "recall": "recall", "ATE": "ATE", "time": "process time"}
    robot_counts = sorted({robots_of(c["name"]) for c in cmp["cells"]})
    by_robots = []
    for R in robot_counts + [None]:
        cells = [c for c in cmp["cells"] if R is None or robots_of(c["name"]) == R]
        row = ["all" if R is None else str(R), str(len(cells)), str(sum(not c["worse"] for c in cells))]
        for m in metrics:
            v = [c["verdict"][m] for c in cells if m in c["verdict"]]
            row.append(f"{v.count('better')} / {v.count('same')} / {v.count('worse')}")
        by_robots.append(row)
    signs = [[names[m], f"{cmp['tally'][m][0]} / {cmp['tally'][m][1]} / {cmp['tally'][m][2]}",
              f"{cmp['signs'][m][0]} / {cmp['signs'][m][1]}", f"{sign_test(*cmp['signs'][m]):.2g}"]
             for m in metrics]
    totals = []
    for tool in (label, "kimera"):
        for R in robot_counts:
            mine = [r for r in rows if r[3] == tool and robots_of(r[0]) == R]
            sel = [r for r in mine if r[12] != "timeout"]
            errs = [r[13] for r in sel if not math.isnan(r[13])]
            totals.append([
                "keel" if tool == label else "Kimera-RPGO", str(R), str(len(mine)),
                str(sum(r[6] for r in sel)), f"{sum(r[4] for r in sel)} of {sum(r[5] for r in sel)}",
                f"{statistics.median(errs):.3g}" if errs else "—",
                f"{sum(r[12] == 'yes' for r in sel)} of {len(sel)}" if tool == label else "—",
                f"{sum(r[10] for r in sel):.1f}", str(len(mine) - len(sel))])
    worse = []
    for m in metrics:
        for c in cmp["cells"]:
            if c["verdict"].get(m) == "worse":
                mean, lo, hi = c["interval"][m]
                f = ".3g" if m == "ATE" else ".3f"
                worse.append([names[m], c["name"], f"{c['rate']:g} %", str(c["files"]),
                              f"{mean:+{f}} [{lo:+{f}}, {hi:+{f}}]"])
    what = (f"{len(rows)} runs over {len(cmp['cells'])} cells (data set, robot count, kind and rate of wrong "
            "closures), each tool once per file, one thread each, the whole process timed for both. A cell shows keel "
            "better, no different or worse by the 95 % t interval of the mean paired difference over its files; "
            "keel's acceptance rules ask for precision and recall at least Kimera-RPGO's, and ATE and time at most. "
            "The sign test is two-sided, over the cells' mean differences.")
    side_by_side.write(path, "keel robust and Kimera-RPGO on the same files", what, provenance, [
        {"caption": "Cells where keel is better / shows no difference / is worse, by robot count",
         "header": ["robots", "cells", "no rule shows keel worse"] +
                   [f"{names[m]}: better / same / worse" for m in metrics],
         "rows": by_robots},
        {"caption": "Over all cells: the cells' mean differences and the sign test",
         "header": ["rule", "cells better / same / worse", "cell means favour keel / Kimera-RPGO", "sign test p"],
         "rows": signs},
        {"caption": "Totals per tool and robot count",
         "header": ["tool", "robots", "files", "wrong closures kept", "true closures kept", "median ATE",
                    "certified", "process s (sum)", "timed out"],
         "rows": totals},
        {"caption": "The cells where keel is worse: mean difference keel − Kimera-RPGO [95 % interval]",
         "header": ["rule", "cell", "wrong closures", "files", "difference"],
         "rows": worse or [["none", "", "", "", ""]]},
    ])


# Two-sided 97.5 % quantiles of Student's t for 1 … 30 degrees of freedom (the 95 % interval of a mean).
T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
        2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


def interval(d):
    """Mean and 95 % t interval of the paired differences d (unbounded for a single value: nothing is shown)."""
    m = statistics.fmean(d)
    if len(d) < 2:
        return m, -math.inf, math.inf
    h = T975[min(len(d) - 1, len(T975)) - 1] * statistics.stdev(d) / math.sqrt(len(d))
    return m, m - h, m + h


def sign_test(up, down):
    """Two-sided exact sign test: the chance of a split at least this uneven if either side were as likely."""
    n, k = up + down, min(up, down)
    if n == 0:
        return 1.0
    return min(1.0, 2.0 * sum(math.comb(n, i) for i in range(k + 1)) / 2.0 ** n)


def paired(rows, label, ref):
    """Tool `label` against tool `ref` on the same files: per cell (data set, rate) the mean difference label − ref
    of precision, recall, ATE (when scored) and process seconds with its 95 % interval over the trials where both
    finished; per metric the cells whose interval lies on either side of 0 or contains it, and a sign test over the
    cells; then the cells where no metric's interval shows label worse."""
    by = {(r[0], r[1], r[2], r[3]): r for r in rows if r[12] != "timeout"}
    cells = sorted({(r[0], r[1]) for r in rows})
    with_ate = any(not math.isnan(r[13]) for r in by.values())
    metrics = [("precision", 8), ("recall", 9)] + ([("ATE", 13)] if with_ate else []) + [("time", 10)]
    lower_better = {"ATE", "time"}
    print(f"\n{label} − {ref}, paired by file (mean [95 % interval]):\n")
    print("| data set | outliers | files | " + " | ".join(
        f"Δ {'process s' if m == 'time' else m}" for m, _ in metrics) + " |")
    print("|---|---|---|" + "---|" * len(metrics))
    tally = {m: [0, 0, 0] for m, _ in metrics}
    signs = {m: [0, 0] for m in tally}  # cells whose mean difference favours label, and ref
    none_worse = 0
    result = {"metrics": [m for m, _ in metrics], "cells": [], "tally": tally, "signs": signs}
    for name, rate in cells:
        pairs = [(by[k], by[(k[0], k[1], k[2], ref)]) for k in by
                 if k[0] == name and k[1] == rate and k[3] == label and (k[0], k[1], k[2], ref) in by]
        if not pairs:
            continue
        out = []
        worse = False
        cell = {"name": name, "rate": rate, "files": len(pairs), "verdict": {}, "interval": {}}
        for m, col in metrics:
            d = [x[col] - y[col] for x, y in pairs if not (math.isnan(x[col]) or math.isnan(y[col]))]
            if not d:
                out.append("—")
                continue
            mean, lo, hi = interval(d)
            # For time and ATE, lower is better: an interval below 0 is label's win.
            win, loss = (lo > 0, hi < 0) if m not in lower_better else (hi < 0, lo > 0)
            tally[m][0 if win else 2 if loss else 1] += 1
            cell["verdict"][m] = "better" if win else "worse" if loss else "same"
            cell["interval"][m] = (mean, lo, hi)
            worse = worse or loss
            if mean != 0:
                signs[m][0 if (mean > 0) == (m not in lower_better) else 1] += 1
            out.append(f"{mean:+.3g} [{lo:+.3g}, {hi:+.3g}]" if m == "ATE" else f"{mean:+.3f} [{lo:+.3f}, {hi:+.3f}]")
        none_worse += not worse
        cell["worse"] = worse
        result["cells"].append(cell)
        print(f"| {name} | {rate:g} % | {len(pairs)} | " + " | ".join(out) + " |")
    print()
    print(f"{label} vs {ref}: no metric shows {label} worse (95 % intervals) in {none_worse} of "
          f"{sum(1 for c in cells if any(k[0] == c[0] and k[1] == c[1] and k[3] == label for k in by))} cells")
    for m, (w, tie, l) in tally.items():
        up, down = signs[m]
        print(f"{label} vs {ref}, {m}: {label} better in {w} cells, no difference shown in {tie}, worse in {l} "
              f"(95 % intervals, each cell alone); the mean difference favours {label} in {up} cells, {ref} in "
              f"{down}: two-sided sign test over the cells p = {sign_test(up, down):.3g}")
    return result


if __name__ == "__main__":
    main()
