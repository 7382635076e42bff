# scripts/lib/reproduce-slurm.bash — the --slurm path of scripts/reproduce, sourced by it after the build. It reads
# reproduce's variables: profile do_bless threads ids preset bin keel shards partition time_limit sbatch_args shared
# dry_run no_wait no_report invoked_from (see `scripts/reproduce --help`).
#
# Layout under the shared folder S (every node must see it at the same path):
#   S/<id>/shard.sh            job-array script: task k runs shard k of N and writes S/<id>/part-<k>.bin
#   S/<id>/merge.sh            merges part-0..N-1.bin into results/<id>/latest.json
#   S/<id>/whole.sh            the plain run of a runs_whole experiment (instead of shard.sh + merge.sh)
#   S/<id>/status-<k|merge|whole>   the exit code of that step, written by the job itself when it ends
#   S/<id>/logs/               %A_%a.out (shards), merge_%j.out, whole_%j.out
#   S/report.sh, S/logs/report_%j.out, S/status-report, S/status-diff
#   S/jobs                     "<kind> <id> <jobid>" per submitted job
# Success is read from these files, not from Slurm's accounting (often disabled): a step succeeded when its status
# file says 0 (and, for a shard, its partial file exists). A job that Slurm killed (time limit, cancel, node failure)
# writes no status and counts as failed.
# shellcheck shell=bash disable=SC2154  # the variables above are assigned by scripts/reproduce, which sources this file

# q ARGS...: the arguments shell-quoted and joined by spaces, as they are pasted into job scripts and commands.
q() {
  local out="" a
  for a in "$@"; do out+="${out:+ }$(printf '%q' "$a")"; done
  printf '%s' "$out"
}

# runs_whole ID: true when experiments/ID/experiment.toml has a top-level `runs_whole = ...` key (before any table).
runs_whole() {
  awk '/^[ \t]*\[/ { exit } /^runs_whole[ \t]*=/ { found = 1; exit } END { exit !found }' "experiments/$1/experiment.toml"
}

slurm_fmt() {  # slurm_fmt SECONDS: 42s, 3m05s, 2h10m
  awk -v s="$1" 'BEGIN { if (s < 60) printf "%ds", s; else if (s < 3600) printf "%dm%02ds", s / 60, s % 60;
                         else printf "%dh%02dm", s / 3600, (s % 3600) / 60 }'
}

# The threads argument a job passes to its driver: --threads N when given, else the CPUs Slurm granted the job.
threads_expr() {
  if [ -n "$threads" ]; then printf '%s' "$threads"; else printf '%s' '"${SLURM_CPUS_PER_TASK:-1}"'; fi
}

# Header lines common to every job script.
job_header() {  # job_header JOBNAME OUTPUT
  printf '#SBATCH --job-name=%s\n#SBATCH --output=%s\n' "$1" "$2"
  [ -z "$threads" ] || printf '#SBATCH --cpus-per-task=%s\n' "$threads"
}

gen_shard() {  # gen_shard ID: the job-array script of one shardable experiment
  local id=$1 dir=$shared/$1
  cat <<EOF
#!/bin/bash
# Shard job of $id (profile $profile, $shards shards), written by scripts/reproduce --slurm. Array task k runs shard
# k of $shards, writes part-k.bin and records its exit code in status-k. Re-run shard K alone with
#   sbatch [the same options] --array=K $dir/shard.sh
$(job_header "keel-$id" "$dir/logs/%A_%a.out")
k=\${SLURM_ARRAY_TASK_ID:?run this script as a job array: sbatch --array=K ...}
dir=$(q "$dir")
rm -f "\$dir/part-\$k.bin" "\$dir/status-\$k"
echo "keel: $id shard \$k/$shards (profile $profile) on \$(hostname), \$(date)"
cd $(q "$repo") && $(q "$repo/$bin/experiments/$id") --config $(q "experiments/$id/experiment.toml") --profile $profile \\
  --slice "\$k/$shards" --partial "\$dir/part-\$k.bin" --threads $(threads_expr)
rc=\$?
if [ \$rc -eq 0 ] && [ ! -s "\$dir/part-\$k.bin" ]; then echo "keel: exit 0 but no partial file \$dir/part-\$k.bin"; rc=1; fi
echo "keel: shard \$k ended with exit code \$rc, \$(date)"
echo \$rc >"\$dir/status-\$k"
exit \$rc
EOF
}

gen_merge() {  # gen_merge ID: the merge job, run after every shard of ID succeeded
  local id=$1 dir=$shared/$1
  cat <<EOF
#!/bin/bash
# Merge job of $id: reads the $shards partial files of its shards and writes results/$id/latest.json (the same
# file a single-machine run writes). Written by scripts/reproduce --slurm; it runs after all shards succeeded.
$(job_header "keel-$id-merge" "$dir/logs/merge_%j.out")
dir=$(q "$dir")
rm -f "\$dir/status-merge"
parts=() missing=()
for ((k = 0; k < $shards; k++)); do
  parts+=("\$dir/part-\$k.bin")
  [ -s "\$dir/part-\$k.bin" ] || missing+=("\$k")
done
if [ \${#missing[@]} -gt 0 ]; then
  echo "keel: no partial file from shard(s) \${missing[*]} of $shards; see their logs \$dir/logs/<job>_<shard>.out"
  echo 1 >"\$dir/status-merge"
  exit 1
fi
echo "keel: merging $shards shards of $id on \$(hostname), \$(date)"
cd $(q "$repo") && $(q "$repo/$bin/experiments/$id") --config $(q "experiments/$id/experiment.toml") --profile $profile \\
  --threads $(threads_expr) --merge "\${parts[@]}" --out $(q "results/$id/latest.json")
rc=\$?
echo "keel: merge ended with exit code \$rc, \$(date)"
echo \$rc >"\$dir/status-merge"
exit \$rc
EOF
}

gen_whole() {  # gen_whole ID: one plain job for a runs_whole experiment
  local id=$1 dir=$shared/$1
  cat <<EOF
#!/bin/bash
# Whole-run job of $id (its experiment.toml says runs_whole: it is not a set of independent trials), written by
# scripts/reproduce --slurm: the normal run, writing results/$id/latest.json.
$(job_header "keel-$id" "$dir/logs/whole_%j.out")
dir=$(q "$dir")
rm -f "\$dir/status-whole"
echo "keel: $id (profile $profile, whole) on \$(hostname), \$(date)"
cd $(q "$repo") && $(q "$repo/$bin/experiments/$id") --config $(q "experiments/$id/experiment.toml") --profile $profile \\
  --threads $(threads_expr) --out $(q "results/$id/latest.json")
rc=\$?
echo "keel: ended with exit code \$rc, \$(date)"
echo \$rc >"\$dir/status-whole"
exit \$rc
EOF
}

gen_report() {  # gen_report: the job after all merges, doing what the local path of scripts/reproduce does last
  local id steps=""
  for id in "${ids[@]}"; do steps+=" $id:${kind[$id]}"; done
  cat <<EOF
#!/bin/bash
# Report job, written by scripts/reproduce --slurm. After every merge and whole run ended (successfully or not), it
# runs what scripts/reproduce runs after its runs over the experiments whose result was written:
#   $([ "$do_bless" -eq 1 ] && echo "keel bless, ")keel diff against the baselines, scripts/plot, keel report.
# Its exit code goes to status-report, that of the diff to status-diff.
$(job_header "keel-report" "$shared/logs/report_%j.out")
shared=$(q "$shared")
rm -f "\$shared/status-report" "\$shared/status-diff"
cd $(q "$repo") || { echo 1 >"\$shared/status-report"; exit 1; }
keel=$(q "$repo/$keel")
ok_ids=() failed=()
for step in$steps; do
  id=\${step%%:*}
  if [ "\$(cat "\$shared/\$id/status-\${step#*:}" 2>/dev/null)" = 0 ]; then ok_ids+=("\$id"); else failed+=("\$id"); fi
done
[ \${#failed[@]} -eq 0 ] || echo "keel: no result from: \${failed[*]} (left out of the diff and the figures)"
rc=0 diff_rc=0
EOF
  if [ "$do_bless" -eq 1 ]; then
    echo "[ \${#ok_ids[@]} -eq 0 ] || \"\$keel\" bless --profile $profile ${bless_args[*]} \"\${ok_ids[@]}\" || rc=1"
  fi
  cat <<EOF
if [ \${#ok_ids[@]} -gt 0 ]; then "\$keel" diff --profile $profile "\${ok_ids[@]}" || diff_rc=\$?; fi
[ \$diff_rc -eq 0 ] || rc=1
scripts/plot --results results --out $(q "$paper/figures") "\${ok_ids[@]}" || { echo "keel: figure rendering failed"; rc=1; }
"\$keel" report --profile $profile --from $([ "$do_bless" -eq 1 ] && echo baseline || echo latest) --paper $(q "$paper") || rc=1
echo \$diff_rc >"\$shared/status-diff"
echo \$rc >"\$shared/status-report"
exit \$rc
EOF
}

# status_of FILE: the exit code recorded in FILE, or "" when there is none.
status_of() { [ -s "$1" ] && tr -dc '0-9' <"$1" || true; }

reproduce_slurm() {
  case "$shards" in '' | *[!0-9]* | 0) echo "reproduce: --shards must be a positive integer, got '$shards'" >&2; return 2 ;; esac
  if [ -n "$threads" ]; then
    case "$threads" in *[!0-9]* | 0) echo "reproduce: --threads must be a positive integer, got '$threads'" >&2; return 2 ;; esac
  fi
  if [ $dry_run -eq 0 ]; then
    local c
    for c in sbatch squeue scancel; do
      command -v "$c" >/dev/null 2>&1 || {
        echo "reproduce: $c not found: run on a Slurm login node (or start a local cluster:" \
          "scripts/slurm-local start DIR, then export SLURM_CONF=DIR/slurm.conf)" >&2
        return 1
      }
    done
  fi
  repo=$PWD
  paper=paper; [ "$profile" = quick ] && paper=paper/quick
  [ -n "$shared" ] || shared=$repo/results/slurm
  case "$shared" in /*) ;; *) shared=$invoked_from/$shared ;; esac
  shared=${shared%/}

  local id
  declare -gA kind=()
  for id in "${ids[@]}"; do
    [ -f "experiments/$id/experiment.toml" ] || { echo "reproduce: unknown experiment '$id' (no experiments/$id/experiment.toml)" >&2; return 2; }
    if [ $dry_run -eq 0 ] && [ ! -x "$bin/experiments/$id" ]; then
      echo "reproduce: no driver $bin/experiments/$id (build preset $preset first)" >&2; return 1
    fi
    if runs_whole "$id"; then kind[$id]=whole; else kind[$id]=merge; fi
  done

  # The options every sbatch call gets.
  sb=()
  [ -z "$partition" ] || sb+=(--partition="$partition")
  [ -z "$time_limit" ] || sb+=(--time="$time_limit")
  local extra=()
  read -r -a extra <<<"$sbatch_args" || true
  sb+=("${extra[@]}")

  if [ $dry_run -eq 1 ]; then
    slurm_dry_run
    return 0
  fi

  # Refuse to reuse a shared folder whose previous jobs are still queued: they would overwrite the new partials.
  if [ -s "$shared/jobs" ]; then
    local old
    old=$(awk '{ print $3 }' "$shared/jobs" | paste -sd, -)
    if [ -n "$old" ] && [ -n "$(squeue -h -j "$old" -o '%i' 2>/dev/null || true)" ]; then
      echo "reproduce: jobs of an earlier submission into $shared are still queued or running ($old);" \
        "wait for them, cancel them (scancel ${old//,/ }), or use another --shared" >&2
      return 1
    fi
  fi

  # Fresh step files; logs are kept (their names carry the job id).
  mkdir -p "$shared/logs"
  rm -f "$shared/jobs" "$shared/status-report" "$shared/status-diff"
  for id in "${ids[@]}"; do
    mkdir -p "$shared/$id/logs"
    rm -f "$shared/$id"/part-*.bin "$shared/$id"/status-*
    if [ "${kind[$id]}" = whole ]; then
      gen_whole "$id" >"$shared/$id/whole.sh"
    else
      gen_shard "$id" >"$shared/$id/shard.sh"
      gen_merge "$id" >"$shared/$id/merge.sh"
    fi
  done
  [ $no_report -eq 1 ] || gen_report >"$shared/report.sh"

  # Submit; if one sbatch fails, cancel what was submitted, so that nothing half-submitted runs.
  declare -gA array_job=() final_job=()
  report_job=""
  local submitted=() j
  submit() {  # submit VAR ARGS...: sbatch --parsable ARGS, the job id into VAR
    local var=$1 out
    shift
    if ! out=$(sbatch --parsable "${sb[@]}" "$@" 2>&1); then
      echo "reproduce: sbatch failed: $out" >&2
      echo "reproduce: the command was: sbatch --parsable $(q "${sb[@]}" "$@")" >&2
      if [ ${#submitted[@]} -gt 0 ]; then
        echo "reproduce: cancelling the jobs already submitted: ${submitted[*]}" >&2
        scancel "${submitted[@]}" 2>/dev/null || true
      fi
      return 1
    fi
    out=${out%%;*}  # "id;cluster" on a federation
    out=$(tail -n1 <<<"$out")
    submitted+=("$out")
    printf -v "$var" '%s' "$out"
  }
  local deps=""
  for id in "${ids[@]}"; do
    if [ "${kind[$id]}" = whole ]; then
      submit j "$shared/$id/whole.sh" || return 1
      final_job[$id]=$j
      echo "whole $id $j" >>"$shared/jobs"
    else
      submit j --array="0-$((shards - 1))" "$shared/$id/shard.sh" || return 1
      array_job[$id]=$j
      echo "array $id $j" >>"$shared/jobs"
      # afterok on an array waits for every task; a failed task makes the dependency impossible, and
      # --kill-on-invalid-dep cancels the merge then instead of leaving it pending for ever.
      submit j --dependency="afterok:${array_job[$id]}" --kill-on-invalid-dep=yes "$shared/$id/merge.sh" || return 1
      final_job[$id]=$j
      echo "merge $id $j" >>"$shared/jobs"
    fi
    deps+=":${final_job[$id]}"
  done
  if [ $no_report -eq 0 ]; then
    submit report_job --dependency="afterany$deps" "$shared/report.sh" || return 1
    echo "report - $report_job" >>"$shared/jobs"
  fi
  t_submit=$(date +%s)
  echo "reproduce: submitted ${#submitted[@]} job(s) for ${#ids[@]} experiment(s) ($profile, $shards shards each" \
    "where shardable); job list in $shared/jobs" >&2

  if [ $no_wait -eq 1 ]; then
    echo "reproduce: not waiting. Follow with: squeue -j $(IFS=,; echo "${submitted[*]}")" >&2
    echo "reproduce: logs under $shared/<id>/logs/; results in results/<id>/latest.json" >&2
    [ -z "$report_job" ] || echo "reproduce: the report ($paper/REPRODUCTION.md) when job $report_job ends" \
      "(log $shared/logs/report_${report_job}.out)" >&2
    return 0
  fi
  slurm_wait "${submitted[@]}"
  slurm_summary
}

slurm_dry_run() {
  local id n=0
  echo "# scripts/reproduce --slurm --dry-run: the job scripts it would write under $shared and the sbatch commands"
  echo "# it would run (in this order; \$a<i>, \$m<i> are the job ids the earlier commands print). Nothing was written,"
  echo "# built or submitted."
  for id in "${ids[@]}"; do
    if [ "${kind[$id]}" = whole ]; then
      echo; echo "#### $shared/$id/whole.sh  (runs_whole: one plain job)"; gen_whole "$id"
    else
      echo; echo "#### $shared/$id/shard.sh"; gen_shard "$id"
      echo; echo "#### $shared/$id/merge.sh"; gen_merge "$id"
    fi
  done
  if [ $no_report -eq 0 ]; then echo; echo "#### $shared/report.sh"; gen_report; fi
  echo; echo "#### submission"
  local deps=""
  for id in "${ids[@]}"; do
    n=$((n + 1))
    if [ "${kind[$id]}" = whole ]; then
      echo "m$n=\$(sbatch --parsable $(q "${sb[@]}" "$shared/$id/whole.sh"))"
    else
      echo "a$n=\$(sbatch --parsable $(q "${sb[@]}" --array="0-$((shards - 1))" "$shared/$id/shard.sh"))"
      echo "m$n=\$(sbatch --parsable $(q "${sb[@]}") --dependency=afterok:\$a$n --kill-on-invalid-dep=yes $(q "$shared/$id/merge.sh"))"
    fi
    deps+=":\$m$n"
  done
  [ $no_report -eq 1 ] || echo "sbatch --parsable $(q "${sb[@]}") --dependency=afterany$deps $(q "$shared/report.sh")"
}

# slurm_wait JOBIDS...: poll squeue until none of the jobs is pending or running, showing per experiment how many
# shards are pending, running and done. Ctrl-C stops waiting, not the jobs.
slurm_wait() {
  local list poll=${KEEL_SLURM_POLL:-5} tty=0 shown=0 last="" squeue_failures=0
  list=$(IFS=,; echo "$*")
  [ -t 2 ] && tty=1
  trap 'echo >&2; echo "reproduce: stopped waiting; the jobs go on (scancel ${list//,/ } cancels them; job list in $shared/jobs)" >&2; exit 130' INT
  local width=6 id
  for id in "${ids[@]}"; do [ ${#id} -le $width ] || width=${#id}; done
  declare -gA qstate=()
  while :; do
    local out rc=0
    out=$(squeue -h -r -j "$list" -o '%i %t %r' 2>&1) || rc=$?
    if [ $rc -ne 0 ]; then
      if grep -q 'Invalid job id' <<<"$out"; then
        out=""  # every job has left the queue
      else
        squeue_failures=$((squeue_failures + 1))
        [ $squeue_failures -lt 3 ] || echo "reproduce: squeue fails ($out); retrying" >&2
        sleep "$poll"
        continue
      fi
    fi
    squeue_failures=0
    qstate=()
    local jid st reason active=0
    while read -r jid st reason; do
      [ -n "$jid" ] || continue
      case "$st" in
        PD)
          # A dependency that can never be met on a cluster without kill_invalid_depend: cancel it ourselves.
          if [ "$reason" = DependencyNeverSatisfied ]; then
            scancel "$jid" 2>/dev/null || true
            continue
          fi
          qstate[$jid]=PD; active=1 ;;
        R | CF | CG | S | ST | RQ | RS | RF | RH | RD | SI | SO) qstate[$jid]=R; active=1 ;;
        *) ;;  # CD, F, CA, TO, NF, OOM, PR, BF, DL: ended
      esac
    done <<<"$out"

    local lines=() done_jobs=0 total_jobs=0 p r d f s k line
    for id in "${ids[@]}"; do
      line=$(printf "  %-${width}s " "$id")
      if [ "${kind[$id]}" = merge ]; then
        p=0 r=0 d=0 f=0
        for ((k = 0; k < shards; k++)); do
          case "${qstate[${array_job[$id]}_$k]:-}" in
            PD) p=$((p + 1)) ;;
            R) r=$((r + 1)) ;;
            *) d=$((d + 1)); [ "$(status_of "$shared/$id/status-$k")" = 0 ] || f=$((f + 1)) ;;
          esac
        done
        # A pending array can also show as one line without a task index.
        if [ "${qstate[${array_job[$id]}]:-}" = PD ] && [ $p -eq 0 ]; then p=$((shards - r)); d=0; f=0; fi
        done_jobs=$((done_jobs + d)); total_jobs=$((total_jobs + shards))
        line+="shards: $p pending, $r running, $d done$([ $f -eq 0 ] || echo " ($f failed)") | merge: "
      else
        line+="whole run: "
      fi
      total_jobs=$((total_jobs + 1))
      case "${qstate[${final_job[$id]}]:-}" in
        PD) [ "${kind[$id]}" = merge ] && line+="waiting" || line+="pending" ;;
        R) line+="running" ;;
        *) done_jobs=$((done_jobs + 1))
           s=$(status_of "$shared/$id/status-${kind[$id]}")
           case "$s" in 0) line+="done" ;; "") line+="not run" ;; *) line+="failed (exit $s)" ;; esac ;;
      esac
      lines+=("$line")
    done
    if [ -n "$report_job" ]; then
      total_jobs=$((total_jobs + 1))
      case "${qstate[$report_job]:-}" in
        PD) line="waiting" ;;
        R) line="running" ;;
        *) done_jobs=$((done_jobs + 1)); line="ended" ;;
      esac
      lines+=("  report: $line")
    fi
    local head="reproduce: $done_jobs/$total_jobs jobs done"
    local text
    text=$(printf '%s\n' "${lines[@]}")
    if [ $tty -eq 1 ]; then
      [ $shown -eq 0 ] || printf '\033[%dA\033[J' $((${#lines[@]} + 1)) >&2
      printf '%s, %s elapsed\n%s\n' "$head" "$(slurm_fmt $(($(date +%s) - t_submit)))" "$text" >&2
      shown=1
    elif [ "$head$text" != "$last" ]; then
      printf '%s, %s elapsed\n%s\n' "$head" "$(slurm_fmt $(($(date +%s) - t_submit)))" "$text" >&2
      last="$head$text"
    fi
    [ $active -eq 1 ] || break
    sleep "$poll"
  done
  trap - INT
  echo "reproduce: all jobs ended after $(slurm_fmt $(($(date +%s) - t_submit)))" >&2
}

# slurm_summary: after the jobs ended, say what failed (with logs and the commands that re-run it) and print the
# report job's output; returns 1 when anything failed.
slurm_summary() {
  local id k s failed=0 failed_shards log sbq
  sbq=$(q "${sb[@]}")
  sbq=${sbq:+$sbq }
  # Status files are written just before a job ends; on a network filesystem they may show up a moment later.
  sleep 1
  for id in "${ids[@]}"; do
    if [ "${kind[$id]}" = merge ]; then
      failed_shards=()
      for ((k = 0; k < shards; k++)); do
        s=$(status_of "$shared/$id/status-$k")
        [ "$s" = 0 ] && [ -s "$shared/$id/part-$k.bin" ] && continue
        failed_shards+=("$k")
        log=$shared/$id/logs/${array_job[$id]}_$k.out
        if [ -z "$s" ]; then s="no exit code recorded (cancelled, out of time or killed: see the log)"
        elif [ "$s" = 0 ]; then s="exit 0 but no partial file"
        else s="exit $s"; fi
        echo "reproduce: FAILED $id shard $k/$shards: $s" >&2
        if [ -e "$log" ]; then
          echo "    log:          $log" >&2
          [ ! -s "$log" ] || tail -n 3 "$log" | sed 's/^/                  | /' >&2
        else
          echo "    log:          none (the shard never started: cancelled while pending?)" >&2
        fi
        echo "    re-run alone: sbatch ${sbq}--array=$k $(q "$shared/$id/shard.sh")" >&2
      done
      if [ ${#failed_shards[@]} -gt 0 ]; then
        failed=1
        echo "  to re-run the failed shards of $id and then merge them:" >&2
        echo "    j=\$(sbatch --parsable ${sbq}--array=$(IFS=,; echo "${failed_shards[*]}") $(q "$shared/$id/shard.sh")) &&" \
          "sbatch ${sbq}--dependency=afterok:\$j $(q "$shared/$id/merge.sh")" >&2
        continue
      fi
    fi
    s=$(status_of "$shared/$id/status-${kind[$id]}")
    [ "$s" = 0 ] && continue
    failed=1
    [ "${kind[$id]}" = merge ] && log=$shared/$id/logs/merge_${final_job[$id]}.out || log=$shared/$id/logs/whole_${final_job[$id]}.out
    echo "reproduce: FAILED $id ${kind[$id]}: $([ -n "$s" ] && echo "exit $s" || echo "no exit code recorded (cancelled, out of time or killed)")" >&2
    echo "    log:    $log" >&2
    [ ! -s "$log" ] || tail -n 5 "$log" | sed 's/^/      | /' >&2
    echo "    re-run: sbatch ${sbq}$(q "$shared/$id/${kind[$id]}.sh")" >&2
  done

  local report_status="" diff_status=""
  if [ -n "$report_job" ]; then
    local rlog=$shared/logs/report_${report_job}.out
    report_status=$(status_of "$shared/status-report")
    diff_status=$(status_of "$shared/status-diff")
    if [ -s "$rlog" ]; then
      echo "reproduce: output of the report job ($rlog):" >&2
      cat "$rlog"
    fi
    if [ -z "$report_status" ]; then
      echo "reproduce: the report job recorded no exit code (cancelled, out of time or killed); log $rlog" >&2
    elif [ "$report_status" != 0 ]; then
      echo "reproduce: the report job failed (exit $report_status); log $rlog" >&2
    fi
  fi
  if [ $failed -ne 0 ]; then
    echo "reproduce: some jobs failed (above); their experiments have no new results/<id>/latest.json" >&2
    [ -z "$report_job" ] || echo "reproduce: after re-running what failed, redo the report:" \
      "sbatch ${sbq}$(q "$shared/report.sh")  (or run scripts/reproduce --slurm again)" >&2
    return 1
  fi
  if [ -n "$report_job" ]; then
    if [ -n "$diff_status" ] && [ "$diff_status" != 0 ]; then
      echo "reproduce: some results left their baseline tolerance (see the table above); if the change is intended," \
        "rerun with --bless and say why in the commit" >&2
      return 1
    fi
    [ "$report_status" = 0 ] || return 1
    echo "reproduce: done; report in $paper/REPRODUCTION.md" >&2
  else
    echo "reproduce: done; results in results/<id>/latest.json (no report: --no-report)" >&2
  fi
  return 0
}
