#!/usr/bin/env python3
"""keel figure specs: load and validate the "figures" of results JSON files.

Usage:
    figure_spec.py FILE...

Validates the "figures" key of each results file given (results/<id>/latest.json)
and prints "ok FILE (N figures)" per valid file.  File names must also be
unique across all the files given, as they are across everything plot.py
renders in one run.

Exit status: 0 all valid, 1 at the first invalid or unreadable file (the
message names the file and the offending key path, e.g.
    results/foo/latest.json: figures[0].panels[1].layers[2].y: length 4 != len(x) 5
), 2 on bad command-line usage.

The contract is scripts/figure_schema.json (JSON Schema, draft 2020-12), which
describes every key.  Validation is in two steps:
  1. the schema, with the jsonschema library; its "number" and "integer" are
     finite (Python's json parses the non-standard NaN / Infinity literals);
  2. what a schema cannot say: equal array lengths within a layer, layout
     rows*cols >= number of panels, y_timings names found in the file's
     timings_s, vmin <= vmax, colours / markers / colormaps known to
     matplotlib, and (FileNames) file names unique across files.
Step 2 also normalizes a figure into the plain dicts plot.py draws from:
numbers become floats, "nan" / "inf" / "-inf" in data arrays become float
NaN / infinities, layout and size get their defaults.

Needs Python 3 + jsonschema + matplotlib (Debian: python3-jsonschema,
python3-matplotlib); plot.py imports this module.
"""

import argparse
import json
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SCHEMA_PATH = os.path.join(HERE, "figure_schema.json")

# Names the script in a missing-module message: figure_spec.py, or plot.py
# when it imports this module.
_PROG = (os.path.basename(sys.argv[0])
         if sys.argv and sys.argv[0].endswith(".py") else "figure_spec.py")

try:
    import jsonschema
    import jsonschema.validators
except ImportError:  # pragma: no cover - depends on the interpreter
    sys.stderr.write(
        "%s: error: the Python module jsonschema is not importable by %s\n"
        "  (scripts/figure_spec.py validates figure specs with it)\n"
        "  apt-get install python3-jsonschema\n" % (_PROG, sys.executable))
    sys.exit(1)

try:
    import matplotlib
    from matplotlib import colors as mcolors
    from matplotlib import markers as mmarkers
except ImportError:  # pragma: no cover - depends on the interpreter
    sys.stderr.write(
        "%s: error: matplotlib is not importable by %s\n"
        "  (scripts/figure_spec.py checks colours, markers and colormaps with it)\n"
        "  apt-get install python3-matplotlib\n" % (_PROG, sys.executable))
    sys.exit(1)

# Strings the C++ results writer stores for non-finite numbers in data arrays.
NON_FINITE = {"nan": float("nan"), "inf": float("inf"), "-inf": float("-inf")}


class SpecError(Exception):
    """A malformed spec; message is '<json>: <key path>: <problem>'."""


# ----------------------------------------------------------------------------
# key paths and messages

def _typename(v):
    return "null" if v is None else type(v).__name__


def _got(v, limit=80):
    """'<type> <repr>' of an offending value, the repr cut to `limit` chars."""
    if v is None:
        return "null"
    r = repr(v)
    if len(r) > limit:
        r = r[:limit - 3] + "..."
    return "%s %s" % (_typename(v), r)


def path_str(path):
    """['figures', 0, 'panels', 1, 'x'] -> 'figures[0].panels[1].x'."""
    out = ""
    for p in path:
        if isinstance(p, int):
            out += "[%d]" % p
        else:
            out += ".%s" % p if out else p
    return out


def _fail(src, path, msg):
    raise SpecError("%s: %s: %s" % (src, path_str(path) or "<top>", msg))


# ----------------------------------------------------------------------------
# step 1: the schema

def _is_number(checker, v):
    """JSON number that is finite: no bool, no NaN / Infinity, no int too
    large for a double."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return False
    try:
        return math.isfinite(v)
    except OverflowError:
        return False


def _is_integer(checker, v):
    return _is_number(checker, v) and (isinstance(v, int) or v.is_integer())


_Validator = jsonschema.validators.extend(
    jsonschema.Draft202012Validator,
    type_checker=jsonschema.Draft202012Validator.TYPE_CHECKER.redefine_many(
        {"number": _is_number, "integer": _is_integer}))

_schema = None
_validator = None


def load_schema():
    """The parsed figure_schema.json (checked against the 2020-12 meta-schema)."""
    global _schema, _validator
    if _schema is None:
        try:
            with open(SCHEMA_PATH, "r", encoding="utf-8") as fh:
                schema = json.load(fh)
            jsonschema.Draft202012Validator.check_schema(schema)
        except (OSError, ValueError, jsonschema.exceptions.SchemaError) as e:
            raise SpecError("%s: broken schema: %s" % (SCHEMA_PATH, e))
        _schema = schema
        _validator = _Validator(schema)
    return _schema


# Schema keywords whose subschema applies to one member / element of the
# instance, i.e. that move one step down the instance path.
_DESCENDING = {"properties", "patternProperties", "additionalProperties",
               "items", "prefixItems"}


def _raise_schema_error(src, e):
    """Raise a jsonschema ValidationError as a SpecError that names the key
    path and says what was expected, from the titles in the schema."""
    path = list(e.absolute_path)
    inst, schema, kw, val = e.instance, e.schema, e.validator, e.validator_value
    title = schema.get("title") if isinstance(schema, dict) else None

    if kw == "required":
        key = next((k for k in val if k not in inst), val[0])
        prop = schema.get("properties", {}).get(key, {})
        hint = ""
        if isinstance(prop, dict) and "enum" in prop:
            hint = " (one of %s)" % ", ".join(str(x) for x in prop["enum"])
        _fail(src, path + [key], "missing required key" + hint)

    if kw == "additionalProperties":
        known = schema.get("properties", {})
        patterns = list(schema.get("patternProperties", {}))
        key = next((k for k in inst if k not in known
                    and not any(re.search(p, k) for p in patterns)), "?")
        _fail(src, path + [key], "unknown key %r for %s (allowed: %s)"
              % (key, title or "this object", ", ".join(sorted(known))))

    if kw == "dependentRequired":
        for key, needs in val.items():
            lacking = [n for n in needs if n not in inst]
            if key in inst and lacking:
                _fail(src, path + [key], "given without %s"
                      % ", ".join('"%s"' % n for n in lacking))

    sp = list(e.relative_schema_path)
    if "dependentSchemas" in sp:
        # A rule that applies when a member is present: blame that member,
        # on the object that holds it.  The failing subschema's title states
        # the rule.
        i = len(sp) - 1 - sp[::-1].index("dependentSchemas")
        steps = sum(1 for k in sp[i + 2:] if k in _DESCENDING)
        _fail(src, path[:len(path) - steps] + [sp[i + 1]], title or e.message)

    if kw == "type" and "object" in (val if isinstance(val, list) else [val]):
        _fail(src, path, "%s must be a JSON object, got %s"
              % (title or "value", _typename(inst)))

    if kw == "enum":
        what = "expected %sone of %s" % ("%s, " % title if title else "",
                                         ", ".join(repr(x) for x in val))
    elif title:
        what = "expected %s" % title
    else:
        _fail(src, path, e.message)

    if path and isinstance(path[-1], int) and not isinstance(inst, (dict, list)):
        # an element of a list of scalars: name the list, then the element
        _fail(src, path[:-1], "element [%d]: %s, got %s" % (path[-1], what, _got(inst)))
    _fail(src, path, "%s, got %s" % (what, _got(inst)))


def check_schema(doc, src):
    """Raise SpecError for the first place where doc breaks figure_schema.json."""
    load_schema()
    for e in _validator.iter_errors(doc):
        _raise_schema_error(src, e)


# ----------------------------------------------------------------------------
# step 2: what the schema cannot say, and normalization (input is schema-valid)

def _num(obj, key):
    return float(obj[key]) if key in obj else None


def _data(obj, key):
    """A data array as floats ("nan" / "inf" / "-inf" as non-finite floats)."""
    if key not in obj:
        return None
    return [NON_FINITE[v] if isinstance(v, str) else float(v) for v in obj[key]]


def _pair(obj, key, conv=float):
    return (conv(obj[key][0]), conv(obj[key][1])) if key in obj else None


def _color(obj, key, src, path):
    v = obj.get(key)
    if v is not None and not mcolors.is_color_like(v):
        _fail(src, path + [key], "not a matplotlib color: %r" % (v,))
    return v


def _marker(obj, key, src, path):
    v = obj.get(key)
    if v is not None:
        try:
            mmarkers.MarkerStyle(v)
        except (ValueError, TypeError):
            _fail(src, path + [key], "not a matplotlib marker: %r" % (v,))
    return v


def _cmap(obj, key, src, path):
    v = obj.get(key)
    if v is not None and v not in matplotlib.colormaps:
        _fail(src, path + [key], "unknown colormap %r" % (v,))
    return v


def _same_len(L, keys, ref, src, path):
    n = len(L[ref])
    for k in keys:
        if L.get(k) is not None and len(L[k]) != n:
            _fail(src, path + [k], "length %d != len(%s) %d" % (len(L[k]), ref, n))


def _timings_y(raw, timings, src, path):
    """The "y_timings" names of a layer resolved against the file's timings_s."""
    out = []
    for i, name in enumerate(raw["y_timings"]):
        if name not in timings:
            _fail(src, path + ["y_timings"],
                  "element [%d]: %r is not in \"timings_s\"" % (i, name))
        v = timings[name]
        if not _is_number(None, v):
            _fail(src, path + ["y_timings"],
                  "element [%d]: timings_s[%r] is not a finite number: %r" % (i, name, v))
        out.append(float(v))
    return out


def _layer(raw, timings, src, path):
    t = raw["type"]
    L = {"type": t,
         "label": raw.get("label"),
         "color": _color(raw, "color", src, path),
         "alpha": _num(raw, "alpha")}
    if t in ("line", "hline", "vline", "segments"):
        L["linewidth"] = _num(raw, "linewidth")
    if t in ("line", "hline", "vline"):
        L["linestyle"] = raw.get("linestyle")
    if t in ("line", "scatter"):
        L["marker"] = _marker(raw, "marker", src, path)
        L["x"] = _data(raw, "x")
        if "y_timings" in raw:
            L["y"] = _timings_y(raw, timings, src, path)
            if len(L["y"]) != len(L["x"]):
                _fail(src, path + ["y_timings"], "length %d != len(x) %d"
                      % (len(L["y"]), len(L["x"])))
        else:
            L["y"] = _data(raw, "y")
            _same_len(L, ["y"], "x", src, path)
        L["empty"] = len(L["x"]) == 0
    if t in ("scatter", "segments"):
        L["c"] = _data(raw, "c")
        L["cmap"] = _cmap(raw, "cmap", src, path)
        L["vmin"] = _num(raw, "vmin")
        L["vmax"] = _num(raw, "vmax")
        if L["vmin"] is not None and L["vmax"] is not None and L["vmin"] > L["vmax"]:
            _fail(src, path + ["vmin"], "vmin %r > vmax %r" % (L["vmin"], L["vmax"]))
    if t == "scatter":
        L["size"] = _num(raw, "size")
        _same_len(L, ["c"], "x", src, path)
    if t == "segments":
        for k in ("x0", "y0", "x1", "y1"):
            L[k] = _data(raw, k)
        _same_len(L, ["y0", "x1", "y1", "c"], "x0", src, path)
        L["empty"] = len(L["x0"]) == 0
    if t == "hline":
        L["y"] = _num(raw, "y")
        L["empty"] = False
    if t == "vline":
        L["x"] = _num(raw, "x")
        L["empty"] = False
    return L


def _panel(raw, timings, src, path):
    P = {k: raw.get(k) for k in ("title", "xlabel", "ylabel", "xscale", "yscale",
                                 "aspect", "legend", "colorbar")}
    P["xlim"] = _pair(raw, "xlim")
    P["ylim"] = _pair(raw, "ylim")
    P["xticks"] = _data(raw, "xticks")
    P["xticklabels"] = raw.get("xticklabels")
    if P["xticklabels"] is not None and len(P["xticklabels"]) != len(P["xticks"]):
        _fail(src, path + ["xticklabels"], "length %d != len(xticks) %d"
              % (len(P["xticklabels"]), len(P["xticks"])))
    P["layers"] = [_layer(l, timings, src, path + ["layers", i])
                   for i, l in enumerate(raw["layers"])]
    return P


def _figure(raw, timings, src, path):
    panels = raw["panels"]
    F = {"file": raw["file"], "title": raw.get("title")}
    layout = _pair(raw, "layout", int)
    if layout is None:
        layout = (1, len(panels))
    elif layout[0] * layout[1] < len(panels):
        _fail(src, path + ["layout"], "%dx%d grid has room for %d panels, spec has %d"
              % (layout[0], layout[1], layout[0] * layout[1], len(panels)))
    F["layout"] = layout
    size = _pair(raw, "size")
    F["size"] = size if size is not None else (5.5 * layout[1], 4.5 * layout[0])
    F["panels"] = [_panel(p, timings, src, path + ["panels", i])
                   for i, p in enumerate(panels)]
    return F


# ----------------------------------------------------------------------------
# entry points

def validate(doc, src):
    """Validate a parsed results document; returns its figures normalized for
    plot.py (a list, [] when there are none).  src names the document in
    error messages."""
    check_schema(doc, src)
    figs = doc.get("figures")
    if figs is None:
        return []
    timings = doc.get("timings_s", {})
    return [_figure(f, timings, src, ["figures", i]) for i, f in enumerate(figs)]


def load_figures(json_path):
    """Parse and validate one results file; returns its normalized figures."""
    try:
        with open(json_path, "r", encoding="utf-8") as fh:
            doc = json.load(fh)
    except json.JSONDecodeError as e:
        raise SpecError("%s: invalid JSON: %s" % (json_path, e))
    except UnicodeDecodeError as e:
        raise SpecError("%s: not UTF-8 text: %s" % (json_path, e))
    except OSError as e:
        raise SpecError("%s: cannot read: %s" % (json_path, e.strerror or e))
    return validate(doc, json_path)


class FileNames:
    """Output file names seen so far: a name may be written once per run."""

    def __init__(self):
        self.seen = {}

    def add(self, src, k, name):
        """Record figures[k] of src writing `name`; SpecError if already taken."""
        if name in self.seen:
            raise SpecError("%s: figures[%d].file: %r is also written by %s"
                            % (src, k, name, self.seen[name]))
        self.seen[name] = "%s figures[%d]" % (src, k)


# ----------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="figure_spec.py",
        description="Validate the \"figures\" of results JSON files against "
                    "scripts/figure_schema.json and the checks a schema cannot "
                    "express.  Prints 'ok FILE (N figures)' per valid file.")
    ap.add_argument("files", nargs="+", metavar="FILE",
                    help="results file (e.g. results/<id>/latest.json)")
    args = ap.parse_args(argv)

    names = FileNames()
    try:
        load_schema()
        for p in args.files:
            figs = load_figures(p)
            for k, F in enumerate(figs):
                names.add(p, k, F["file"])
            print("ok %s (%d figure%s)" % (p, len(figs), "" if len(figs) == 1 else "s"))
    except SpecError as e:
        sys.stderr.write("figure_spec.py: error: %s\n" % e)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
