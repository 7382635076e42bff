#!/usr/bin/env bash
# keel's certified solve and SE-Sync side by side on the graphs of ext_certified_noise (subsets of SE-Sync's
# benchmark graphs with rotation noise or outlier closures on their loop closures), one thread each.
#
#   bench/side_by_side/noise.sh [OUT.tsv]
#
# 1. build/release/bench/keel_noise_graphs writes the experiment's graphs (its own generator, its seed, the
#    profile PROFILE, default full) as g2o files into GRAPHS_DIR (default a new temporary folder);
# 2. bench/side_by_side/certified.sh runs both tools on every file, with its two timing rules (each tool's own
#    timer; the whole process, file reading and problem construction included) and its environment (REPEAT,
#    SESYNC_MEASURE, TIMEOUT, KEEL). keel runs with the experiment's options: `keel solve --certify`'s defaults
#    are its gap tolerance, rank limit, iterations and stationarity test, and --time-limit is its time_limit_s.
#
# keel reads the files back, so its costs are the experiment's (the round trip is exact); its times are a second
# measurement of the same solves. SUMMARY_JSON=FILE (with OUT.tsv given) also writes the tables the report renders
# beside ext_certified_noise (certified_summary.py; commit it as
# results/ext_certified_noise/side_by_side.json), with the keel commit, the date, the machine, the command and
# SESYNC_VERSION (e.g. "SE-Sync 9b631b6") as its provenance.
set -euo pipefail
cd "$(dirname "$0")/../.."
PROFILE=${PROFILE:-full}
GEN=${GEN:-build/release/bench/keel_noise_graphs}
CONFIG=experiments/ext_certified_noise/experiment.toml
[[ -x $GEN ]] || { echo "noise.sh: $GEN not built (cmake --build build/release --target keel_noise_graphs)" >&2; exit 2; }
DIR=${GRAPHS_DIR:-$(mktemp -d)}
limit=$(sed -n 's/^time_limit_s *= *\([0-9.]*\).*/\1/p' "$CONFIG")
[[ -n $limit ]] || { echo "noise.sh: no time_limit_s in $CONFIG" >&2; exit 2; }
files=$("$GEN" "$CONFIG" "$PROFILE" "$DIR" | tr '\n' ' ')
echo "noise.sh: $(wc -w <<<"$files") graphs in $DIR, keel --time-limit $limit" >&2
if [[ -z ${SUMMARY_JSON:-} ]]; then
  FILES="$files" KEEL_ARGS="--time-limit $limit" exec bench/side_by_side/certified.sh "$@"
fi
[[ $# -ge 1 ]] || { echo "noise.sh: SUMMARY_JSON needs OUT.tsv" >&2; exit 2; }
FILES="$files" KEEL_ARGS="--time-limit $limit" bench/side_by_side/certified.sh "$@"
peers=()
if [[ -n ${SESYNC_VERSION:-} ]]; then
  peers=(--provenance "peers=$SESYNC_VERSION, driven by bench/side_by_side/sesync_measure.cpp")
fi
python3 bench/side_by_side/certified_summary.py "$1" "$SUMMARY_JSON" --stamp \
  --provenance "command=PROFILE=$PROFILE REPEAT=${REPEAT:-1} bench/side_by_side/noise.sh OUT.tsv" \
  --provenance "inputs=ext_certified_noise's $PROFILE-profile graphs (keel_noise_graphs: its generator and seed)" \
  "${peers[@]}"
