#!/usr/bin/env bash
# keel's certified solve (keel solve --certify) and SE-Sync side by side, one data set at a time, one thread each,
# in one run. Both solve the same isotropic (chordal) problem, so the costs compare directly; the certificates
# differ (keel: a rigorous lower bound with a rounding margin on the rotation-shifted S; SE-Sync: Cholesky of
# S + 1e-3·I over all coordinates, no margin; at MaxRank SE-Sync's SDPval is not a bound).
#
#   bench/side_by_side/certified.sh [OUT.tsv]
#
# Two timing rules, both reported for both tools:
#   own      each tool's own timer: keel's times_s.total (problem set-up included, file reading not);
#            SE-Sync's total_computation_time (its problem construction, the data matrices and two Cholesky
#            factorizations, NOT included).
#   process  the whole process, from exec to exit: loading its libraries, reading the file, construction, solve,
#            output. Timed here around each command, the same way for both tools (the SE-Sync driver's own
#            process_s, from main's start to the end of the solve, leaves out the loader and static
#            initialization and is not used).
#
# REPEAT (default 1) runs each tool that many times per data set and reports the median times (the costs are
# the last run's). KEEL (default build/release/keel) is keel's command. SESYNC_MEASURE, when set, is the
# measurement driver bench/side_by_side/sesync_measure.cpp built outside the repository against SE-Sync's
# library (shared/notes/peers.md gives the recipe); it prints key=value lines (F_xhat, SDPval, status,
# final_rank, sesync_total_s, process_s). Without it only keel runs. SESYNC_SERIAL_OPENMP=1 (set here)
# serializes OpenMP in the driver as keel does for CHOLMOD. DATASETS (default ../shared/datasets) holds the
# files; FILES, when set, replaces the list: "name=path name=path ...". TIMEOUT (default 600 s) bounds each run.
# KEEL_ARGS (default none) adds options to keel's command (bench/side_by_side/noise.sh: --time-limit).
set -euo pipefail
cd "$(dirname "$0")/../.."
KEEL=${KEEL:-build/release/keel}
D=${DATASETS:-../shared/datasets}
OUT=${1:-/dev/stdout}
REPEAT=${REPEAT:-1}
TIMEOUT=${TIMEOUT:-600}
KEEL_ARGS=${KEEL_ARGS:-}
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 SESYNC_SERIAL_OPENMP=1
[[ -x $KEEL ]] || { echo "certified.sh: $KEEL not built (cmake --build build/release --target keel)" >&2; exit 2; }
files=()
if [[ -n ${FILES:-} ]]; then
  read -r -a files <<<"$FILES"
else
  for b in CSAIL MIT ais2klinik cubicle kitti_00 kitti_02 kitti_05 smallGrid3D sphere_bignoise_vertex3 torus3D tinyGrid3D; do
    files+=("$b=$D/se-sync-benchmarks/$b.g2o")
  done
  files+=("manhattan=$D/manhattan3500/se-sync/manhattan.g2o" "city10000=$D/city10000/se-sync/city10000.g2o"
          "intel=$D/intel/se-sync/intel.g2o" "sphere2500=$D/sphere2500/se-sync/sphere2500.g2o"
          "parking-garage=$D/parking-garage/se-sync/parking-garage.g2o")
fi
# The median of the arguments (seconds).
median() { python3 -c "import statistics,sys; print('%.4f' % statistics.median(map(float, sys.argv[1:])))" "$@"; }
# Seconds from one $EPOCHREALTIME to another, the process rule's clock for both tools.
elapsed() { python3 -c "import sys; print('%.4f' % (float(sys.argv[2]) - float(sys.argv[1])))" "$1" "$2"; }
# A field of keel's --json certificate; a missing bound (null: nothing proven) prints "none".
field() {
  python3 -c "import json,sys; j=json.load(open(sys.argv[1])); c=j['certificate']; v=$2; print('none' if v is None else v)" "$1"
}
# "keel 1.23x" or "SE-Sync 1.23x": who is faster by how much; SE-Sync's timer has 1 ms resolution, so below
# 2 ms on either side the ratio means nothing.
faster() {
  [[ -n $1 && -n $2 ]] || return 0
  python3 -c "import sys; k,s=float(sys.argv[1]),float(sys.argv[2]); print('below 2 ms' if min(k,s)<0.002 else 'keel %.2fx' % (s/k) if k<s else 'SE-Sync %.2fx' % (k/s))" "$1" "$2"
}
{
  printf 'dataset\tkeel_F\tkeel_lower\tkeel_gap\tkeel_status\tkeel_rank\tkeel_iterations\tkeel_own_s\tkeel_process_s\tsesync_F\tsesync_SDPval\tsesync_status\tsesync_rank\tsesync_own_s\tsesync_process_s\tfaster_own\tfaster_process\n'
  for entry in "${files[@]}"; do
    name=${entry%%=*} f=${entry#*=}
    [[ -f $f ]] || { echo "certified.sh: $f missing (scripts/fetch-datasets)" >&2; continue; }
    echo "== $name" >&2
    k=$(mktemp)
    kTs=() kPs=()
    for ((rep = 0; rep < REPEAT; ++rep)); do
      start=$EPOCHREALTIME
      rc=0
      timeout "$TIMEOUT" "$KEEL" solve --certify --json -q $KEEL_ARGS "$f" >"$k" 2>"$k.err" || rc=$?
      end=$EPOCHREALTIME
      ((rc <= 1)) || break  # 1: done, not certified (a relaxation that is not exact); anything else failed
      kTs+=("$(field "$k" "'%.4f' % c['times_s']['total']")")
      kPs+=("$(elapsed "$start" "$end")")
    done
    if ((${#kTs[@]} == REPEAT)); then
      kF=$(field "$k" "'%.10g' % c['final_cost']")
      kL=$(field "$k" "None if c['lower_bound'] is None else '%.10g' % c['lower_bound']")
      kG=$(field "$k" "None if c['relative_gap'] is None else '%.2g' % c['relative_gap']")
      kS=$(field "$k" "c['termination']")
      kR=$(field "$k" "c['final_rank']")
      kI=$(field "$k" "c['iterations']")
      kT=$(median "${kTs[@]}") kP=$(median "${kPs[@]}")
    else
      kF=error kL= kG= kS="$(head -c 120 "$k.err" | tr '\t\n' '  ')" kR= kI= kT= kP=
    fi
    rm -f "$k" "$k.err"
    sF= sV= sS= sR= sT= sP=
    if [[ -n ${SESYNC_MEASURE:-} ]]; then
      s=$(mktemp)
      sTs=() sPs=()
      get() { grep -m1 "^$1=" "$s" | cut -d= -f2-; }
      for ((rep = 0; rep < REPEAT; ++rep)); do
        start=$EPOCHREALTIME
        timeout "$TIMEOUT" "$SESYNC_MEASURE" "$f" >"$s" 2>&1 || break
        end=$EPOCHREALTIME
        sTs+=("$(get sesync_total_s)")
        sPs+=("$(elapsed "$start" "$end")")
      done
      if ((${#sTs[@]} == REPEAT)); then
        sF=$(get F_xhat) sV=$(get SDPval) sS=$(get status) sR=$(get final_rank)
        sT=$(median "${sTs[@]}") sP=$(median "${sPs[@]}")
      else
        sS=error
      fi
      rm -f "$s"
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$kF" "$kL" "$kG" "$kS" "$kR" \
      "$kI" "$kT" "$kP" "$sF" "$sV" "$sS" "$sR" "$sT" "$sP" "$(faster "$kT" "$sT")" "$(faster "$kP" "$sP")"
  done
} >"$OUT"
