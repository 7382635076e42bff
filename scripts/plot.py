#!/usr/bin/env python3
"""keel figure renderer: results/<id>/latest.json "figures" -> PNG files.

Usage:
    plot.py [--results results] [--out paper/figures] [ids...]

Renders every figure spec found in results/<id>/latest.json (all ids, or only
the ids given) to <out>/<file> as PNG (dpi 150, Agg backend) and prints one
line per written file.  The renderer is generic: it knows nothing about any
experiment.  Needs Python 3 + matplotlib + jsonschema (use scripts/plot, which
finds an interpreter that has matplotlib; Debian: python3-matplotlib,
python3-jsonschema).

Exit status: 0 success (also when there is nothing to plot), 1 on a malformed
spec / missing latest.json / render failure, 2 on bad command-line usage.
All specs of all requested ids are validated before anything is written, so a
malformed spec leaves <out> untouched.

The contract (the "figures" key of latest.json) is scripts/figure_schema.json,
a JSON Schema (draft 2020-12) whose descriptions say what every key means;
scripts/figure_spec.py validates specs against it plus the checks a schema
cannot express, and normalizes them for drawing.  Error messages name the json
file and the offending key path, e.g.
    results/foo/latest.json: figures[0].panels[1].layers[2].y: length 4 != len(x) 5
Output is deterministic: no timestamps / version strings are embedded, so the
same spec gives byte-identical PNGs on the same matplotlib install.
"""

import argparse
import os
import sys
import tempfile

os.environ.setdefault("SOURCE_DATE_EPOCH", "0")
os.environ.setdefault("MPLBACKEND", "Agg")

try:
    import matplotlib
except ImportError:  # pragma: no cover - depends on the interpreter
    sys.stderr.write(
        "plot.py: error: matplotlib is not importable by %s\n"
        "  run scripts/plot (it picks a Python that has matplotlib), or\n"
        "  apt-get install python3-matplotlib\n" % sys.executable)
    sys.exit(1)

matplotlib.use("Agg")
from matplotlib import colors as mcolors  # noqa: E402
from matplotlib import markers as mmarkers  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figure_spec  # noqa: E402
from figure_spec import SpecError  # noqa: E402

DPI = 150

STYLE = {
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "legend.fontsize": 9,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "figure.titlesize": 13,
    "axes.grid": True,
    "grid.alpha": 0.35,
    "grid.linestyle": "-",
    "grid.linewidth": 0.6,
    "axes.axisbelow": True,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.5,
    "legend.frameon": True,
    "legend.framealpha": 0.85,
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
    "svg.hashsalt": "keel",
    "path.simplify": True,
}

# ----------------------------------------------------------------------------
# rendering

def _norm(L):
    if L["vmin"] is None and L["vmax"] is None:
        return None
    return mcolors.Normalize(vmin=L["vmin"], vmax=L["vmax"])


def _opt(**kw):
    return {k: v for k, v in kw.items() if v is not None}


def draw_layer(ax, L):
    """Draw one layer; returns (has_label, mappable_or_None)."""
    t = L["type"]
    if L["empty"]:
        return False, None
    common = _opt(label=L["label"], alpha=L["alpha"])
    mappable = None
    if t == "line":
        ax.plot(L["x"], L["y"], **common, **_opt(
            color=L["color"], marker=L["marker"], linestyle=L["linestyle"],
            linewidth=L["linewidth"]))
    elif t == "scatter":
        kw = _opt(s=L["size"], marker=L["marker"])
        if L["c"] is not None:
            kw.update(_opt(c=L["c"], cmap=L["cmap"], norm=_norm(L)))
        else:
            kw.update(_opt(color=L["color"]))
        if "s" not in kw:
            kw["s"] = 12.0
        if mmarkers.MarkerStyle(L["marker"] or "o").is_filled():
            kw["linewidths"] = 0  # no edge halo around filled markers
        mappable = ax.scatter(L["x"], L["y"], **common, **kw)
        if L["c"] is None:
            mappable = None
    elif t == "segments":
        segs = [((a, b), (c, d)) for a, b, c, d in
                zip(L["x0"], L["y0"], L["x1"], L["y1"])]
        lc = LineCollection(segs, **common, **_opt(linewidths=L["linewidth"]))
        if L["c"] is not None:
            lc.set_array(L["c"])
            if L["cmap"] is not None:
                lc.set_cmap(L["cmap"])
            n = _norm(L)
            if n is not None:
                lc.set_norm(n)
            lc.update_scalarmappable()  # so a legend entry shows mapped colour
            mappable = lc
        else:
            lc.set_color(L["color"] if L["color"] is not None else "C0")
        ax.add_collection(lc)
        ax.autoscale_view()
    elif t == "hline":
        ax.axhline(L["y"], **common, **_opt(
            color=L["color"] if L["color"] is not None else "0.3",
            linestyle=L["linestyle"] if L["linestyle"] is not None else "--",
            linewidth=L["linewidth"] if L["linewidth"] is not None else 1.0))
    elif t == "vline":
        ax.axvline(L["x"], **common, **_opt(
            color=L["color"] if L["color"] is not None else "0.3",
            linestyle=L["linestyle"] if L["linestyle"] is not None else "--",
            linewidth=L["linewidth"] if L["linewidth"] is not None else 1.0))
    return bool(L["label"]), mappable


def draw_panel(fig, ax, P):
    labelled = False
    last_mappable = None
    for L in P["layers"]:
        has_label, m = draw_layer(ax, L)
        labelled = labelled or has_label
        if m is not None:
            last_mappable = m
    if P["xscale"]:
        ax.set_xscale(P["xscale"])
    if P["yscale"]:
        ax.set_yscale(P["yscale"])
    if P["xlim"] is not None:
        ax.set_xlim(*P["xlim"])
    if P["ylim"] is not None:
        ax.set_ylim(*P["ylim"])
    if P["xticks"] is not None:
        ax.set_xticks(P["xticks"])
        if P["xticklabels"] is not None:
            ax.set_xticklabels(P["xticklabels"], rotation=45, ha="right", rotation_mode="anchor")
            ax.minorticks_off()
    if P["aspect"]:
        ax.set_aspect(P["aspect"], adjustable="datalim" if P["aspect"] == "equal"
                      and (P["xlim"] is None or P["ylim"] is None) else "box")
    if P["title"]:
        ax.set_title(P["title"])
    if P["xlabel"]:
        ax.set_xlabel(P["xlabel"])
    if P["ylabel"]:
        ax.set_ylabel(P["ylabel"])
    loc = P["legend"]
    if loc is None:
        loc = "best" if labelled else "none"
    if loc != "none" and labelled:
        ax.legend(loc=loc)
    if P["colorbar"] is not None and last_mappable is not None:
        cb = fig.colorbar(last_mappable, ax=ax)
        cb.set_label(P["colorbar"])


def render_figure(F, out_path):
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=F["size"], dpi=DPI)
        FigureCanvasAgg(fig)
        rows, cols = F["layout"]
        axes = fig.subplots(rows, cols, squeeze=False)
        flat = [a for row in axes for a in row]
        for ax, P in zip(flat, F["panels"]):
            draw_panel(fig, ax, P)
        for ax in flat[len(F["panels"]):]:
            ax.set_visible(False)
        if F["title"]:
            fig.suptitle(F["title"])
        fig.tight_layout()
        out_dir = os.path.dirname(out_path) or "."
        fd, tmp = tempfile.mkstemp(prefix=".plot-", suffix=".png", dir=out_dir)
        os.close(fd)
        try:
            fig.savefig(tmp, dpi=DPI, format="png",
                        metadata={"Software": None})
            os.chmod(tmp, 0o644)
            os.replace(tmp, out_path)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise


# ----------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="plot.py",
        description="Render results/<id>/latest.json \"figures\" specs to PNG. "
                    "The contract is scripts/figure_schema.json.")
    ap.add_argument("--results", default="results",
                    help="results directory (default: results)")
    ap.add_argument("--out", default=os.path.join("paper", "figures"),
                    help="output directory (default: paper/figures)")
    ap.add_argument("ids", nargs="*",
                    help="experiment ids (results/<id>); default: all")
    args = ap.parse_args(argv)

    def die(msg):
        sys.stderr.write("plot.py: error: %s\n" % msg)
        return 1

    if not os.path.isdir(args.results):
        return die("results directory %r does not exist" % args.results)

    if args.ids:
        jobs = []
        for i in args.ids:
            rid = i.rstrip("/")
            if not rid or "/" in rid or rid in (".", ".."):
                return die("bad id %r: expected a directory name under %s"
                           % (i, args.results))
            p = os.path.join(args.results, rid, "latest.json")
            if not os.path.isfile(p):
                return die("%s: missing (no latest.json for id %r; run its "
                           "driver first)" % (p, rid))
            jobs.append(p)
    else:
        jobs = [os.path.join(args.results, d, "latest.json")
                for d in sorted(os.listdir(args.results))
                if os.path.isfile(os.path.join(args.results, d, "latest.json"))]

    # Validate everything first: a malformed spec writes nothing.
    todo = []
    names = figure_spec.FileNames()
    try:
        for p in jobs:
            for k, F in enumerate(figure_spec.load_figures(p)):
                names.add(p, k, F["file"])
                todo.append((p, k, F))
    except SpecError as e:
        return die(str(e))

    if not todo:
        print("plot.py: no figures in %s (%d latest.json file%s checked)"
              % (args.results, len(jobs), "" if len(jobs) == 1 else "s"))
        return 0

    try:
        os.makedirs(args.out, exist_ok=True)
    except OSError as e:
        return die("cannot create output directory %r: %s" % (args.out, e))

    for p, k, F in todo:
        out_path = os.path.join(args.out, F["file"])
        try:
            render_figure(F, out_path)
        except Exception as e:  # render-time failure: still name the spec
            return die("%s: figures[%d] (%s): rendering failed: %s: %s"
                       % (p, k, F["file"], type(e).__name__, e))
        print(out_path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
