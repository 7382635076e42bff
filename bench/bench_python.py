#!/usr/bin/env python3
"""Overhead of the Python bindings (engine/python) against the C++ Google Benchmarks that do the same work.

Run from the repository root after building the module (and, for the comparison, the C++ benchmarks):

    cmake --build build/release --target keel_python bench_pgo bench_cov -j2
    PYTHONPATH=build/release/python /usr/bin/python3 bench/bench_python.py [--repeat N] [--threads 1 2]
    PYTHONPATH=build/release/python /usr/bin/python3 bench/bench_python.py --cpp build/release/bench

With --cpp DIR each line first runs its C++ benchmark from DIR (Google Benchmark, --benchmark_repetitions=N,
median of the repetitions), then the Python timing, and prints both side by side with the overhead of the
bindings, (Python − C++) / C++: one run, one machine, interleaved so that a drift of the machine's speed hits both.

Each line times the same engine work as one C++ benchmark, with the same inputs and options, and prints the
median (and min) of N wall-clock repetitions (time.perf_counter) in milliseconds. Compare with the C++ medians of

    build/release/bench/bench_pgo --benchmark_filter='BM_Manhattan3500/<threads>/' --benchmark_repetitions=N
    build/release/bench/bench_cov --benchmark_filter='BM_Factorize|BM_AllPairMarginals' --benchmark_repetitions=N

(`--benchmark_report_aggregates_only=true` prints the median directly):

  python line                            C++ benchmark                                  work
  solve manhattan3500 threads=T          BM_Manhattan3500/T/real_time (bench_pgo)       pgo::optimize of
                                                                                        manhattanOlson3500.txt,
                                                                                        initial_guess = odometry,
                                                                                        threads = T, other options
                                                                                        default
  factorize (MarginalCovariance)         BM_Factorize (bench_cov)                       information matrix at the
                                                                                        ground truth + CHOLMOD
                                                                                        analysis/factorization,
                                                                                        default CovarianceOptions
  pairs config=C threads=T               BM_AllPairMarginals/config:C/threads:T/        pair_marginals_2d of the
                                         real_time (bench_cov)                          44 425 pairs (i, i+k),
                                                                                        k in {5,..,50,100,200,500},
                                                                                        on a factor made once;
                                                                                        config 0 = defaults,
                                                                                        1 = METIS, 2 = solve
  marginals (one call) threads=T         BM_MarginalsOneCall/threads:T/real_time        keel.marginals: both of the
                                         (bench_cov)                                    above in one call (with two
                                                                                        threads CHOLMOD's BLAS
                                                                                        threads, still spinning after
                                                                                        the factorization, slow the
                                                                                        extraction down in C++ too)

The Python timings include what the bindings add: argument conversion (numpy -> engine types, e.g. the ground-
truth poses and the 44 425 pairs), releasing/re-acquiring the GIL, and building the numpy results (the solution
poses; the (44 425, 6, 6) array, 12.8 MB). The C++ BM_AllPairMarginals keeps its std::vector<Mat6> result, so
the copy into numpy is overhead that the bindings add. Inputs are read once, outside the timed region, as the C++
benchmarks do. On a shared or busy machine run both programs back to back, several times.
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np

import keel

KS = (5, 10, 15, 20, 25, 30, 35, 40, 45, 50, 100, 200, 500)


def timed(fn, repeat):
    fn()  # warm-up (first touch of memory, CHOLMOD workspaces), as Google Benchmark's first iterations
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times)


UNITS = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def cpp_median(cpp_dir, program, names, repeat):
    """Median real time in seconds of the C++ benchmarks `names` (summed) of build/.../bench/<program>."""
    pattern = "^(" + "|".join(names) + ")$"
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        subprocess.run([os.path.join(cpp_dir, program), f"--benchmark_filter={pattern}",
                        f"--benchmark_repetitions={repeat}", "--benchmark_report_aggregates_only=true",
                        f"--benchmark_out={f.name}", "--benchmark_out_format=json"], capture_output=True, check=True)
        results = json.load(open(f.name))["benchmarks"]
    medians = {b["run_name"]: b["real_time"] * UNITS[b["time_unit"]]
               for b in results if b.get("aggregate_name") == "median"}
    missing = [n for n in names if n not in medians]
    if missing:
        raise SystemExit(f"{program}: no result for {missing} (got {sorted(medians)})")
    return sum(medians[n] for n in names)


class Reporter:
    """Prints one line per piece of work. With --cpp DIR: `rounds` times, the C++ benchmark (median of `repeat`
    repetitions) and then the Python timing (median of `repeat`), alternately, so that a drift of the machine's
    speed hits both; the overhead is the median over the rounds of (Python − C++) / C++, with its range."""

    def __init__(self, cpp_dir, repeat, rounds):
        self.cpp_dir, self.repeat, self.rounds, self.rows = cpp_dir, repeat, rounds, []

    def __call__(self, name, compare, fn, cpp=None):
        if not (self.cpp_dir and cpp):
            med, best = timed(fn, self.repeat)
            print(f"{name:<40} median {med * 1e3:9.2f} ms   min {best * 1e3:9.2f} ms   vs {compare}", flush=True)
            return
        py, c, ratio = [], [], []
        for _ in range(self.rounds):
            c.append(cpp_median(self.cpp_dir, cpp[0], cpp[1], self.repeat))
            py.append(timed(fn, self.repeat)[0])
            ratio.append(py[-1] / c[-1] - 1.0)
        row = (name, statistics.median(py), statistics.median(c), statistics.median(ratio), min(ratio), max(ratio))
        self.rows.append(row)
        print(f"{name:<40} Python {row[1] * 1e3:9.2f} ms   C++ {row[2] * 1e3:9.2f} ms   overhead "
              f"{row[3] * 100:+6.1f} % ({row[4] * 100:+.1f} … {row[5] * 100:+.1f} % over {self.rounds} rounds)   "
              f"[{' + '.join(cpp[1])}]", flush=True)

    def summary(self):
        if not self.rows:
            return
        print(f"\nside by side (medians over {self.rounds} rounds of {self.repeat} repetitions, ms):")
        print(f"  {'work':<38} {'Python':>9} {'C++':>9} {'overhead':>9}   range over the rounds")
        for name, py, c, o, lo, hi in self.rows:
            print(f"  {name:<38} {py * 1e3:9.2f} {c * 1e3:9.2f} {o * 100:+8.1f} %   {lo * 100:+.1f} … {hi * 100:+.1f} %")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5, help="timed repetitions per line (median reported)")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts (as the C++ args)")
    ap.add_argument("--configs", type=int, nargs="+", default=[0, 1, 2], help="BM_AllPairMarginals configs")
    ap.add_argument("--skip-solve", action="store_true")
    ap.add_argument("--skip-marginals", action="store_true")
    ap.add_argument("--rounds", type=int, default=3, help="with --cpp: alternating C++/Python rounds per line")
    ap.add_argument("--cpp", metavar="DIR", help="run the C++ benchmarks from DIR beside each line (bench_pgo, bench_cov)")
    a = ap.parse_args()
    report = Reporter(a.cpp, a.repeat, a.rounds)

    graph = keel.read_graph(keel.dataset_file("manhattan3500", "isam/manhattanOlson3500.txt"))

    if not a.skip_solve:
        for t in a.threads:
            r = keel.solve(graph, init="odometry", threads=t)
            report(f"solve manhattan3500 threads={t}", f"bench_pgo BM_Manhattan3500/{t}/real_time",
                   lambda: keel.solve(graph, init="odometry", threads=t),
                   ("bench_pgo", [f"BM_Manhattan3500/{t}/real_time"]))
            print(f"{'':40} iterations {r.iterations}, final cost {r.cost:.6f}, {r.termination}")

    if not a.skip_marginals:
        truth = keel.read_poses(
            keel.dataset_file("manhattan3500", "derived/manhattanOlson3500_groundtruth_poses.txt"), dim=2)
        n = truth.shape[0]
        pairs = np.array([(i, i + k) for k in KS for i in range(n - k)], dtype=np.int64)
        assert pairs.shape == (44425, 2), pairs.shape
        report("factorize (MarginalCovariance)", "bench_cov BM_Factorize",
               lambda: keel.MarginalCovariance(graph, poses=truth), ("bench_cov", ["BM_Factorize"]))
        configs = {0: {}, 1: {"ordering": "metis"}, 2: {"extraction": "solve"}}
        for c in a.configs:
            opts = configs[c]
            mc = keel.MarginalCovariance(graph, poses=truth, **opts)
            for t in a.threads:
                report(f"pairs config={c} threads={t}",
                       f"bench_cov BM_AllPairMarginals/config:{c}/threads:{t}/real_time",
                       lambda: mc.pairs(pairs, threads=t),
                       ("bench_cov", [f"BM_AllPairMarginals/config:{c}/threads:{t}/real_time"]))
        for t in a.threads:
            report(f"marginals (one call) threads={t}", f"bench_cov BM_MarginalsOneCall/threads:{t}",
                   lambda: keel.marginals(graph, poses=truth, pairs=pairs, threads=t),
                   ("bench_cov", [f"BM_MarginalsOneCall/threads:{t}/real_time"]))
    report.summary()


if __name__ == "__main__":
    main()
