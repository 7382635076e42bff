#!/usr/bin/env bash
# tests/reproduce/local_times.sh — scripts/reproduce's local path reports time: each experiment's time after it
# ran, a table of them longest first (wall time, share, CPU time, cores kept busy) with the total at the end, and a time left that scales the baselines'
# expectations by the pace of the experiments already run. Runs on a scratch copy of the scripts, two experiments'
# configs and baselines, with the stand-in drivers and `keel` of tests/slurm/make-fakes (each fake run sleeps
# FAKE_SLEEP seconds; the fake `keel eta` expects 1 s per experiment), so neither the engine nor this checkout's
# results/ and paper/ are touched.
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
ids=(ch5_fig5_4_composition ch5_fig5_6_relative_pose)
mkdir -p "$scratch/tests/slurm" "$scratch/experiments" "$scratch/results"
cp -r "$src/scripts" "$scratch/"
cp "$src/tests/slurm/make-fakes" "$scratch/tests/slurm/"
for id in "${ids[@]}"; do
  cp -r "$src/experiments/$id" "$scratch/experiments/"
  mkdir -p "$scratch/results/$id"
  cp "$src/results/$id/baseline.quick.json" "$scratch/results/$id/"
done
cd "$scratch"
bash tests/slurm/make-fakes fake 2>/dev/null
# The fake results are the committed baselines, whose figure panels blessing strips: the figures are not what this
# test is about, so scripts/plot is a stand-in that succeeds.
printf '#!/usr/bin/env bash\nexit 0\n' >scripts/plot
out=$(FAKE_SLEEP=2 KEEL_PRESET=fake KEEL_NO_BUILD=1 KEEL_PROGRESS=0 scripts/reproduce --profile quick --threads 1 \
  "${ids[@]}" 2>&1) || { echo "$out"; echo "FAIL: scripts/reproduce exited non-zero"; exit 1; }
fail=0
expect() {  # expect REGEX WHAT: a line of the output matches
  if ! grep -Eq -- "$1" <<<"$out"; then echo "FAIL: no line for $2 (regex: $1)"; fail=1; fi
}
# Each experiment's time after it ran (2 s each, the fake baseline said 1 s).
expect "^\[1/2\] ch5_fig5_4_composition: took [2-9]s \(expected 1s\)$" "the first experiment's time"
expect "^\[2/2\] ch5_fig5_6_relative_pose: took [2-9]s \(expected 1s\)$" "the second experiment's time"
# Time left before the second: its 1 s of baseline scaled by the pace so far (2 s taken for 1 s expected).
expect "^\[1/2\] ch5_fig5_4_composition \(quick\): expected 1s \(from its baseline\), about 2s left in total$" \
  "the time left before any experiment ran (baselines as recorded)"
expect "^\[2/2\] ch5_fig5_6_relative_pose \(quick\): expected 1s \(from its baseline\), about [2-9]s left in total$" \
  "the time left scaled by this run's pace"
# The table at the end: both experiments, with wall seconds, share, CPU seconds and cores kept busy, and the total.
expect "^reproduce: time per experiment \(quick, threads 1\), longest first:$" "the table's heading"
row=" +[0-9]+\.[0-9] s +[0-9]+\.[0-9] % +[0-9]+\.[0-9] s +[0-9]+\.[0-9]{2}  "
expect "^${row}ch5_fig5_4_composition$" "the first experiment's row"
expect "^${row}ch5_fig5_6_relative_pose$" "the second experiment's row"
expect "^reproduce: ran 2 experiment\(s\) in [0-9]+s \([0-9]+\.[0-9] s\)$" "the total"
# Shares of a total that includes both runs: each near half, their sum at most 100 %.
shares=$(sed -nE 's/^ +[0-9.]+ s +([0-9.]+) % .*  ch5_.*/\1/p' <<<"$out")
if ! awk '{ s += $1; if ($1 < 30 || $1 > 70) bad = 1 } END { exit (bad || s > 100.05) }' <<<"$shares"; then
  echo "FAIL: shares $(tr '\n' ' ' <<<"$shares") are not about half each, summing to at most 100 %"; fail=1
fi
# The fake drivers sleep: their CPU is a small part of their wall time, so the CPU column is the children's CPU
# time, not their wall time.
cores=$(sed -nE 's/^ +[0-9.]+ s +[0-9.]+ % +[0-9.]+ s +([0-9.]+)  ch5_.*/\1/p' <<<"$out")
if [ "$(wc -l <<<"$cores")" -ne 2 ] || ! awk '{ if ($1 >= 0.5) bad = 1 } END { exit bad }' <<<"$cores"; then
  echo "FAIL: cores $(tr '\n' ' ' <<<"$cores") of two sleeping drivers are not both below 0.5"; fail=1
fi
if [ $fail -ne 0 ]; then echo "--- output:"; echo "$out"; exit 1; fi
echo "reproduce.local_times: ok"
