#!/usr/bin/env bash
# keel's certified solve (keel solve --certify) and SE-Sync side by side on SE-Sync's benchmark graphs, one data
# set at a time, one thread each, in one run. Both solve the same isotropic (chordal) problem, so the costs compare
# directly; the certificates differ (keel: a rigorous lower bound with a rounding margin on the rotation-shifted
# S; SE-Sync: Cholesky of S + 1e-3·I over all coordinates, no margin).
#
#   bench/side_by_side/certified.sh [OUT.tsv]
#
# REPEAT (default 1) runs each tool that many times per data set and reports the median time, for a machine whose
# timings scatter. KEEL (default build/release/keel) is keel's command; SESYNC_MEASURE, when set, is a measurement
# driver built outside the repository against SE-Sync's library (docs/DESIGN.md, "Certified pose-graph
# optimization", says how it was built and what it prints: lines key=value with F_xhat, total_s, final_rank,
# status; with SESYNC_SERIAL_OPENMP=1 it serializes OpenMP as keel does). Without it only keel runs. DATASETS
# (default ../shared/datasets) holds the files.
set -euo pipefail
cd "$(dirname "$0")/../.."
KEEL=${KEEL:-build/release/keel}
D=${DATASETS:-../shared/datasets}
OUT=${1:-/dev/stdout}
REPEAT=${REPEAT:-1}  # runs per tool and data set; the times are their median (the costs are the last run's)
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
[[ -x $KEEL ]] || { echo "certified.sh: $KEEL not built (cmake --build build/release --target keel)" >&2; exit 2; }
files=()
for b in CSAIL MIT ais2klinik cubicle kitti_00 kitti_02 kitti_05 smallGrid3D sphere_bignoise_vertex3 torus3D tinyGrid3D; do
  files+=("$b=$D/se-sync-benchmarks/$b.g2o")
done
files+=("manhattan=$D/manhattan3500/se-sync/manhattan.g2o" "city10000=$D/city10000/se-sync/city10000.g2o"
        "intel=$D/intel/se-sync/intel.g2o" "sphere2500=$D/sphere2500/se-sync/sphere2500.g2o"
        "parking-garage=$D/parking-garage/se-sync/parking-garage.g2o")
# The median of the arguments (seconds).
median() { python3 -c "import statistics,sys; print('%.4f' % statistics.median(map(float, sys.argv[1:])))" "$@"; }
# A field of keel's --json certificate; a missing bound (null: nothing proven) prints "none".
field() {
  python3 -c "import json,sys; j=json.load(open(sys.argv[1])); c=j['certificate']; v=$2; print('none' if v is None else v)" "$1"
}
{
  printf 'dataset\tkeel_F\tkeel_lower\tkeel_gap\tkeel_status\tkeel_rank\tkeel_iterations\tkeel_total_s\tsesync_F\tsesync_status\tsesync_rank\tsesync_total_s\tfaster\n'
  for entry in "${files[@]}"; do
    name=${entry%%=*} f=${entry#*=}
    [[ -f $f ]] || { echo "certified.sh: $f missing (scripts/fetch-datasets)" >&2; continue; }
    echo "== $name" >&2
    k=$(mktemp)
    kTs=()
    for ((rep = 0; rep < REPEAT; ++rep)); do
      timeout 600 "$KEEL" solve --certify --json -q "$f" >"$k" 2>"$k.err" || break
      kTs+=("$(field "$k" "'%.4f' % c['times_s']['total']")")
    done
    if ((${#kTs[@]} == REPEAT)); then
      kF=$(field "$k" "'%.10g' % c['final_cost']")
      kL=$(field "$k" "None if c['lower_bound'] is None else '%.10g' % c['lower_bound']")
      kG=$(field "$k" "None if c['relative_gap'] is None else '%.2g' % c['relative_gap']")
      kS=$(field "$k" "c['termination']")
      kR=$(field "$k" "c['final_rank']")
      kI=$(field "$k" "c['iterations']")
      kT=$(median "${kTs[@]}")
    else
      kF=error kL= kG= kS="$(head -c 120 "$k.err" | tr '\t\n' '  ')" kR= kI= kT=
    fi
    rm -f "$k" "$k.err"
    sF= sS= sR= sT=
    if [[ -n ${SESYNC_MEASURE:-} ]]; then
      s=$(mktemp)
      sTs=()
      get() { grep -m1 "^$1=" "$s" | cut -d= -f2-; }
      for ((rep = 0; rep < REPEAT; ++rep)); do
        timeout 600 "$SESYNC_MEASURE" "$f" >"$s" 2>&1 || break
        sTs+=("$(get total_s)")
      done
      if ((${#sTs[@]} == REPEAT)); then
        sF=$(get F_xhat) sS=$(get status) sR=$(get final_rank) sT=$(median "${sTs[@]}")
      else
        sS=error
      fi
      rm -f "$s"
    fi
    faster=
    if [[ -n $sT && -n $kT ]]; then
      # SE-Sync's timer has 1 ms resolution: below 2 ms on either side the ratio means nothing.
      faster=$(python3 -c "import sys; k,s=float(sys.argv[1]),float(sys.argv[2]); print('below 2 ms' if min(k,s)<0.002 else 'keel %.2fx' % (s/k) if k<s else 'SE-Sync %.2fx' % (k/s))" "$kT" "$sT")
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$kF" "$kL" "$kG" "$kS" "$kR" "$kI" "$kT" \
      "$sF" "$sS" "$sR" "$sT" "$faster"
  done
} >"$OUT"
