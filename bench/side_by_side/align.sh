#!/usr/bin/env bash
# Side-by-side timing of keel.align's Proposed method (thesis ch. 3) at several keel revisions, on the worlds of
# ch3_table3_1_alignment's generator, one thread, with the answers compared between revisions.
#
# Usage: bench/side_by_side/align.sh [--worlds=N] [--batch=B] SCRATCH REV...
#   SCRATCH   work directory: builds are cached here per revision, results go to SCRATCH/results/
#   REV...    keel revisions: commit ids of this repository, or `worktree` for this checkout's files as they are
#             when the script runs (rsync'ed to SCRATCH/keel-worktree and rebuilt incrementally every time)
#   --worlds=N  worlds 0 … N − 1 (default 200, the Table 3.1 experiment's count); --batch=B worlds per driver
#               run (default 10): the revisions take turns batch by batch, so drift in the machine's load hits
#               them alike.
#
# What it does:
#   1. for each commit id: `git archive` into SCRATCH/keel-<sha>, configures it with its own "release" preset (or a
#      plain Release configure),
#      appends a keel_align_worlds target (this checkout's align_worlds.cpp, linked to keel_align_impl and keel_sim_impl)
#      and builds only that target; kept and reused on later runs;
#   2. runs the drivers batch by batch, interleaved, one thread (OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1);
#   3. writes SCRATCH/results/align-<stamp>.tsv (revision and the driver's columns) and align-<stamp>.md: per
#      revision the median, mean and quartiles of the time per world, the ratio to the first revision, and the
#      largest difference of the answer (cost and transform, relative to 1 + |value|) from the first revision's.
#
# Needs: git, rsync (else tar), cmake >= 3.28, ninja, clang++-19 and keel's dependencies, python3. Does not modify
# this checkout.
set -euo pipefail

worlds=200
batch=10
positional=()
for a in "$@"; do
  case "$a" in
    --worlds=*) worlds=${a#--worlds=} ;;
    --batch=*) batch=${a#--batch=} ;;
    --*) echo "unknown option $a" >&2; exit 2 ;;
    *) positional+=("$a") ;;
  esac
done
if [ "${#positional[@]}" -lt 2 ]; then
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
scratch=$(mkdir -p "${positional[0]}" && cd "${positional[0]}" && pwd)
revs=("${positional[@]:1}")

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(git -C "$here" rev-parse --show-toplevel)
mkdir -p "$scratch/logs" "$scratch/results"
stamp=$(date +%Y%m%d-%H%M%S)

sbs_name=align.sh
# shellcheck source=keel_revisions.sh
. "$here/keel_revisions.sh"

declare -A bin
for rev in "${revs[@]}"; do
  keel_revision "$rev" keel_align_worlds "$here/align_worlds.cpp" keel_align_impl keel_sim_impl
  bin[$rev]=$keel_binary
done

tsv=$scratch/results/align-$stamp.tsv
md=$scratch/results/align-$stamp.md
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
printf 'revision\tworld\ttime_s\trounds\tsector\tcost\ta11\ta12\ta21\ta22\ttx\tty\n' >"$tsv"
log "running $worlds worlds in batches of $batch x (${revs[*]})"
t_runs=$SECONDS
for ((first = 0; first < worlds; first += batch)); do
  count=$((worlds - first < batch ? worlds - first : batch))
  for rev in "${revs[@]}"; do
    "${bin[$rev]}" "$first" "$count" | sed "s/^/$rev\t/" >>"$tsv"
  done
done
log "runs: $((SECONDS - t_runs)) s"

{
  printf '# keel.align Proposed side by side (%s)\n\n' "$stamp"
  printf -- '- machine: %s, %s cores; one thread\n' "$(uname -srm)" "$(nproc)"
  for rev in "${revs[@]}"; do
    if [ "$rev" = worktree ]; then
      printf -- '- worktree: %s (HEAD %s, uncommitted paths: %s)\n' "$repo" "$(git -C "$repo" rev-parse --short=12 HEAD)" \
        "$(git -C "$repo" status --porcelain | wc -l | tr -d ' ')"
    else
      printf -- '- %s: %s\n' "$rev" "$(git -C "$repo" log -1 --format='%H %s' "$rev")"
    fi
  done
  printf -- '- worlds 0 … %s of the default generator (seed 20181022), batches of %s; TSV: %s\n\n' \
    "$((worlds - 1))" "$batch" "$tsv"
} >"$md"
python3 - "$tsv" "$md" "${revs[@]}" <<'PY'
import csv, statistics, sys

tsv, md, revs = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = list(csv.DictReader(open(tsv), delimiter="\t"))
if not rows:
    print("no runs")
    sys.exit(0)
by = {(r["revision"], int(r["world"])): r for r in rows}
worlds = sorted({int(r["world"]) for r in rows})
ref = revs[0]
fields = ["cost", "a11", "a12", "a21", "a22", "tx", "ty"]
lines = ["| revision | worlds | median s/world | mean | quartiles | median / " + ref +
         " | largest answer difference from " + ref + " | sector or round count differs |",
         "|---|---|---|---|---|---|---|---|"]
base_median = None
for rev in revs:
    t = [float(by[(rev, w)]["time_s"]) for w in worlds if (rev, w) in by]
    q = statistics.quantiles(t, n=4) if len(t) > 1 else [t[0]] * 3
    med = statistics.median(t)
    if base_median is None:
        base_median = med
    worst, differ = 0.0, 0
    for w in worlds:
        a, b = by.get((ref, w)), by.get((rev, w))
        if a is None or b is None:
            continue
        if a["sector"] != b["sector"] or a["rounds"] != b["rounds"]:
            differ += 1
        for f in fields:
            x, y = float(a[f]), float(b[f])
            worst = max(worst, abs(x - y) / (1 + abs(x)))
    lines.append(f"| {rev} | {len(t)} | {med:.4f} | {statistics.fmean(t):.4f} | {q[0]:.4f} … {q[2]:.4f} | "
                 f"{med / base_median:.3f} | {worst:.2g} | {differ} |")
open(md, "a").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
log "summary: $md"
