#!/usr/bin/env python3
"""keel robust and Kimera-RPGO side by side on graphs with wrong loop closures added (bench/side_by_side/robust.sh).

For each data set, outlier rate and trial this writes one corrupted g2o file and runs both tools on it, one thread
each, timing each whole process (file reading and set-up included, the same for both) beside each tool's own timer:

  corruption  the file's odometry (edges i -> i+1) and loop closures kept as they are; wrong closures appended so that
              they are `rate` % of all loop closures: between random pose pairs 2 or more apart that no edge joins,
              measurements uniform within WRONG_T m (each axis) and a uniform rotation, information copied from a
              random true loop closure (as confident as the true ones). VERTEX lines are the odometry chained from
              pose 0 at the identity, so both tools start from the same estimate.
  keel        `keel robust FILE --json --p P` (PCM per group, exact clique, the certified solve);
  Kimera-RPGO kimera_measure (keel's driver, Kimera-RPGO's Mahalanobis PCM with its threshold set to sqrt(gamma) of
              keel's gamma, the norm it compares, then GNC unless NO_GNC=1).

A kept closure is scored against the truth: precision = true kept / kept, recall = true kept / true closures.
Writes one TSV row per run and prints a summary per data set and rate (medians over trials).

  robust.py --keel K --kimera M --out OUT.tsv [--rates 0,10,20,40] [--trials 3] [--seed 1] [--p 0.11]
            NAME=FILE.g2o ...
"""
import argparse
import json
import math
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time


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


def run_file(a, name, rate, trial, f, n_true, wrong_pairs, gammas, rows, out):
    """Runs keel robust and Kimera-RPGO on file f, scores both and appends their rows to rows and out."""
    r, keel_s = timed([a.keel, "robust", f, "--json", "-q", "--p", str(a.p)], a.timeout)
    if r is not None and r.returncode not in (0, 1):
        sys.exit(f"robust.py: keel robust {f} exited {r.returncode}: {r.stderr}")
    result = []
    gamma = gammas.get(name)
    if r is None:
        result.append(("keel", None, keel_s, float("nan"), "timeout"))
    else:
        j = json.loads(r.stdout)
        gamma = gammas.setdefault(name, j["gamma"])
        kept = [(c["i"], c["j"]) for c in j["candidate_list"] if c["kept"]]
        own = sum(v for v in j["times_s"].values())
        result.append(("keel", kept, keel_s, own, "yes" if j["certificate"]["certified"] else "no"))
    if gamma is None:
        sys.exit(f"robust.py: keel timed out on {name}'s first file, so there is no gamma for "
                 "Kimera-RPGO's threshold")
    r, kim_s = timed([a.kimera, "--threshold", f"{math.sqrt(gamma):.12g}", f]
                     + (["--no-gnc"] if os.environ.get("NO_GNC") == "1" else []), a.timeout)
    if r is None:
        result.append(("kimera", None, kim_s, float("nan"), "timeout"))
    else:
        if r.returncode != 0:
            sys.exit(f"robust.py: kimera_measure {f} exited {r.returncode}: {r.stderr}")
        kv = dict(line.split("=", 1) for line in r.stdout.splitlines() if "=" in line)
        kept_k = [tuple(map(int, e.split("-"))) for e in kv["kept_edges"].split()]
        result.append(("kimera", kept_k, kim_s, float(kv["rpgo_s"]), ""))
    for tool, kept_pairs, proc, own_s, cert in result:
        if kept_pairs is None:  # timed out
            row = (name, rate, trial, tool, "", n_true, "", len(wrong_pairs), float("nan"), float("nan"),
                   proc, own_s, cert)
            rows.append(row)
            out.write("\t".join(str(v) for v in row) + "\n")
            continue
        kw = sum(1 for p in kept_pairs if p in wrong_pairs)
        kt = len(kept_pairs) - kw
        prec = kt / len(kept_pairs) if kept_pairs else 1.0
        rec = kt / n_true if n_true else 1.0
        row = (name, rate, trial, tool, kt, n_true, kw, len(wrong_pairs), prec, rec, proc, own_s, cert)
        rows.append(row)
        out.write("\t".join(str(v) for v in row) + "\n")
        out.flush()
    print(f"{name} {rate:g}% trial {trial}: " + "; ".join(
        f"{row[3]} P {row[8]:.3f} R {row[9]:.3f} {row[10]:.2f} s {row[12]}" for row in rows[-2:]),
          file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keel", required=True)
    ap.add_argument("--kimera", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--rates", default="0,10,20,40")
    ap.add_argument("--trials", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--p", type=float, default=0.11)
    ap.add_argument("--wrong-t", type=float, default=5.0)
    ap.add_argument("--workdir", default=None)
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per tool and file (a run past it is "
                    "recorded as 'timeout', its time as the limit)")
    ap.add_argument("--prepared", default=None, help="a list written by keel_robust_graphs (lines 'KEY=FILE "
                    "TRUE_EDGES'): run on those files instead of corrupting data sets; the edges after the first "
                    "TRUE_EDGES are the wrong closures")
    ap.add_argument("datasets", nargs="*", help="NAME=FILE.g2o")
    a = ap.parse_args()
    if bool(a.prepared) == bool(a.datasets):
        sys.exit("robust.py: give data sets or --prepared LIST, not both or neither")
    work = a.workdir or tempfile.mkdtemp(prefix="keel_robust_")
    rates = [float(r) for r in a.rates.split(",")]
    rows = []
    gammas = {}  # γ(p) of a data set's dimension, from its first keel run (Kimera-RPGO's threshold is √γ)
    with open(a.out, "w") as out:
        out.write("dataset\trate\ttrial\ttool\tkept_true\ttrue\tkept_wrong\twrong\tprecision\trecall\tprocess_s\t"
                  "own_s\tcertified\n")
        for line in open(a.prepared) if a.prepared else []:
            # <graph>.r1.<kind>.out<percent>.t<trial> or <graph>.r1.clean.t<trial> (ext_robust_backend's cells)
            key, rest = line.strip().split("=", 1)
            f, true_edges = rest.rsplit(" ", 1)
            parts = key.split(".")
            name = parts[0] if parts[2] == "clean" else f"{parts[0]}.{parts[2]}"
            rate = 0.0 if parts[2] == "clean" else float(parts[3][3:])
            trial = int(parts[-1][1:])
            edges = read_edges(f)
            clean, wrong = edges[:int(true_edges)], edges[int(true_edges):]
            n_true = sum(1 for t in clean if abs(int(t[2]) - int(t[1])) != 1)
            run_file(a, name, rate, trial, f, n_true, {(int(t[1]), int(t[2])) for t in wrong}, gammas, rows, out)
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
    print("| data set | outliers | tool | precision (median) | recall (median) | wrong kept (median) | "
          "process s (median) | keel certified |")
    print("|---|---|---|---|---|---|---|---|")
    keys = sorted({(r[0], r[1], r[3]) for r in rows}, key=lambda k: (k[0], k[1], k[2] != "keel"))
    for name, rate, tool in keys:
        sel = [r for r in rows if (r[0], r[1], r[3]) == (name, rate, tool)]
        cert = f"{sum(r[12] == 'yes' for r in sel)} of {len(sel)}" if tool == "keel" else ""
        done = [r for r in sel if r[12] != "timeout"]
        late = len(sel) - len(done)
        if not done:
            print(f"| {name} | {rate:g} % | {tool} | — | — | — | > {a.timeout:g} (all {late} timed out) | {cert} |")
            continue
        print(f"| {name} | {rate:g} % | {tool} | {statistics.median(r[8] for r in done):.3f} | "
              f"{statistics.median(r[9] for r in done):.3f} | {statistics.median(r[6] for r in done):g} | "
              f"{statistics.median(r[10] for r in done):.2f}{f' ({late} timed out)' if late else ''} | {cert} |")


if __name__ == "__main__":
    main()
