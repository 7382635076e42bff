# Sourced by the side-by-side scripts (clique.sh, align.sh): their log lines, and one driver target built at keel
# revisions in a scratch directory. The sourcing script sets `scratch` (work directory, with logs/ in it), `repo`
# (this checkout's top level) and `sbs_name` (the name its log lines carry) first.
#
# keel_revision REV TARGET SOURCE LIBRARY...  sets `keel_binary` to the driver TARGET built from SOURCE and linked
#   to the LIBRARYs, at REV: a commit id of this repository (`git archive` into SCRATCH/keel-<sha>, kept and reused
#   on later runs), or `worktree` for this checkout's files as they are (copied to SCRATCH/keel-worktree and rebuilt
#   incrementally). The copy's top-level CMakeLists.txt gets the target appended; it is configured with its own
#   "release" preset (falling back to a plain Release/Ninja/clang++-19 configure) and only that target is built.

log() { printf '[%s %s] %s\n' "$sbs_name" "$(date +%H:%M:%S)" "$*" >&2; }
timed() {  # timed LABEL LOGFILE CMD...: run CMD with its output in LOGFILE, report the wall time
  local label=$1 logfile=$2 t0=$SECONDS
  shift 2
  if ! "$@" >>"$logfile" 2>&1; then
    log "$label FAILED; the last lines of $logfile:"
    tail -n 30 "$logfile" >&2
    exit 1
  fi
  log "$label: $((SECONDS - t0)) s"
}

keel_append_target() {  # keel_append_target TREE BASE TARGET SOURCE LIBRARY...: TREE/CMakeLists.txt := BASE + TARGET
  local tree=$1 base=$2 target=$3 source=$4 tmp
  shift 4
  tmp=$(mktemp)
  {
    cat "$base"
    printf '\n# appended by bench/side_by_side/%s\n' "$sbs_name"
    printf 'add_executable(%s %s)\n' "$target" "$source"
    printf 'target_link_libraries(%s PRIVATE %s)\n' "$target" "$*"
  } >"$tmp"
  # rewritten only when it changes, so that its time stamp (and the build) moves only then
  if cmp -s "$tmp" "$tree/CMakeLists.txt"; then rm -f "$tmp"; else mv "$tmp" "$tree/CMakeLists.txt"; fi
}

keel_configure_and_build() {  # keel_configure_and_build LABEL TREE TARGET
  local label=$1 tree=$2 target=$3 logfile=$scratch/logs/keel-$1.log
  if [ ! -e "$tree/build/release/build.ninja" ]; then
    local t0=$SECONDS
    if ! (cd "$tree" && cmake --preset release) >>"$logfile" 2>&1; then
      log "$label: the release preset failed to configure; falling back to a plain Release configure"
      rm -rf "$tree/build/release"
      timed "$label configure (fallback)" "$logfile" \
        cmake -S "$tree" -B "$tree/build/release" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-19
    else
      log "$label configure (release preset): $((SECONDS - t0)) s"
    fi
  fi
  timed "$label build $target" "$logfile" cmake --build "$tree/build/release" --target "$target"
}

keel_revision() {  # keel_revision REV TARGET SOURCE LIBRARY...: sets keel_binary
  local rev=$1 target=$2 tree sha
  if [ "$rev" = worktree ]; then
    tree=$scratch/keel-worktree
    mkdir -p "$tree"
    # This checkout's files as they are now (tracked or not), less its builds, results and git directory; the
    # top-level CMakeLists.txt is written by keel_append_target.
    if command -v rsync >/dev/null; then
      rsync -a --delete --exclude /build --exclude /results --exclude /.git --exclude /CMakeLists.txt \
        "$repo/" "$tree/"
    else  # the same copy by tar (time stamps kept), except that files deleted here are not deleted there
      log "no rsync: copying the worktree with tar (deletions are not propagated)"
      tar -C "$repo" --exclude=./build --exclude=./results --exclude=./.git --exclude=./CMakeLists.txt -cf - . \
        | tar -C "$tree" -xf -
    fi
    keel_append_target "$tree" "$repo/CMakeLists.txt" "${@:2}"
  else
    sha=$(git -C "$repo" rev-parse --verify "$rev^{commit}")
    tree=$scratch/keel-${sha:0:12}
    if [ ! -e "$tree/.keel-extracted" ]; then
      rm -rf "$tree"
      mkdir -p "$tree"
      git -C "$repo" archive "$sha" | tar -x -C "$tree"
      cp "$tree/CMakeLists.txt" "$tree/CMakeLists.txt.orig"
      echo "$sha" >"$tree/.keel-extracted"
    fi
    keel_append_target "$tree" "$tree/CMakeLists.txt.orig" "${@:2}"
  fi
  keel_configure_and_build "$rev" "$tree" "$target"
  keel_binary=$tree/build/release/$target
}
