#!/usr/bin/env python3
"""keel figure renderer: results/<id>/latest.json "figures" -> PNG files.

Usage:
    plot.py [--results results] [--out paper/figures] [ids...]

Renders every figure spec found in results/<id>/latest.json (all ids, or only
the ids given) to <out>/<file> as PNG (dpi 150, Agg backend) and prints one
line per written file.  The renderer is generic: it knows nothing about any
experiment.  Needs Python 3 + matplotlib only (use scripts/plot, which finds
an interpreter that has matplotlib).

Exit status: 0 success (also when there is nothing to plot), 1 on a malformed
spec / missing latest.json / render failure, 2 on bad command-line usage.
All specs of all requested ids are validated before anything is written, so a
malformed spec leaves <out> untouched.

CONTRACT (the "figures" key of latest.json)
==========================================
"figures": [                                   # list; absent or [] = no figures
  { "file":   "ch5_fig5_6_relative_pose.png",  # REQUIRED. bare file name ending in
                                               #   .png; no '/', '\\' or '..';
                                               #   unique across everything rendered
    "title":  "optional suptitle",
    "layout": [rows, cols],                    # optional, default [1, len(panels)];
                                               #   rows*cols >= len(panels); panels
                                               #   fill row-major, spare cells hidden
    "size":   [w_inches, h_inches],            # optional, default [5.5*cols, 4.5*rows]
    "panels": [                                # REQUIRED, non-empty
      { "title": "...", "xlabel": "...", "ylabel": "...",       # optional strings
        "xscale": "linear"|"log"|"logit", "yscale": "linear"|"log"|"logit",     # optional
        "aspect": "equal"|"auto",                                # optional
        "xlim": [a, b], "ylim": [a, b],                          # optional numbers
        "legend": "best"|"none"|<matplotlib loc string>,         # optional; default
                                  #   "best" if any drawn layer has a label, else none
        "colorbar": "label text", # optional: colorbar for the last layer with "c"
                                  #   (error if no layer has "c")
        "layers": [                                              # REQUIRED list
          {"type": "line", "x": [...], "y": [...],
           "label": str, "color": str, "marker": str, "linestyle": str,
           "linewidth": num, "alpha": num},
                                  # line and scatter may give "y_timings":
                                  #   [names...] instead of "y": the values are
                                  #   looked up in the same file's "timings_s"
                                  #   object (wall times, kept out of the figure
                                  #   data so result files stay comparable)
          {"type": "scatter", "x": [...], "y": [...],
           "label": str, "color": str, "size": num (points^2), "alpha": num,
           "marker": str,
           "c": [...], "cmap": str, "vmin": num, "vmax": num},  # c: len(x) values,
                                                               #   overrides color
          {"type": "segments", "x0": [...], "y0": [...], "x1": [...], "y1": [...],
           "c": [...], "cmap": str, "vmin": num, "vmax": num,  # c optional
           "color": str, "linewidth": num, "alpha": num, "label": str},
                                  # LineCollection of (x0,y0)-(x1,y1), coloured by c
          {"type": "hline", "y": num, "label": str, "color": str,
           "linestyle": str, "linewidth": num, "alpha": num},
          {"type": "vline", "x": num, ...same optional keys as hline...}
        ] } ] } ]

Rules:
  * Every key not listed above is an error (catches typos), except keys that
    start with "_" (free-form comments / metadata, ignored).
  * Data arrays are JSON lists of finite numbers (int or float; no bool, no
    null, no NaN/Infinity).  Arrays of one layer must have equal lengths
    (x/y; x0/y0/x1/y1; and c when present).
  * A layer whose data arrays are empty is skipped (its label too).
  * Nothing is sorted; layers are drawn in the given order.
  * Error messages name the json file and the offending key path, e.g.
      results/foo/latest.json: figures[0].panels[1].layers[2].y: length 4 != len(x) 5
  * Output is deterministic: no timestamps / version strings are embedded, so
    the same spec gives byte-identical PNGs on the same matplotlib install.
"""

import argparse
import json
import math
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

LEGEND_LOCS = ("best", "upper right", "upper left", "lower left", "lower right",
               "right", "center left", "center right", "lower center",
               "upper center", "center")
LINESTYLES = ("-", "--", "-.", ":", "solid", "dashed", "dashdot", "dotted",
              "none", "None", "")
SCALES = ("linear", "log", "logit")  # logit: probabilities in (0, 1), e.g. thresholds p near 0 and 1
ASPECTS = ("equal", "auto")

FIGURE_KEYS = {"file", "title", "layout", "size", "panels"}
PANEL_KEYS = {"title", "xlabel", "ylabel", "xscale", "yscale", "aspect", "xlim",
              "ylim", "legend", "colorbar", "layers"}
LAYER_KEYS = {
    "line": {"type", "x", "y", "y_timings", "label", "color", "marker",
             "linestyle", "linewidth", "alpha"},
    "scatter": {"type", "x", "y", "y_timings", "label", "color", "size",
                "alpha", "marker", "c", "cmap", "vmin", "vmax"},
    "segments": {"type", "x0", "y0", "x1", "y1", "c", "cmap", "vmin", "vmax",
                 "color", "linewidth", "alpha", "label"},
    "hline": {"type", "y", "label", "color", "linestyle", "linewidth", "alpha"},
    "vline": {"type", "x", "label", "color", "linestyle", "linewidth", "alpha"},
}


class SpecError(Exception):
    """A malformed spec; message is '<json>: <key path>: <problem>'."""


# ----------------------------------------------------------------------------
# validation helpers (each returns the cleaned value or raises SpecError)

class Ctx:
    def __init__(self, src, path=""):
        self.src = src
        self.path = path

    def sub(self, key):
        if isinstance(key, int):
            return Ctx(self.src, "%s[%d]" % (self.path, key))
        return Ctx(self.src, "%s.%s" % (self.path, key) if self.path else key)

    def fail(self, msg):
        raise SpecError("%s: %s: %s" % (self.src, self.path or "<top>", msg))


def _is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _typename(v):
    return "null" if v is None else type(v).__name__


def check_keys(obj, allowed, ctx, what):
    if not isinstance(obj, dict):
        ctx.fail("%s must be a JSON object, got %s" % (what, _typename(obj)))
    for k in obj:
        if k not in allowed and not k.startswith("_"):
            ctx.sub(k).fail("unknown key %r for %s (allowed: %s)"
                            % (k, what, ", ".join(sorted(allowed))))


def get_num(obj, key, ctx, default=None, positive=False, unit=False):
    if key not in obj:
        return default
    v, c = obj[key], ctx.sub(key)
    if not _is_num(v) or not math.isfinite(v):
        c.fail("expected a finite number, got %s %r" % (_typename(v), v))
    if positive and not v > 0:
        c.fail("expected a number > 0, got %r" % (v,))
    if unit and not 0 <= v <= 1:
        c.fail("expected a number in [0, 1], got %r" % (v,))
    return float(v)


def get_str(obj, key, ctx, default=None, choices=None):
    if key not in obj:
        return default
    v, c = obj[key], ctx.sub(key)
    if not isinstance(v, str):
        c.fail("expected a string, got %s %r" % (_typename(v), v))
    if choices is not None and v not in choices:
        c.fail("expected one of %s, got %r" % (", ".join(repr(x) for x in choices), v))
    return v


def get_color(obj, key, ctx):
    v = get_str(obj, key, ctx)
    if v is not None and not mcolors.is_color_like(v):
        ctx.sub(key).fail("not a matplotlib color: %r" % (v,))
    return v


def get_marker(obj, key, ctx):
    v = get_str(obj, key, ctx)
    if v is not None:
        try:
            mmarkers.MarkerStyle(v)
        except (ValueError, TypeError):
            ctx.sub(key).fail("not a matplotlib marker: %r" % (v,))
    return v


def get_cmap(obj, key, ctx):
    v = get_str(obj, key, ctx)
    if v is not None and v not in matplotlib.colormaps:
        ctx.sub(key).fail("unknown colormap %r" % (v,))
    return v


def get_array(obj, key, ctx, required=True):
    if key not in obj:
        if required:
            ctx.sub(key).fail("missing required key")
        return None
    v, c = obj[key], ctx.sub(key)
    if not isinstance(v, list):
        c.fail("expected a list of numbers, got %s" % _typename(v))
    for i, e in enumerate(v):
        if not _is_num(e) or not math.isfinite(e):
            c.fail("element [%d] is not a finite number: %s %r"
                   % (i, _typename(e), e))
    return [float(e) for e in v]


def get_pair(obj, key, ctx, ints=False, positive=False, increasing=False):
    if key not in obj:
        return None
    v, c = obj[key], ctx.sub(key)
    if not isinstance(v, list) or len(v) != 2:
        c.fail("expected a list of 2 numbers, got %r" % (v,))
    for e in v:
        ok = _is_num(e) and math.isfinite(e)
        if ok and ints:
            ok = float(e).is_integer()
        if not ok:
            c.fail("expected 2 %s, got %r" % ("integers" if ints else "finite numbers", v))
        if positive and not e > 0:
            c.fail("expected 2 values > 0, got %r" % (v,))
    if increasing and v[0] == v[1]:
        c.fail("limits must differ, got %r" % (v,))
    return (int(v[0]), int(v[1])) if ints else (float(v[0]), float(v[1]))


def get_timings_y(obj, ctx, timings):
    """The "y_timings" names of a layer resolved against the file's timings_s."""
    c = ctx.sub("y_timings")
    if "y" in obj:
        c.fail("give either \"y\" or \"y_timings\", not both")
    names = obj["y_timings"]
    if not isinstance(names, list):
        c.fail("expected a list of timing names, got %s" % _typename(names))
    out = []
    for i, name in enumerate(names):
        if not isinstance(name, str):
            c.fail("element [%d] is not a string: %s %r" % (i, _typename(name), name))
        if name not in timings:
            c.fail("element [%d]: %r is not in \"timings_s\"" % (i, name))
        v = timings[name]
        if not _is_num(v) or not math.isfinite(v):
            c.fail("element [%d]: timings_s[%r] is not a finite number: %r" % (i, name, v))
        out.append(float(v))
    return out


def same_len(layer, keys, ctx, ref):
    n = len(layer[ref])
    for k in keys:
        if layer.get(k) is not None and len(layer[k]) != n:
            ctx.sub(k).fail("length %d != len(%s) %d" % (len(layer[k]), ref, n))


def validate_layer(raw, ctx, timings=None):
    if not isinstance(raw, dict):
        ctx.fail("layer must be a JSON object, got %s" % _typename(raw))
    if "type" not in raw:
        ctx.sub("type").fail("missing required key (one of %s)"
                             % ", ".join(sorted(LAYER_KEYS)))
    t = raw["type"]
    if t not in LAYER_KEYS:
        ctx.sub("type").fail("unknown layer type %r (known: %s)"
                             % (t, ", ".join(sorted(LAYER_KEYS))))
    check_keys(raw, LAYER_KEYS[t], ctx, "%s layer" % t)
    L = {"type": t,
         "label": get_str(raw, "label", ctx),
         "color": get_color(raw, "color", ctx),
         "alpha": get_num(raw, "alpha", ctx, unit=True)}
    if t in ("line", "hline", "vline", "segments"):
        L["linewidth"] = get_num(raw, "linewidth", ctx, positive=True)
    if t in ("line", "hline", "vline"):
        L["linestyle"] = get_str(raw, "linestyle", ctx, choices=LINESTYLES)
    if t in ("line", "scatter"):
        L["marker"] = get_marker(raw, "marker", ctx)
        L["x"] = get_array(raw, "x", ctx)
        if "y_timings" in raw:
            L["y"] = get_timings_y(raw, ctx, timings or {})
            if len(L["y"]) != len(L["x"]):
                ctx.sub("y_timings").fail("length %d != len(x) %d"
                                          % (len(L["y"]), len(L["x"])))
        else:
            L["y"] = get_array(raw, "y", ctx)
            same_len(L, ["y"], ctx, "x")
        L["empty"] = len(L["x"]) == 0
    if t in ("scatter", "segments"):
        L["c"] = get_array(raw, "c", ctx, required=False)
        L["cmap"] = get_cmap(raw, "cmap", ctx)
        L["vmin"] = get_num(raw, "vmin", ctx)
        L["vmax"] = get_num(raw, "vmax", ctx)
        if L["vmin"] is not None and L["vmax"] is not None and L["vmin"] > L["vmax"]:
            ctx.sub("vmin").fail("vmin %r > vmax %r" % (L["vmin"], L["vmax"]))
        if L["c"] is None:
            for k in ("cmap", "vmin", "vmax"):
                if k in raw:
                    ctx.sub(k).fail("given without \"c\"")
    if t == "scatter":
        L["size"] = get_num(raw, "size", ctx, positive=True)
        same_len(L, ["c"], ctx, "x")
    if t == "segments":
        for k in ("x0", "y0", "x1", "y1"):
            L[k] = get_array(raw, k, ctx)
        same_len(L, ["y0", "x1", "y1", "c"], ctx, "x0")
        L["empty"] = len(L["x0"]) == 0
    if t == "hline":
        if "y" not in raw:
            ctx.sub("y").fail("missing required key")
        L["y"] = get_num(raw, "y", ctx)
        L["empty"] = False
    if t == "vline":
        if "x" not in raw:
            ctx.sub("x").fail("missing required key")
        L["x"] = get_num(raw, "x", ctx)
        L["empty"] = False
    return L


def validate_panel(raw, ctx, timings=None):
    check_keys(raw, PANEL_KEYS, ctx, "panel")
    P = {
        "title": get_str(raw, "title", ctx),
        "xlabel": get_str(raw, "xlabel", ctx),
        "ylabel": get_str(raw, "ylabel", ctx),
        "xscale": get_str(raw, "xscale", ctx, choices=SCALES),
        "yscale": get_str(raw, "yscale", ctx, choices=SCALES),
        "aspect": get_str(raw, "aspect", ctx, choices=ASPECTS),
        "xlim": get_pair(raw, "xlim", ctx, increasing=True),
        "ylim": get_pair(raw, "ylim", ctx, increasing=True),
        "legend": get_str(raw, "legend", ctx, choices=LEGEND_LOCS + ("none",)),
        "colorbar": get_str(raw, "colorbar", ctx),
    }
    for k in ("xlim", "ylim"):
        scale = P["xscale" if k == "xlim" else "yscale"]
        if scale == "log" and P[k] is not None and min(P[k]) <= 0:
            ctx.sub(k).fail("log scale needs limits > 0, got %r" % (list(P[k]),))
        if scale == "logit" and P[k] is not None and (min(P[k]) <= 0 or max(P[k]) >= 1):
            ctx.sub(k).fail("logit scale needs limits inside (0, 1), got %r" % (list(P[k]),))
    if "layers" not in raw:
        ctx.sub("layers").fail("missing required key")
    layers = raw["layers"]
    if not isinstance(layers, list):
        ctx.sub("layers").fail("expected a list, got %s" % _typename(layers))
    P["layers"] = [validate_layer(l, ctx.sub("layers").sub(i), timings)
                   for i, l in enumerate(layers)]
    if P["colorbar"] is not None and not any(
            l.get("c") is not None for l in P["layers"]):
        ctx.sub("colorbar").fail("no layer in this panel has \"c\"")
    return P


def validate_figure(raw, ctx, timings=None):
    check_keys(raw, FIGURE_KEYS, ctx, "figure")
    if "file" not in raw:
        ctx.sub("file").fail("missing required key")
    f = get_str(raw, "file", ctx)
    fc = ctx.sub("file")
    if (not f or "/" in f or "\\" in f or ".." in f or f.startswith(".")
            or os.path.basename(f) != f):
        fc.fail("must be a bare file name (no directories, no '..'), got %r" % (f,))
    if not f.lower().endswith(".png"):
        fc.fail("must end in .png, got %r" % (f,))
    if "panels" not in raw:
        ctx.sub("panels").fail("missing required key")
    panels = raw["panels"]
    if not isinstance(panels, list) or not panels:
        ctx.sub("panels").fail("expected a non-empty list, got %r"
                               % (panels if not isinstance(panels, list) else "[]",))
    F = {"file": f, "title": get_str(raw, "title", ctx)}
    layout = get_pair(raw, "layout", ctx, ints=True, positive=True)
    if layout is None:
        layout = (1, len(panels))
    elif layout[0] * layout[1] < len(panels):
        ctx.sub("layout").fail("%dx%d grid has room for %d panels, spec has %d"
                               % (layout[0], layout[1], layout[0] * layout[1],
                                  len(panels)))
    F["layout"] = layout
    size = get_pair(raw, "size", ctx, positive=True)
    F["size"] = size if size is not None else (5.5 * layout[1], 4.5 * layout[0])
    F["panels"] = [validate_panel(p, ctx.sub("panels").sub(i), timings)
                   for i, p in enumerate(panels)]
    return F


def load_figures(json_path):
    """Parse and validate one latest.json; returns list of validated figures."""
    try:
        with open(json_path, "r", encoding="utf-8") as fh:
            doc = json.load(fh)
    except json.JSONDecodeError as e:
        raise SpecError("%s: invalid JSON: %s" % (json_path, e))
    except OSError as e:
        raise SpecError("%s: cannot read: %s" % (json_path, e.strerror or e))
    ctx = Ctx(json_path)
    if not isinstance(doc, dict):
        ctx.fail("top level must be a JSON object, got %s" % _typename(doc))
    figs = doc.get("figures")
    if figs is None:
        return []
    if not isinstance(figs, list):
        ctx.sub("figures").fail("expected a list, got %s" % _typename(figs))
    timings = doc.get("timings_s", {})
    if not isinstance(timings, dict):
        ctx.sub("timings_s").fail("expected an object, got %s" % _typename(timings))
    return [validate_figure(f, ctx.sub("figures").sub(i), timings)
            for i, f in enumerate(figs)]


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
                    "See the contract at the top of this file.")
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
    seen = {}
    try:
        for p in jobs:
            for k, F in enumerate(load_figures(p)):
                if F["file"] in seen:
                    raise SpecError(
                        "%s: figures[%d].file: %r is also written by %s"
                        % (p, k, F["file"], seen[F["file"]]))
                seen[F["file"]] = "%s figures[%d]" % (p, k)
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
