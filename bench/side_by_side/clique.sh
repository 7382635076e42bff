#!/usr/bin/env bash
# Side-by-side timing of maximum-clique / densest-subgraph solvers: keel at several revisions (keel_clique.cpp:
# the exact search, its colouring-only / single-bound variants where a revision has the switches, and the densest
# selector) against CLIPPER's dense-cluster solver (clipper_clique.cpp), on a family of DIMACS graphs
# (bench_clique --write-family).
#
# Usage: bench/side_by_side/clique.sh [--repeat=N] [--methods=LIST] SCRATCH CLIPPER_SRC FAMILY REV...
#   SCRATCH      work directory: builds are cached here per revision, results go to SCRATCH/results/
#   CLIPPER_SRC  a checkout (or `git archive`) of https://github.com/mit-acl/clipper
#   FAMILY       directory of *.clq graphs (DIMACS "p edge", 1-based edges)
#   REV...       keel revisions: commit ids of this repository, or `worktree` for this checkout's files as they are
#                when the script runs (rsync'ed to SCRATCH/keel-worktree and rebuilt incrementally every time)
#   --repeat=N, --methods=LIST are passed to every driver (defaults: 3; all methods).
#   CLIPPER_COMMIT (environment) names CLIPPER's commit in the summary when CLIPPER_SRC is not a git checkout.
#
# What it does:
#   1. builds CLIPPER's core library (g++-12, OpenMP; no Python bindings, PMC, SCS or tests; FetchContent
#      disconnected) in SCRATCH/clipper-build and the driver SCRATCH/clipper_clique, if missing or out of date;
#   2. for each commit id: `git archive` into SCRATCH/keel-<sha>, configures with its own "release" preset
#      (falling back to a plain Release/Ninja/clang++-19 configure), appends a keel_clique target (this checkout's
#      keel_clique.cpp, linked to keel_pcm_impl) to that copy's top-level CMakeLists.txt and builds only that target;
#      kept and reused on later runs;
#   3. runs, for every graph in turn, every driver on that graph (interleaved, so that drift in the machine's
#      load hits all solvers alike), one thread (OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1);
#   4. writes SCRATCH/results/clique-<stamp>.tsv (columns: solver graph method median_ms min_ms size nodes valid)
#      and SCRATCH/results/clique-<stamp>.md (per-graph table, ratios, worst and geometric-mean rows, flags) and
#      prints the headline.
#
# Needs: git, rsync (else tar), cmake >= 3.28, ninja, clang++-19 and keel's dependencies (for keel), g++-12 with OpenMP
# and Eigen 3 (for CLIPPER), python3. Does not modify this checkout.
set -euo pipefail

driver_args=()
positional=()
for a in "$@"; do
  case "$a" in
    --*) driver_args+=("$a") ;;
    *) positional+=("$a") ;;
  esac
done
if [ "${#positional[@]}" -lt 4 ]; then
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
scratch=$(mkdir -p "${positional[0]}" && cd "${positional[0]}" && pwd)
clipper_src=$(cd "${positional[1]}" && pwd)
family=$(cd "${positional[2]}" && pwd)
revs=("${positional[@]:3}")

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(git -C "$here" rev-parse --show-toplevel)
mkdir -p "$scratch/logs" "$scratch/results"
stamp=$(date +%Y%m%d-%H%M%S)

sbs_name=clique.sh
# shellcheck source=keel_revisions.sh
. "$here/keel_revisions.sh"

# ---- CLIPPER -------------------------------------------------------------------------------------------------
clipper_build=$scratch/clipper-build
clipper_bin=$scratch/clipper_clique
if [ ! -e "$clipper_build/libclipper.so" ]; then
  timed "CLIPPER configure" "$scratch/logs/clipper.log" \
    cmake -S "$clipper_src" -B "$clipper_build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=g++-12 \
      -DCLIPPER_BUILD_BINDINGS_PYTHON=OFF -DCLIPPER_BUILD_BINDINGS_MATLAB=OFF -DCLIPPER_ENABLE_MAXCLIQUE=OFF \
      -DCLIPPER_ENABLE_SCS_SDR=OFF -DCLIPPER_BUILD_TESTS=OFF -DCLIPPER_BUILD_BENCHMARKS=OFF \
      -DFETCHCONTENT_FULLY_DISCONNECTED=ON
  timed "CLIPPER library build" "$scratch/logs/clipper.log" cmake --build "$clipper_build" --target clipper
fi
if [ ! -x "$clipper_bin" ] || [ "$here/clipper_clique.cpp" -nt "$clipper_bin" ] || [ "$here/dimacs.hpp" -nt "$clipper_bin" ] \
   || [ "$clipper_build/libclipper.so" -nt "$clipper_bin" ]; then
  # CLIPPER's library is compiled with -march=native -mavx -mfma (its public flags); the driver matches them.
  timed "CLIPPER driver build" "$scratch/logs/clipper.log" \
    g++-12 -std=c++17 -O2 -fopenmp -march=native -mavx -mfma -I"$clipper_src/include" -isystem /usr/include/eigen3 \
      "$here/clipper_clique.cpp" -o "$clipper_bin" -L"$clipper_build" -lclipper -Wl,-rpath,"$clipper_build"
fi
if [ -n "${CLIPPER_COMMIT:-}" ]; then
  clipper_commit=$CLIPPER_COMMIT
elif [ -e "$clipper_src/.git" ]; then
  clipper_commit=$(git -C "$clipper_src" rev-parse HEAD)
else
  clipper_commit="unknown (not a git checkout; set CLIPPER_COMMIT)"
fi

# ---- keel revisions ------------------------------------------------------------------------------------------
declare -A bin
for rev in "${revs[@]}"; do
  keel_revision "$rev" keel_clique "$here/keel_clique.cpp" keel_pcm_impl
  bin[$rev]=$keel_binary
done

# ---- runs ----------------------------------------------------------------------------------------------------
tsv=$scratch/results/clique-$stamp.tsv
md=$scratch/results/clique-$stamp.md
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
mapfile -t graphs < <(find "$family" -maxdepth 1 -name '*.clq' | sort)
[ "${#graphs[@]}" -gt 0 ] || { log "no *.clq in $family"; exit 1; }
log "running ${#graphs[@]} graphs x (${revs[*]} clipper), driver options: ${driver_args[*]:-(defaults)}"
failures=$scratch/results/clique-$stamp.failures
: >"$failures"
run_one() {  # run_one SOLVER GRAPH CMD...: append CMD's lines to the TSV under SOLVER; a failure is logged, not fatal
  local solver=$1 graph=$2 out rc=0
  shift 2
  out=$("$@" "$graph") || rc=$?
  if [ "$rc" -eq 0 ]; then
    [ -z "$out" ] || printf '%s\n' "$out" | sed "s/^/$solver\t/" >>"$tsv"
  else
    log "$solver FAILED on $(basename "$graph") (exit $rc)"
    printf '%s\t%s\n' "$solver" "$(basename "$graph" .clq)" >>"$failures"
  fi
}
printf 'solver\tgraph\tmethod\tmedian_ms\tmin_ms\tsize\tnodes\tvalid\n' >"$tsv"
t_runs=$SECONDS
for g in "${graphs[@]}"; do
  t0=$SECONDS
  for rev in "${revs[@]}"; do
    run_one "$rev" "$g" "${bin[$rev]}" "${driver_args[@]}"
  done
  run_one clipper "$g" "$clipper_bin" "${driver_args[@]}"
  [ $((SECONDS - t0)) -lt 20 ] || log "$(basename "$g"): $((SECONDS - t0)) s"
done
log "runs: $((SECONDS - t_runs)) s"

# ---- summary -------------------------------------------------------------------------------------------------
{
  printf '# Maximum clique / densest subgraph side by side (%s)\n\n' "$stamp"
  printf -- '- machine: %s, %s cores; one thread (OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1)\n' \
    "$(uname -srm)" "$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)"
  printf -- '- driver options: %s\n' "${driver_args[*]:-(defaults)}"
  for rev in "${revs[@]}"; do
    if [ "$rev" = worktree ]; then
      printf -- '- worktree: %s files as of %s (HEAD %s, with uncommitted changes: %s)\n' "$repo" "$stamp" \
        "$(git -C "$repo" rev-parse --short=12 HEAD)" \
        "$(git -C "$repo" status --porcelain | wc -l | tr -d ' ') paths"
    else
      printf -- '- %s: %s\n' "$rev" "$(git -C "$repo" log -1 --format='%H %s' "$rev")"
    fi
  done
  printf -- '- clipper: mit-acl/clipper %s, CLIPPER::solve() with default Params on sparse M = C = A (+ I implicit)\n' \
    "$clipper_commit"
  printf -- '- family: %s (%s graphs); TSV: %s\n\n' "$family" "${#graphs[@]}" "$tsv"
} >"$md"
python3 - "$tsv" "$md" "$failures" "${revs[@]}" <<'PY'
import csv, math, sys
from collections import defaultdict

tsv, md, failures, revs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
rows = list(csv.DictReader(open(tsv), delimiter="\t"))
r = {}                       # (solver, graph, method) -> row
graphs = []
for x in rows:
    r[(x["solver"], x["graph"], x["method"])] = x
    if x["graph"] not in graphs:
        graphs.append(x["graph"])
new = "worktree" if "worktree" in revs else revs[-1]
others = [v for v in revs if v != new]
exact_like = ["exact", "colouring", "recolour", "maxsat"]
variants = {v: [m for m in exact_like if any((v, g, m) in r for g in graphs)] for v in revs}

def ms(s, g, m):
    x = r.get((s, g, m))
    return float(x["median_ms"]) if x else None

def fmt(t):
    return "" if t is None else (f"{t:.3g}" if t < 100 else f"{t:.0f}")

cols = []                    # (header, function of graph -> cell value, is_ratio)
for v in revs:
    for m in variants[v]:
        cols.append((f"{v} {m} ms", lambda g, v=v, m=m: ms(v, g, m), False))
for v in revs:
    cols.append((f"{v} densest ms", lambda g, v=v: ms(v, g, "densest"), False))
cols.append(("clipper ms", lambda g: ms("clipper", g, "clipper"), False))

def ratio(a, b):
    return None if a is None or b is None or b <= 0 else a / b

ratio_cols = []              # (header, numerator time, denominator time), times as functions of the graph
if "colouring" in variants[new]:
    ratio_cols.append((f"{new} exact/colouring", lambda g: ms(new, g, "exact"), lambda g: ms(new, g, "colouring")))
for v in others:
    ratio_cols.append((f"{new} exact/{v} exact", lambda g: ms(new, g, "exact"), lambda g, v=v: ms(v, g, "exact")))
ratio_cols.append((f"{new} densest/clipper", lambda g: ms(new, g, "densest"), lambda g: ms("clipper", g, "clipper")))
# The selector's options (DensestOptions::line_search = clipper, penalty_step = mean, both) where they ran.
densest_variants = [m for m in ("densest_steps", "densest_mean", "densest_clipper")
                    if any((new, g, m) in r for g in graphs)]
for m in densest_variants:
    ratio_cols.append((f"{new} {m}/clipper", lambda g, m=m: ms(new, g, m), lambda g: ms("clipper", g, "clipper")))

flags = [f"FAILED: {line.strip()}" for line in open(failures) if line.strip()]
sizes = {}
for g in graphs:
    ex = {(s, m): int(x["size"]) for (s, gg, m), x in r.items() if gg == g and m in exact_like}
    if len(set(ex.values())) > 1:
        flags.append(f"size mismatch between exact runs on {g}: " +
                     ", ".join(f"{s} {m} {k}" for (s, m), k in sorted(ex.items())))
    for (s, gg, m), x in r.items():
        if gg == g and x["valid"] != "1":
            flags.append(f"valid = 0: {s} {m} on {g} (size {x['size']})")
    omega = max(ex.values()) if ex else None
    dens = r.get((new, g, "densest"))
    clip = r.get(("clipper", g, "clipper"))
    sizes[g] = (omega, int(dens["size"]) if dens else None, int(clip["size"]) if clip else None)

head = (["graph"] + [c[0] for c in cols] + ["ω (exact)", f"{new} densest size", "clipper size"]
        + [c[0] for c in ratio_cols])
out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
ratios = defaultdict(list)
for g in graphs:
    cells = [g] + [fmt(f(g)) for _, f, _ in cols]
    cells += ["" if s is None else str(s) for s in sizes[g]]
    for name, fa, fb in ratio_cols:
        q = ratio(fa(g), fb(g))
        if q is not None:
            ratios[name].append((q, g))
        cells.append("" if q is None else f"{q:.2f}")
    out.append("| " + " | ".join(cells) + " |")
blank = [""] * (len(cols) + 3)
def summary_row(label, fn):
    return "| " + " | ".join([f"**{label}**"] + blank + [fn(ratios[n]) for n, _, _ in ratio_cols]) + " |"
worst = lambda v: f"{max(v)[0]:.2f} ({max(v)[1]})" if v else ""
geo = lambda v: f"{math.exp(sum(math.log(q) for q, _ in v) / len(v)):.2f}" if v else ""
best = lambda v: f"{min(v)[0]:.2f} ({min(v)[1]})" if v else ""
# The worst ratio again over the graphs where both times are at least 1 ms (below that, a few microseconds of fixed
# cost or timer noise decide the ratio).
floor_ms = 1.0
ratios_1ms = {n: [(q, g) for q, g in ratios[n] if min(fa(g), fb(g)) >= floor_ms] for n, fa, fb in ratio_cols}
def worst_1ms(name):
    v = ratios_1ms[name]
    return f"{max(v)[0]:.2f} ({max(v)[1]}; {len(v)} graphs)" if v else ""
out += [summary_row("worst (max)", worst), summary_row("best (min)", best), summary_row("geometric mean", geo),
        "| " + " | ".join(["**worst, both ≥ 1 ms**"] + blank + [worst_1ms(n) for n, _, _ in ratio_cols]) + " |"]

# Densest / CLIPPER set sizes against ω, in one line each (ω only where an exact search ran).
def size_of(s, g, m):
    x = r.get((s, g, m))
    return int(x["size"]) if x else None
for who, idx in ((f"{new} densest", 1), ("clipper", 2)):
    ran = [g for g in graphs if sizes[g][idx] is not None]
    if not ran:
        flags.append(f"note: {who} did not run (--methods)")
        continue
    if all(sizes[g][0] is None for g in ran):
        flags.append(f"note: ω unknown (no exact search ran), so {who}'s sizes are not compared with it")
        continue
    ran = [g for g in ran if sizes[g][0] is not None]
    miss = [g for g in ran if sizes[g][idx] != sizes[g][0]]
    flags.append(f"note: {who} selected a maximum clique (size ω) on {len(ran) - len(miss)} of {len(ran)} "
                 "graphs" + ("; not on " + ", ".join(f"{g} ({sizes[g][idx]} of {sizes[g][0]})" for g in miss)
                            if miss else ""))

# Selection sizes of the new build's selector (and its options) against CLIPPER's and the other revisions'.
for m in ["densest"] + densest_variants:
    for other, om in [("clipper", "clipper")] + [(v, "densest") for v in others]:
        pairs = [(size_of(new, g, m), size_of(other, g, om)) for g in graphs]
        pairs = [(a, b) for a, b in pairs if a is not None and b is not None]
        if pairs:
            flags.append(f"note: {new} {m} size against {other} {om}: larger on {sum(a > b for a, b in pairs)}, "
                         f"equal on {sum(a == b for a, b in pairs)}, smaller on {sum(a < b for a, b in pairs)} "
                         f"of {len(pairs)} graphs")

headline = [f"- {n}: worst {worst(ratios[n])}, geometric mean {geo(ratios[n])} over {len(ratios[n])} graphs; "
            f"worst where both take >= 1 ms: {worst_1ms(n) or 'none'}; within 1.5x on "
            f"{sum(q <= 1.5 for q, _ in ratios[n])}" for n, _, _ in ratio_cols if ratios[n]]
with open(md, "a") as f:
    f.write("## Headline\n\n" + "\n".join(headline) + "\n\n")
    f.write("Times are medians in ms; ratios < 1 mean the first named is faster.\n\n")
    f.write("\n".join(out) + "\n\n## Flags\n\n")
    f.write("\n".join(f"- {x}" for x in flags) + "\n")
print("\n".join(headline))
print("\n".join(flags))
PY
log "TSV: $tsv"
log "Markdown: $md"
