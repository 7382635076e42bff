#!/usr/bin/env python3
"""The rows of bench/side_by_side/certified.sh (keel's certified solve and SE-Sync, one thread each) as the tables
the report renders beside an experiment: results/<id>/side_by_side.json (repro/report.hpp gives the format).

  certified_summary.py ROWS.tsv OUT.json [--stamp] [--provenance KEY=VALUE ...]

A graph's level is its name's second field (ext_certified_noise's <graph>.<level>.d<k>: rot0p1 is rotation noise
σ = 0.1 rad on the loop closures, out10 is 10 % of them replaced by outliers); names without one form one level.
Tables: per level, the certificates, the time ratios keel / SE-Sync by both timing rules (the whole process, and
each tool's own timer), the graphs where keel's process time is within 2× of SE-Sync's and where keel is faster,
and the two cross-checks of the answers (keel's F at most SE-Sync's, to 1e-9 relative; keel's proven lower bound at
most SE-Sync's SDP value where SE-Sync reports GlobalOpt); then every graph. Every number comes from the rows.
"""
import argparse
import os
import re
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import side_by_side  # noqa: E402  (beside this file)

COLUMNS = ["dataset", "keel_F", "keel_lower", "keel_gap", "keel_status", "keel_rank", "keel_iterations", "keel_own_s",
           "keel_process_s", "sesync_F", "sesync_SDPval", "sesync_status", "sesync_rank", "sesync_own_s",
           "sesync_process_s", "faster_own", "faster_process"]


def level_of(name):
    parts = name.split(".")
    if len(parts) < 2:
        return "—"
    t = parts[1]
    if m := re.fullmatch(r"rot([0-9]+)(?:p([0-9]+))?", t):
        return f"σ = {m.group(1)}{'.' + m.group(2) if m.group(2) else ''} rad"
    if m := re.fullmatch(r"out([0-9]+)", t):
        return f"{m.group(1)} % outliers"
    return t


def number(row, key, path, line):
    try:
        return float(row[key])
    except ValueError:
        sys.exit(f"certified_summary.py: {path}:{line}: {key} is {row[key]!r}, not a number (a failed run?)")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("rows")
    ap.add_argument("out")
    ap.add_argument("--provenance", action="append", default=[], help="KEY=VALUE, shown as given")
    ap.add_argument("--stamp", action="store_true", help="also name the keel commit, the date and the machine")
    a = ap.parse_args()
    provenance = side_by_side.provenance(a.provenance, "certified_summary.py", a.stamp)
    graphs = []
    with open(a.rows) as f:
        header = f.readline().rstrip("\n").split("\t")
        if header != COLUMNS:
            sys.exit(f"certified_summary.py: {a.rows} is not a TSV of certified.sh (header {header})")
        for line, text in enumerate(f, start=2):
            v = text.rstrip("\n").split("\t")
            if len(v) != len(COLUMNS):
                sys.exit(f"certified_summary.py: {a.rows}:{line}: {len(v)} fields, expected {len(COLUMNS)}")
            row = dict(zip(COLUMNS, v))
            if not row["sesync_status"]:
                sys.exit(f"certified_summary.py: {a.rows}:{line}: no SE-Sync result (run with SESYNC_MEASURE)")
            g = {"name": row["dataset"], "level": level_of(row["dataset"]), "row": row}
            for k in ("keel_F", "keel_own_s", "keel_process_s", "sesync_F", "sesync_SDPval", "sesync_own_s",
                      "sesync_process_s"):
                g[k] = number(row, k, a.rows, line)
            g["keel_lower"] = None if row["keel_lower"] == "none" else number(row, "keel_lower", a.rows, line)
            g["certified"] = row["keel_status"] == "certified"
            g["global_opt"] = row["sesync_status"] == "GlobalOpt"
            g["process_ratio"] = g["keel_process_s"] / g["sesync_process_s"]
            g["own_ratio"] = g["keel_own_s"] / g["sesync_own_s"] if g["sesync_own_s"] > 0 else float("inf")
            g["f_ok"] = g["keel_F"] <= g["sesync_F"] + 1e-9 * abs(g["sesync_F"])
            g["bound_ok"] = g["keel_lower"] is None or g["keel_lower"] <= g["sesync_SDPval"]
            graphs.append(g)
    if not graphs:
        sys.exit(f"certified_summary.py: {a.rows} has no rows")
    levels = list(dict.fromkeys(g["level"] for g in graphs))
    per_level = []
    for lv in levels + ["all"]:
        sel = [g for g in graphs if lv == "all" or g["level"] == lv]
        pr, orr = [g["process_ratio"] for g in sel], [g["own_ratio"] for g in sel]
        opt = [g for g in sel if g["global_opt"]]
        per_level.append([
            lv, str(len(sel)), str(sum(g["certified"] for g in sel)), str(len(opt)),
            f"{statistics.median(pr):.2f}", f"{max(pr):.2f}", str(sum(r <= 2.0 for r in pr)),
            str(sum(g["keel_process_s"] < g["sesync_process_s"] for g in sel)),
            f"{statistics.median(orr):.2f}", f"{max(orr):.2f}",
            f"{sum(g['f_ok'] for g in sel)} of {len(sel)}",
            f"{sum(g['bound_ok'] for g in opt)} of {len(opt)}"])
    per_graph = []
    for g in graphs:
        r = g["row"]
        per_graph.append([
            g["name"], r["keel_F"], r["keel_lower"], f"{r['keel_status']} ({r['keel_rank']})", r["keel_own_s"],
            r["keel_process_s"], r["sesync_F"], r["sesync_SDPval"], f"{r['sesync_status']} ({r['sesync_rank']})",
            r["sesync_own_s"], r["sesync_process_s"], f"{g['process_ratio']:.2f}"])
    what = (f"{len(graphs)} graphs, each tool on each file, one thread each (OpenMP serialized in both). Two timing "
            "rules for both tools: the whole process from exec to exit (file reading and problem construction "
            "included, timed the same way for both), and each tool's own timer (keel's times_s.total; SE-Sync's "
            "total_computation_time, which leaves out its problem construction). \"Certified\" is keel's proven "
            "bound within its gap tolerance; SE-Sync's GlobalOpt says its rank-r point is optimal for the "
            "relaxation, not that its rounded answer is. The acceptance rule asks keel within 2× of SE-Sync's "
            "process time on every graph.")
    side_by_side.write(a.out, "keel's certified solve and SE-Sync on the same files", what, provenance, [
        {"caption": "Per level: certificates, time ratios keel / SE-Sync, and the answers cross-checked",
         "header": ["level", "graphs", "keel certified", "SE-Sync GlobalOpt", "process ratio: median",
                    "process ratio: max", "within 2×", "keel faster", "own-timer ratio: median",
                    "own-timer ratio: max", "keel F ≤ SE-Sync F", "keel bound ≤ SE-Sync SDPval (GlobalOpt)"],
         "rows": per_level},
        {"caption": "Per graph (seconds are medians over the runs of each tool)",
         "header": ["graph", "keel F", "keel bound", "keel status (rank)", "keel own s", "keel process s",
                    "SE-Sync F", "SE-Sync SDPval", "SE-Sync status (rank)", "SE-Sync own s", "SE-Sync process s",
                    "process ratio"],
         "rows": per_graph},
    ])


if __name__ == "__main__":
    main()
