"""What the side-by-side summaries share (robust.py --summary-json, certified_summary.py): their provenance and the
file the report renders beside an experiment, results/<id>/side_by_side.json (repro/report.hpp gives the format)."""
import json
import os
import subprocess
import sys
import time


def provenance(pairs, prog, stamp=False):
    """The --provenance KEY=VALUE pairs as a dict. With `stamp`, first what this checkout and machine say of the run:
    the keel commit (with "with uncommitted changes" when engine/ or bench/ differ from it), today's date (UTC) and
    the processor with its CPU count; a pair given by hand replaces the stamped entry of its key."""
    out = {}
    if stamp:
        repo = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
        git = lambda *args: subprocess.run(["git", "-C", repo, *args], capture_output=True, text=True)
        sha = git("rev-parse", "--short=7", "HEAD").stdout.strip()
        if git("diff", "--quiet", "HEAD", "--", "engine", "bench").returncode != 0:
            sha += " with uncommitted changes"
        model = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                      if line.startswith("model name")), "unknown processor")
        out = {"keel_commit": sha, "date": time.strftime("%Y-%m-%d", time.gmtime()),
               "machine": f"{model}, {os.cpu_count()} CPUs"}
    for kv in pairs:
        if "=" not in kv or not kv.split("=", 1)[0]:
            sys.exit(f"{prog}: --provenance takes KEY=VALUE (got {kv!r})")
        key, value = kv.split("=", 1)
        out[key] = value
    return out


def write(path, title, what, prov, tables):
    """The report's side-by-side file: every value a string."""
    doc = {"title": title, "what": what, "provenance": prov, "tables": tables}
    with open(path, "w") as out:
        json.dump(doc, out, indent=1, ensure_ascii=False)
        out.write("\n")
