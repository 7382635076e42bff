#!/usr/bin/env bash
# keel robust and Kimera-RPGO side by side on data sets with wrong loop closures added (robust.py says how the
# files are made and scored), one thread each, both timed as whole processes.
#
#   KIMERA_MEASURE=/path/to/kimera_measure bench/side_by_side/robust.sh OUT.tsv [NAME=FILE.g2o ...]
#
# kimera_measure is keel's driver (bench/side_by_side/kimera_measure.cpp) built against externally built GTSAM and
# Kimera-RPGO (docs/PEERS.md). GTSAM_GNC_MEASURE, when set, adds GTSAM's GncOptimizer
# (bench/side_by_side/gtsam_gnc_measure.cpp, built the same way) as a further tool. Environment: KEEL (default build/release/keel), RATES (default 0,10,20,40),
# TRIALS (default 3), SEED (default 1), P (default 0.11), NO_GNC=1 (Kimera-RPGO's PCM alone), TIMEOUT
# (seconds per tool and file, default 600). Without data sets
# given: Intel, MIT, Manhattan (M3500) and the parking garage from ../shared/datasets. PREPARED=N instead runs the
# graphs of ext_robust_backend's full profile, its first N trials per cell (keel_robust_graphs writes them with the
# experiment's own generator and seed, or with SEED when set: graphs drawn fresh); ROBOTS (default 1; e.g. 1,2,4)
# names the robot counts whose cells are run, each robot's graph a file and the inter-robot candidates another,
# given to both tools; each tool's ATE against the experiment's reference is scored (robust.py).
# GTSAM_GNC_MEASURE takes single-robot cells only. KEEL_VARIANTS
# (";"-separated LABEL=ARGS, e.g. "edge=;snooping=--residual-test snooping") runs keel robust once per variant
# with those extra arguments (default: one run, no extra arguments, labelled keel). SUMMARY_JSON=FILE also writes
# the tables the report renders beside ext_robust_backend (robust.py --summary-json; commit it as
# results/ext_robust_backend/side_by_side.json), with the keel commit, the date, the machine and the command as its
# provenance; PEERS names the peers' versions there (e.g. "Kimera-RPGO d28b4df over GTSAM 0ffe6c930").
set -euo pipefail
cd "$(dirname "$0")/../.."
KEEL=${KEEL:-build/release/keel}
[[ -x $KEEL ]] || { echo "robust.sh: $KEEL not built (scripts/build release)" >&2; exit 2; }
[[ -n ${KIMERA_MEASURE:-} && -x $KIMERA_MEASURE ]] ||
  { echo "robust.sh: set KIMERA_MEASURE to the built kimera_measure (docs/PEERS.md)" >&2; exit 2; }
[[ $# -ge 1 ]] || { echo "usage: robust.sh OUT.tsv [NAME=FILE.g2o ...]" >&2; exit 2; }
out=$1
shift
D=../shared/datasets
sets=("$@")
summary=()
if [[ -n ${SUMMARY_JSON:-} ]]; then
  command=""
  for v in PREPARED SEED ROBOTS RATES TRIALS P NO_GNC TIMEOUT KEEL_VARIANTS; do
    if [[ -n ${!v:-} ]]; then command+="$v=$(printf '%q' "${!v}") "; fi
  done
  summary=(--summary-json "$SUMMARY_JSON" --stamp --provenance "command=${command}bench/side_by_side/robust.sh OUT.tsv $*")
  if [[ -n ${PEERS:-} ]]; then summary+=(--provenance "peers=$PEERS"); fi
fi
if [[ -n ${PREPARED:-} ]]; then
  B=$(dirname "$KEEL")/bench/keel_robust_graphs
  [[ -x $B ]] || { echo "robust.sh: $B not built (scripts/build release)" >&2; exit 2; }
  work=$(mktemp -d)
  seed=${SEED:-$(sed -nE 's/^seed *= *([0-9]+).*/\1/p' experiments/ext_robust_backend/experiment.toml)}
  "$B" experiments/ext_robust_backend/experiment.toml full "$work" "$PREPARED" "$seed" "${ROBOTS:-1}" \
    >"$work/list.txt"
  # ATE is scored with keel's Python module (robust.py), which needs numpy: Debian's python3 (a python3 on PATH
  # may be a pyenv shim without it), as scripts/plot chooses.
  py=${KEEL_PYTHON:-$([[ -x /usr/bin/python3 ]] && echo /usr/bin/python3 || echo python3)}
  exec "$py" bench/side_by_side/robust.py --keel "$KEEL" --kimera "$KIMERA_MEASURE" --out "$out" \
    --p "${P:-0.11}" --timeout "${TIMEOUT:-600}" --variants "${KEEL_VARIANTS:-keel=}" ${GTSAM_GNC_MEASURE:+--gtsam-gnc "$GTSAM_GNC_MEASURE"} \
    --keel-python "$(dirname "$KEEL")/python" --prepared "$work/list.txt" "${summary[@]}"
fi
[[ ${#sets[@]} -gt 0 ]] || sets=(intel=$D/intel/se-sync/intel.g2o mit=$D/se-sync-benchmarks/MIT.g2o
  manhattan=$D/manhattan3500/se-sync/manhattan.g2o garage=$D/parking-garage/se-sync/parking-garage.g2o)
exec python3 bench/side_by_side/robust.py --keel "$KEEL" --kimera "$KIMERA_MEASURE" --out "$out" \
  --rates "${RATES:-0,10,20,40}" --trials "${TRIALS:-3}" --seed "${SEED:-1}" --p "${P:-0.11}" \
  --timeout "${TIMEOUT:-600}" --variants "${KEEL_VARIANTS:-keel=}" \
  ${GTSAM_GNC_MEASURE:+--gtsam-gnc "$GTSAM_GNC_MEASURE"} "${summary[@]}" "${sets[@]}"
