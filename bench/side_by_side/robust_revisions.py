#!/usr/bin/env python3
"""Two builds of `keel robust` side by side on the same prepared graphs: same answers, and how long each takes.

Each input of a list written by keel_robust_graphs (lines "KEY=FILE TRUE [REFERENCE]" for one robot, "KEY=F0,F1,...
CANDIDATES TRUE WRONG_FILE [REFERENCE]" for several) is run by both binaries, one thread each:
`keel robust FILES... [--candidates C] --json -q --p P --threads 1`. The two alternate on each input, and which of
them goes first alternates between inputs. Each whole process is timed (file reading included, the same for both)
beside the report's own residual-check time.

"Same answers" compares the two JSON reports whole, apart from their times and the test statistics (snooping_t,
residual_group_t, residual_chi2), with every number rounded to six significant digits. It covers the kept flags and
reasons, the rounds, gamma, the clique's status and bound, the certificate's status, gap, costs and bounds, and the
exit codes.

  robust_revisions.py OLD_KEEL NEW_KEEL OUT.tsv LIST... [--p 0.11]

Writes one TSV row per input, prints the count of identical answers, the time sums and one line per data set and
robot count, and exits 1 if any answer differs.
"""
import argparse
import collections
import json
import subprocess
import sys
import time

STATISTICS = ("snooping_t", "residual_group_t", "residual_chi2")


def comparable(d):
    if isinstance(d, dict):
        return {k: comparable(v) for k, v in d.items() if "time" not in k and k not in STATISTICS}
    if isinstance(d, list):
        return [comparable(x) for x in d]
    if isinstance(d, float):
        return float(f"{d:.6g}")
    return d


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("out")
    ap.add_argument("lists", nargs="+")
    ap.add_argument("--p", default="0.11")
    a = ap.parse_args()
    rows = []
    for lst in a.lists:
        with open(lst) as f:
            lines = [line.strip() for line in f if line.strip()]
        for line in lines:
            key, rest = line.split("=", 1)
            fields = rest.split(" ")
            robots = key.split(".")[1]
            args = fields[0].split(",") + ["--candidates", fields[1]] if robots != "r1" else [fields[0]]
            order = [("old", a.old), ("new", a.new)]
            if len(rows) % 2:
                order.reverse()
            res = {}
            for tag, binary in order:
                t0 = time.perf_counter()
                p = subprocess.run([binary, "robust", *args, "--json", "-q", "--p", a.p, "--threads", "1"],
                                   capture_output=True, text=True)
                wall = time.perf_counter() - t0
                try:
                    report = json.loads(p.stdout)
                except json.JSONDecodeError:
                    report = {}
                res[tag] = (p.returncode, wall, report)
            (rc_o, w_o, d_o), (rc_n, w_n, d_n) = res["old"], res["new"]
            same = rc_o == rc_n and comparable(d_o) == comparable(d_n)
            if not same:
                print(f"robust_revisions.py: the answers differ on {key}", file=sys.stderr)
            rows.append((key, rc_o, rc_n, same, w_o, w_n, d_o.get("times_s", {}).get("residual_solves", 0.0),
                         d_n.get("times_s", {}).get("residual_solves", 0.0)))
    with open(a.out, "w") as f:
        f.write("key\trc_old\trc_new\tsame\twall_old\twall_new\tresidual_old\tresidual_new\n")
        for r in rows:
            f.write("\t".join(str(x) for x in r) + "\n")
    tot = [sum(r[i] for r in rows) for i in range(4, 8)]
    print(f"{len(rows)} inputs, answers identical on {sum(r[3] for r in rows)}")
    print(f"all: process {tot[0]:.2f} -> {tot[1]:.2f} s ({tot[1] / tot[0]:.3f}), "
          f"residual check {tot[2]:.2f} -> {tot[3]:.2f} s")
    by = collections.defaultdict(lambda: [0.0] * 4)
    for r in rows:
        group = ".".join(r[0].split(".")[:2])
        for i in range(4):
            by[group][i] += r[4 + i]
    for group, v in sorted(by.items()):
        print(f"{group}: process {v[0]:.2f} -> {v[1]:.2f} s ({v[1] / v[0]:.3f}), "
              f"residual check {v[2]:.2f} -> {v[3]:.2f} s")
    sys.exit(0 if all(r[3] for r in rows) else 1)


if __name__ == "__main__":
    main()
