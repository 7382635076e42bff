#!/usr/bin/env python3
"""Self-check for scripts/plot.py, scripts/figure_spec.py and
scripts/figure_schema.json (and the scripts/plot wrapper).

Writes a temporary results tree, runs plot.py on it and checks: every layer
type renders, PNGs are real and non-trivial, output is byte-identical across
runs, malformed specs fail with a message naming the json file and the key,
missing ids fail, empty results succeed, and the wrapper finds matplotlib.
Then the validator: figure_schema.json is a valid Draft 2020-12 schema; the
malformed cases are told apart into those the schema alone rejects and those
only figure_spec.py's cross-field checks reject; figure_spec.py's command
line accepts the good spec and rejects every malformed one; "nan" / "inf" /
"-inf" strings in data arrays are accepted and rendered; without jsonschema
both scripts fail with a message saying what to install.

Usage: /usr/bin/python3 scripts/plot_selftest.py [--keep DIR]
Prints "N passed, M failed"; exits non-zero on any failure.
"""

import argparse
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
PLOT_PY = os.path.join(HERE, "plot.py")
FIGURE_SPEC = os.path.join(HERE, "figure_spec.py")
SCHEMA = os.path.join(HERE, "figure_schema.json")
WRAPPER = os.path.join(HERE, "plot")

PASSED = []
FAILED = []


def check(name, cond, detail=""):
    if cond:
        PASSED.append(name)
        print("PASS  %s" % name)
    else:
        FAILED.append(name)
        print("FAIL  %s%s" % (name, ("\n      " + detail.replace("\n", "\n      "))
                               if detail else ""))


def run(args, env=None, cmd=None):
    e = dict(os.environ)
    if env:
        e.update(env)
    p = subprocess.run((cmd or [sys.executable, PLOT_PY]) + args,
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       universal_newlines=True, env=e)
    return p.returncode, p.stdout, p.stderr


def write_json(root, rid, doc):
    d = os.path.join(root, rid)
    os.makedirs(d, exist_ok=True)
    p = os.path.join(d, "latest.json")
    with open(p, "w") as fh:
        json.dump(doc, fh, indent=1)
    return p


def png_info(path):
    """(width, height, n_distinct_sampled_rows) of an 8-bit RGB(A) PNG, or None."""
    with open(path, "rb") as fh:
        data = fh.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    pos, w, h = 8, None, None
    idat = b""
    chunks = []
    while pos < len(data):
        n, typ = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        chunks.append(typ.decode("latin-1"))
        if typ == b"IHDR":
            w, h = struct.unpack(">II", body[:8])
        elif typ == b"IDAT":
            idat += body
        pos += 12 + n
    return {"w": w, "h": h, "chunks": chunks, "raw": zlib.decompress(idat),
            "bytes": len(data)}


def non_white_fraction(path):
    """Fraction of pixels that are not (near) white, via matplotlib.image."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mimg
    img = mimg.imread(path)
    rgb = img[..., :3]
    nonwhite = (rgb < 0.95).any(axis=-1)
    return float(nonwhite.mean()), img.shape


# ---------------------------------------------------------------------------
# specs

def good_doc():
    n = 200
    xs = [i / 20.0 for i in range(n)]
    xl = [10 ** (i / 40.0) for i in range(n)]  # 1 .. ~1e5
    ring_x = [math.cos(2 * math.pi * i / 60) for i in range(60)]
    ring_y = [math.sin(2 * math.pi * i / 60) for i in range(60)]
    # a pose-graph-like set of segments coloured by a weight in [0,1]
    seg = {"x0": [], "y0": [], "x1": [], "y1": [], "c": []}
    for i in range(60):
        for j in (1, 7):
            k = (i + j) % 60
            seg["x0"].append(ring_x[i]); seg["y0"].append(ring_y[i])
            seg["x1"].append(ring_x[k]); seg["y1"].append(ring_y[k])
            seg["c"].append((i % 10) / 9.0)
    cloud_x = [math.cos(i * 0.37) * (1 + 0.3 * math.sin(i * 1.3)) for i in range(500)]
    cloud_y = [math.sin(i * 0.37) * (1 + 0.3 * math.cos(i * 0.7)) for i in range(500)]
    cloud_c = [abs(math.sin(i * 0.05)) for i in range(500)]
    return {
        "experiment": "selftest",
        "figures": [
            {
                "file": "selftest_all_layers.png",
                "title": "Self-test: every layer type",
                "layout": [2, 2],
                "_comment": "underscore keys are ignored",
                "panels": [
                    {"title": "line + hline + vline", "xlabel": "t [s]",
                     "ylabel": "value",
                     "layers": [
                         {"type": "line", "x": xs, "y": [math.sin(v) for v in xs],
                          "label": "sin", "color": "C0"},
                         {"type": "line", "x": xs[::10],
                          "y": [math.cos(v) for v in xs[::10]], "label": "cos",
                          "color": "C1", "marker": "o", "linestyle": "--",
                          "linewidth": 1.0, "alpha": 0.8},
                         {"type": "hline", "y": 0.95, "label": "0.95",
                          "color": "k", "linestyle": ":"},
                         {"type": "vline", "x": 5.0, "label": "t = 5",
                          "color": "tab:red", "linestyle": "-."},
                         {"type": "line", "x": [], "y": [], "label": "empty (skipped)"},
                     ]},
                    {"title": "log-log", "xlabel": "n", "ylabel": "error",
                     "xscale": "log", "yscale": "log", "legend": "upper right",
                     "layers": [
                         {"type": "line", "x": xl, "y": [1.0 / v for v in xl],
                          "label": "1/n"},
                         {"type": "line", "x": xl, "y": [v ** -0.5 for v in xl],
                          "label": "1/sqrt(n)"},
                         {"type": "scatter", "x": xl[::8],
                          "y": [2.0 / v for v in xl[::8]], "label": "samples",
                          "color": "C3", "size": 14, "marker": "x"},
                     ]},
                    {"title": "scatter coloured by c", "xlabel": "x [m]",
                     "ylabel": "y [m]", "aspect": "equal", "colorbar": "weight",
                     "layers": [
                         {"type": "scatter", "x": cloud_x, "y": cloud_y,
                          "c": cloud_c, "cmap": "viridis", "vmin": 0, "vmax": 1,
                          "size": 6, "alpha": 0.8, "marker": "."},
                     ]},
                    {"title": "segments", "xlabel": "x [m]", "ylabel": "y [m]",
                     "aspect": "equal", "xlim": [-1.3, 1.3], "ylim": [-1.3, 1.3],
                     "colorbar": "edge weight", "legend": "lower left",
                     "layers": [
                         dict(seg, type="segments", cmap="Greys", vmin=-0.3,
                              vmax=1, linewidth=0.8, label="edges"),
                         {"type": "scatter", "x": ring_x, "y": ring_y,
                          "color": "C0", "size": 10, "label": "poses"},
                         {"type": "segments", "x0": [], "y0": [], "x1": [], "y1": []},
                     ]},
                ],
            },
            {
                "file": "selftest_simple.png",
                "panels": [{"layers": [
                    {"type": "line", "x": [0, 1, 2, 3], "y": [0, 1, 4, 9]},
                    {"type": "segments", "x0": [0, 1], "y0": [0, 1],
                     "x1": [1, 2], "y1": [2, 3], "color": "C2"},
                    {"type": "line", "x": [0, 1, 2], "label": "wall time",
                     "y_timings": ["solve.n0", "solve.n1", "solve.n2"],
                     "marker": "s"}]}],
            },
        ],
        "timings_s": {"solve.n0": 0.5, "solve.n1": 2.0, "solve.n2": 6.5,
                      "other": 1.0},
    }


def bad(mutator):
    doc = good_doc()
    mutator(doc)
    return doc


def L(doc, f, p, l):
    return doc["figures"][f]["panels"][p]["layers"][l]


MALFORMED = [
    # (id, mutator, substrings that must appear in stderr)
    ("bad_len", lambda d: L(d, 0, 0, 1).update(y=L(d, 0, 0, 1)["y"][:-1]),
     ["bad_len/latest.json", "figures[0].panels[0].layers[1].y", "length"]),
    ("bad_type", lambda d: L(d, 0, 1, 0).update(type="bar"),
     ["bad_type/latest.json", "figures[0].panels[1].layers[0].type", "'bar'"]),
    ("bad_value", lambda d: L(d, 0, 2, 0)["c"].__setitem__(3, "oops"),
     ["bad_value/latest.json", "figures[0].panels[2].layers[0].c", "element [3]"]),
    ("bad_null", lambda d: L(d, 1, 0, 0)["y"].__setitem__(1, None),
     ["bad_null/latest.json", "figures[1].panels[0].layers[0].y", "null"]),
    ("bad_file", lambda d: d["figures"][1].update(file="../escape.png"),
     ["bad_file/latest.json", "figures[1].file"]),
    ("bad_file_dir", lambda d: d["figures"][1].update(file="sub/x.png"),
     ["figures[1].file"]),
    ("bad_seg_len", lambda d: L(d, 0, 3, 0)["x1"].pop(),
     ["figures[0].panels[3].layers[0].x1", "length"]),
    ("bad_unknown_key", lambda d: d["figures"][0]["panels"][0].update(xlable="oops"),
     ["figures[0].panels[0].xlable", "unknown key"]),
    ("bad_layout", lambda d: d["figures"][0].update(layout=[1, 2]),
     ["figures[0].layout"]),
    ("bad_scale", lambda d: d["figures"][0]["panels"][1].update(xscale="symlog"),
     ["figures[0].panels[1].xscale"]),
    ("bad_logit_limits", lambda d: d["figures"][0]["panels"][1].update(xscale="logit", xlim=[0.0, 1.0]),
     ["figures[0].panels[1].xlim", "logit"]),
    ("bad_ticklabels", lambda d: d["figures"][0]["panels"][0].update(xticks=[1.0, 2.0], xticklabels=["a"]),
     ["figures[0].panels[0].xticklabels", "length"]),
    ("bad_ticklabels_alone", lambda d: d["figures"][0]["panels"][0].update(xticklabels=["a"]),
     ["figures[0].panels[0]", "xticks"]),
    ("bad_missing_x", lambda d: L(d, 1, 0, 0).pop("x"),
     ["figures[1].panels[0].layers[0].x", "missing"]),
    ("bad_hline", lambda d: L(d, 0, 0, 2).update(y=[0.95]),
     ["figures[0].panels[0].layers[2].y"]),
    ("bad_figures", lambda d: d.update(figures={"file": "x.png"}),
     ["bad_figures/latest.json", "figures", "expected a list"]),
    ("bad_colorbar", lambda d: d["figures"][1]["panels"][0].update(colorbar="z"),
     ["figures[1].panels[0].colorbar"]),
    ("bad_dup_file", lambda d: d["figures"][1].update(file="selftest_all_layers.png"),
     ["figures[1].file", "also written"]),
    ("bad_timing_name", lambda d: L(d, 1, 0, 2)["y_timings"].__setitem__(1, "solve.nX"),
     ["bad_timing_name/latest.json", "figures[1].panels[0].layers[2].y_timings",
      "'solve.nX' is not in"]),
    ("bad_timing_both", lambda d: L(d, 1, 0, 2).update(y=[1, 2, 3]),
     ["figures[1].panels[0].layers[2].y_timings", "not both"]),
    ("bad_timing_len", lambda d: L(d, 1, 0, 2)["y_timings"].pop(),
     ["figures[1].panels[0].layers[2].y_timings", "length 2 != len(x) 3"]),
    ("bad_timing_missing", lambda d: d.pop("timings_s"),
     ["figures[1].panels[0].layers[2].y_timings", "'solve.n0' is not in"]),
]

# Which step of figure_spec.py rejects each MALFORMED case: the schema alone
# ("schema") or only the checks a schema cannot express ("cross").
CAUGHT_BY = {
    "bad_len": "cross", "bad_type": "schema", "bad_value": "schema",
    "bad_null": "schema", "bad_file": "schema", "bad_file_dir": "schema",
    "bad_seg_len": "cross", "bad_unknown_key": "schema", "bad_layout": "cross",
    "bad_scale": "schema", "bad_logit_limits": "schema",
    "bad_missing_x": "schema", "bad_hline": "schema", "bad_figures": "schema",
    "bad_colorbar": "schema", "bad_dup_file": "cross",
    "bad_timing_name": "cross", "bad_timing_both": "schema",
    "bad_timing_len": "cross", "bad_timing_missing": "cross",
    "bad_ticklabels": "cross", "bad_ticklabels_alone": "schema",
}

# Rejected by figure_schema.json on its own.
SCHEMA_ONLY = [
    ("schema_layer_key", lambda d: L(d, 0, 1, 2).update(linestyle="--"),
     ["figures[0].panels[1].layers[2].linestyle", "unknown key", "scatter layer"]),
    ("schema_size", lambda d: d["figures"][1].update(size=[4, -1]),
     ["figures[1].size", "element [1]", "> 0"]),
    ("schema_same_limits", lambda d: d["figures"][0]["panels"][3].update(xlim=[1, 1.0]),
     ["figures[0].panels[3].xlim", "different"]),
    ("schema_log_limits", lambda d: d["figures"][0]["panels"][1].update(xlim=[0, 100]),
     ["figures[0].panels[1].xlim", "element [0]", "log scale"]),
    ("schema_cmap_without_c", lambda d: L(d, 0, 3, 1).update(cmap="viridis"),
     ["figures[0].panels[3].layers[1].cmap", 'given without "c"']),
    ("schema_alpha", lambda d: L(d, 0, 0, 1).update(alpha=1.5),
     ["figures[0].panels[0].layers[1].alpha", "[0, 1]"]),
    ("schema_not_png", lambda d: d["figures"][1].update(file="simple.jpg"),
     ["figures[1].file", ".png", "'simple.jpg'"]),
    ("schema_nan_scalar", lambda d: L(d, 0, 0, 2).update(y="nan"),
     ["figures[0].panels[0].layers[2].y", "finite number", "'nan'"]),
    ("schema_nan_case", lambda d: L(d, 1, 0, 0)["y"].__setitem__(2, "NaN"),
     ["figures[1].panels[0].layers[0].y", "element [2]", "'NaN'"]),
    ("schema_layout_float", lambda d: d["figures"][0].update(layout=[2, 2.5]),
     ["figures[0].layout", "element [1]", "integer"]),
    ("schema_no_panels", lambda d: d["figures"][1].update(panels=[]),
     ["figures[1].panels", "non-empty"]),
    ("schema_linestyle", lambda d: L(d, 0, 0, 1).update(linestyle="dots"),
     ["figures[0].panels[0].layers[1].linestyle", "'dots'"]),
    ("schema_timings_type", lambda d: d.update(timings_s=[0.5, 2.0]),
     ["schema_timings_type/latest.json", "timings_s", "JSON object"]),
    ("schema_missing_y", lambda d: L(d, 1, 0, 0).pop("y"),
     ["figures[1].panels[0].layers[0].y", "missing required key"]),
    ("schema_layer_object", lambda d: d["figures"][1]["panels"][0]["layers"].append([1, 2]),
     ["figures[1].panels[0].layers[3]", "layer must be a JSON object"]),
]

# Accepted by figure_schema.json, rejected by the checks a schema cannot
# express (array lengths, layout room, timings, vmin <= vmax, matplotlib names).
CROSS_ONLY = [
    ("cross_scatter_c_len", lambda d: L(d, 0, 2, 0)["c"].pop(),
     ["figures[0].panels[2].layers[0].c", "length 499 != len(x) 500"]),
    ("cross_vmin_vmax", lambda d: L(d, 0, 2, 0).update(vmin=2),
     ["figures[0].panels[2].layers[0].vmin", "> vmax"]),
    ("cross_color", lambda d: L(d, 0, 0, 0).update(color="notacolour"),
     ["figures[0].panels[0].layers[0].color", "not a matplotlib color"]),
    ("cross_marker", lambda d: L(d, 0, 0, 1).update(marker="qq"),
     ["figures[0].panels[0].layers[1].marker", "not a matplotlib marker"]),
    ("cross_cmap", lambda d: L(d, 0, 2, 0).update(cmap="no_such_cmap"),
     ["figures[0].panels[2].layers[0].cmap", "unknown colormap"]),
    ("cross_layout", lambda d: d["figures"][0].update(layout=[3, 1]),
     ["figures[0].layout", "3x1 grid has room for 3 panels, spec has 4"]),
    ("cross_timing_value", lambda d: d["timings_s"].update({"solve.n1": "slow"}),
     ["figures[1].panels[0].layers[2].y_timings", "timings_s['solve.n1'] is not a finite number"]),
]

# Python's json writes and reads NaN / Infinity, which are not JSON: the
# schema's "number" is taken to be finite, so these are rejected too.
NONFINITE_LITERALS = [
    ("bad_nan_literal", lambda d: L(d, 1, 0, 0)["y"].__setitem__(1, float("nan")),
     ["figures[1].panels[0].layers[0].y", "element [1]", "float nan"]),
    ("bad_inf_literal", lambda d: L(d, 0, 0, 1).update(alpha=float("inf")),
     ["figures[0].panels[0].layers[1].alpha", "float inf"]),
]

ALL_MALFORMED = MALFORMED + SCHEMA_ONLY + CROSS_ONLY + NONFINITE_LITERALS


def nan_doc():
    """The good spec with the strings the C++ writer uses for non-finite
    numbers in some data arrays."""
    d = good_doc()
    L(d, 1, 0, 0)["y"][1] = "nan"
    L(d, 1, 0, 1)["x1"][0] = "inf"
    L(d, 1, 0, 1)["y0"][1] = "-inf"
    L(d, 0, 2, 0)["c"][5] = "nan"
    L(d, 0, 2, 0)["x"][7] = "-inf"
    L(d, 0, 3, 0)["c"][0] = "inf"
    return d


def run_without_jsonschema(script, args):
    """Run a script with `import jsonschema` failing."""
    boot = ("import sys; sys.modules['jsonschema'] = None; "
            "sys.argv = [%r] + %r; "
            "exec(compile(open(%r).read(), %r, 'exec'), "
            "{'__name__': '__main__', '__file__': %r})"
            % (script, args, script, script, script))
    return run([], cmd=[sys.executable, "-c", boot])


def check_validator(res, tmp):
    """figure_schema.json, figure_spec.py (module and command line)."""
    good = os.path.join(res, "good", "latest.json")

    # the schema itself
    try:
        import jsonschema
    except ImportError:
        check("jsonschema is importable (apt-get install python3-jsonschema)", False)
        return
    with open(SCHEMA) as fh:
        schema = json.load(fh)
    try:
        jsonschema.Draft202012Validator.check_schema(schema)
        err = ""
    except jsonschema.exceptions.SchemaError as e:
        err = str(e)
    check("figure_schema.json is a valid Draft 2020-12 schema", not err, err)
    check("figure_schema.json says it is draft 2020-12",
          schema.get("$schema") == "https://json-schema.org/draft/2020-12/schema")

    # which step rejects which case: the plain schema (a stock validator,
    # no figure_spec.py) must reject the schema cases and accept the others
    plain = jsonschema.Draft202012Validator(schema)
    check("plain schema accepts the good spec", plain.is_valid(good_doc()),
          "; ".join(e.message for e in plain.iter_errors(good_doc())))
    check("plain schema accepts the nan/inf spec", plain.is_valid(nan_doc()))
    cases = ([(rid, mut, CAUGHT_BY[rid]) for rid, mut, _ in MALFORMED]
             + [(rid, mut, "schema") for rid, mut, _ in SCHEMA_ONLY]
             + [(rid, mut, "cross") for rid, mut, _ in CROSS_ONLY])
    check("every MALFORMED case says which step rejects it",
          sorted(CAUGHT_BY) == sorted(rid for rid, _, _ in MALFORMED))
    for rid, mut, step in cases:
        valid = plain.is_valid(bad(mut))
        check("%s is rejected by %s" % (rid, "the schema alone" if step == "schema"
                                         else "cross-field checks only"),
              valid == (step == "cross"))

    # module: every malformed case rejected with the json file and key path;
    # normalized figures, "nan" / "inf" / "-inf" as floats
    sys.path.insert(0, HERE)
    try:
        import figure_spec
    except (ImportError, SystemExit) as e:  # report, keep going
        check("figure_spec is importable", False, "%s: %s" % (type(e).__name__, e))
        return
    finally:
        sys.path.remove(HERE)

    def spec_error(path):
        """What `figure_spec.py path` reports, in-process: None if valid."""
        try:
            names = figure_spec.FileNames()
            for k, F in enumerate(figure_spec.load_figures(path)):
                names.add(path, k, F["file"])
        except figure_spec.SpecError as e:
            return str(e)
        return None

    for rid, _, needles in ALL_MALFORMED:
        p = os.path.join(res, rid, "latest.json")
        err = spec_error(p) or ""
        missing = [n for n in needles if n not in err]
        check("figure_spec rejects %s naming the key path" % rid,
              err.startswith(p + ": ") and not missing,
              "missing=%r error=%s" % (missing, err))
    check("figure_spec accepts the good spec", spec_error(good) is None)
    try:
        figs = figure_spec.load_figures(os.path.join(res, "nanstr", "latest.json"))
        seg = figs[1]["panels"][0]["layers"][1]
        sc = figs[0]["panels"][2]["layers"][0]
        ok = (math.isnan(figs[1]["panels"][0]["layers"][0]["y"][1])
              and seg["x1"][0] == float("inf") and seg["y0"][1] == float("-inf")
              and math.isnan(sc["c"][5]) and sc["x"][7] == float("-inf")
              and all(isinstance(v, float) for v in sc["x"]))
        detail = ""
    except Exception as e:  # report, keep going
        ok, detail = False, "%s: %s" % (type(e).__name__, e)
    check('figure_spec.load_figures turns "nan"/"inf"/"-inf" into floats', ok, detail)

    # command line
    rc, so, se = run([good], cmd=[sys.executable, FIGURE_SPEC])
    check("figure_spec.py good spec -> exit 0, 'ok FILE (2 figures)'",
          rc == 0 and so.strip() == "ok %s (2 figures)" % good, so + se)
    nanp = os.path.join(res, "nanstr", "latest.json")
    emptyp = os.path.join(res, "emptyfigs", "latest.json")
    rc, so, se = run([nanp, emptyp], cmd=[sys.executable, FIGURE_SPEC])
    check('figure_spec.py accepts "nan"/"inf"/"-inf" in data arrays',
          rc == 0 and so.splitlines() == ["ok %s (2 figures)" % nanp,
                                          "ok %s (0 figures)" % emptyp], so + se)
    for rid, needles in ((r, n) for r, _, n in ALL_MALFORMED
                         if r in ("bad_type", "bad_len", "bad_dup_file", "bad_nan_literal")):
        p = os.path.join(res, rid, "latest.json")
        rc, so, se = run([p], cmd=[sys.executable, FIGURE_SPEC])
        missing = [n for n in needles if n not in se]
        check("figure_spec.py %s -> exit 1 with the key path" % rid,
              rc == 1 and not missing and "Traceback" not in se and not so,
              "rc=%d missing=%r stderr=%s" % (rc, missing, se.strip()))
    badp = os.path.join(res, "bad_len", "latest.json")
    rc, so, se = run([good, badp, nanp], cmd=[sys.executable, FIGURE_SPEC])
    check("figure_spec.py stops at the first invalid file",
          rc == 1 and so.strip() == "ok %s (2 figures)" % good and badp in se, so + se)
    rc, so, se = run([good, os.path.join(res, "good", "latest.json")],
                     cmd=[sys.executable, FIGURE_SPEC])
    check("figure_spec.py: file names unique across files",
          rc == 1 and "is also written by %s figures[0]" % good in se, se)
    rc, so, se = run([os.path.join(tmp, "nope.json")], cmd=[sys.executable, FIGURE_SPEC])
    check("figure_spec.py missing file -> exit 1", rc == 1 and "cannot read" in se, se)
    rc, so, se = run([], cmd=[sys.executable, FIGURE_SPEC])
    check("figure_spec.py without files -> exit 2", rc == 2 and "usage" in se, se)
    rc, so, se = run(["--bogus", good], cmd=[sys.executable, FIGURE_SPEC])
    check("figure_spec.py bad option -> exit 2", rc == 2, se)

    # rendering with non-finite values
    outn = os.path.join(tmp, "out_nan")
    rc, so, se = run(["--results", res, "--out", outn, "nanstr"])
    check('plot.py renders "nan"/"inf"/"-inf" data', rc == 0 and all(
        os.path.isfile(os.path.join(outn, f))
        for f in ("selftest_all_layers.png", "selftest_simple.png")), so + se)

    # without jsonschema: a clear message and exit 1, from both scripts
    for script, args in ((FIGURE_SPEC, [good]),
                         (PLOT_PY, ["--results", res, "--out",
                                    os.path.join(tmp, "out_nojs"), "good"])):
        rc, so, se = run_without_jsonschema(script, args)
        check("%s without jsonschema -> exit 1, says apt-get install python3-jsonschema"
              % os.path.basename(script),
              rc == 1 and "apt-get install python3-jsonschema" in se
              and "Traceback" not in se, "rc=%d %s" % (rc, se.strip()))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--keep", help="copy rendered figures into this directory")
    a = ap.parse_args()

    tmp = tempfile.mkdtemp(prefix="keel_plot_selftest_")
    try:
        res = os.path.join(tmp, "results")
        write_json(res, "good", good_doc())
        write_json(res, "nofigs", {"experiment": "x", "metrics": {"a": 1}})
        write_json(res, "emptyfigs", {"figures": []})
        write_json(res, "nanstr", nan_doc())
        for rid, mut, _ in ALL_MALFORMED:
            write_json(res, rid, bad(mut))

        # 1. render the good spec
        out1 = os.path.join(tmp, "out1")
        rc, so, se = run(["--results", res, "--out", out1, "good"])
        check("good spec exits 0", rc == 0, se)
        lines = so.strip().splitlines()
        check("one output line per written file", len(lines) == 2 and all(
            l.endswith(".png") and os.path.isfile(l) for l in lines), so + se)
        for f, (w_in, h_in) in (("selftest_all_layers.png", (11.0, 9.0)),
                                ("selftest_simple.png", (5.5, 4.5))):
            p = os.path.join(out1, f)
            ok = os.path.isfile(p)
            check("%s exists" % f, ok)
            if not ok:
                continue
            info = png_info(p)
            check("%s is a PNG" % f, info is not None)
            if info is None:
                continue
            check("%s has default size %gx%g in @150dpi" % (f, w_in, h_in),
                  (info["w"], info["h"]) == (round(w_in * 150), round(h_in * 150)),
                  "got %sx%s" % (info["w"], info["h"]))
            check("%s has no tIME/tEXt chunks (deterministic)" % f,
                  not any(c in ("tIME", "tEXt", "iTXt", "zTXt") for c in info["chunks"]),
                  str(info["chunks"]))
            frac, shape = non_white_fraction(p)
            check("%s is non-trivial (%d bytes, %.1f%% non-white)"
                  % (f, info["bytes"], 100 * frac),
                  info["bytes"] > 10000 and 0.02 < frac < 0.9)

        # 2. determinism: second run, different out dir, identical bytes
        out2 = os.path.join(tmp, "out2")
        rc2, _, se2 = run(["--results", res, "--out", out2, "good"])
        same = rc2 == 0 and all(
            open(os.path.join(out1, f), "rb").read()
            == open(os.path.join(out2, f), "rb").read()
            for f in ("selftest_all_layers.png", "selftest_simple.png"))
        check("two runs give byte-identical PNGs", same, se2)

        # 3. malformed specs: non-zero, message names json + key, nothing written
        #    (the other malformed cases go through figure_spec in step 8)
        for rid, _, needles in MALFORMED:
            outb = os.path.join(tmp, "out_" + rid)
            rc, so, se = run(["--results", res, "--out", outb, rid])
            missing = [n for n in needles if n not in se]
            key = [n for n in needles if n.startswith("figures")] or needles
            check("malformed %s -> exit!=0, names %s" % (rid, key[0]),
                  rc != 0 and not missing and "Traceback" not in se,
                  "rc=%d missing=%r stderr=%s" % (rc, missing, se.strip()))
            check("malformed %s wrote nothing" % rid,
                  not os.path.exists(outb) or not os.listdir(outb))

        # 4. all ids (no ids given) fails because of the malformed ones
        rc, so, se = run(["--results", res, "--out", os.path.join(tmp, "all")])
        check("all ids with a malformed one -> exit!=0", rc != 0 and
              "latest.json" in se, se)

        # 5. missing latest.json for a requested id
        rc, so, se = run(["--results", res, "--out", os.path.join(tmp, "m"),
                          "good", "does_not_exist"])
        check("missing id -> exit!=0 naming latest.json",
              rc != 0 and "does_not_exist/latest.json" in se and "missing" in se, se)

        # 6. results with no figures -> message + exit 0
        rc, so, se = run(["--results", res, "--out", os.path.join(tmp, "n"),
                          "nofigs", "emptyfigs"])
        check("no figures -> exit 0 and says so",
              rc == 0 and "no figures" in so, so + se)
        empty_res = os.path.join(tmp, "empty_results")
        os.makedirs(empty_res)
        rc, so, se = run(["--results", empty_res, "--out", os.path.join(tmp, "n2")])
        check("empty results dir -> exit 0 and says so",
              rc == 0 and "no figures" in so, so + se)
        rc, so, se = run(["--results", os.path.join(tmp, "nope"), "--out",
                          os.path.join(tmp, "n3")])
        check("nonexistent results dir -> exit!=0", rc != 0 and "nope" in se, se)

        # 7. wrapper: finds a matplotlib python, passes args through
        if os.access(WRAPPER, os.X_OK):
            outw = os.path.join(tmp, "outw")
            rc, so, se = run(["--results", res, "--out", outw, "good"],
                             cmd=[WRAPPER])
            check("scripts/plot wrapper renders", rc == 0 and os.path.isfile(
                os.path.join(outw, "selftest_simple.png")), se)
            rc, so, se = run(["--results", res, "--out", outw + "b", "good"],
                             cmd=[WRAPPER], env={"KEEL_PYTHON": "/nonexistent/python"})
            check("wrapper falls back past a bad KEEL_PYTHON", rc == 0, se)
            rc, so, se = run(["--results", res, "--out", outw + "c", "bad_len"],
                             cmd=[WRAPPER])
            check("wrapper propagates failure exit status",
                  rc != 0 and "figures[0].panels[0].layers[1].y" in se, se)
        else:
            check("scripts/plot wrapper is executable", False, WRAPPER)

        # 8. the schema and the validator
        check_validator(res, tmp)

        if a.keep:
            os.makedirs(a.keep, exist_ok=True)
            for f in os.listdir(out1):
                shutil.copy(os.path.join(out1, f), a.keep)
            print("kept rendered figures in %s" % a.keep)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    print("%d passed, %d failed" % (len(PASSED), len(FAILED)))
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main())
