// Sharded Monte-Carlo runs: one experiment's trials split over N processes (a Slurm job array) and merged
// back to exactly the single-machine result.
//
// Every Monte-Carlo study runs its trials through trial_loop (instead of parallel_for): trial i draws from
// its own random stream (DESIGN convention 9) and writes its outcome into slot i; the reduction over the
// slots is serial. A run is in one of three modes (experiment_main's --slice / --merge set it):
//   whole  trial_loop is parallel_for;
//   slice  shard k of N: only the indices [⌊k·n/N⌋, ⌊(k+1)·n/N⌋) of each loop are computed, their records are
//          saved into the partial file, and the other slots receive a copy of a computed trial so that the
//          rest of the body (whose result is discarded) runs on ordinary values;
//   merge  no trial is computed: every slot is loaded from the partials in index order, and the unchanged
//          serial reduction then gives the single-machine result bit for bit.
// Loops are matched by their order of execution; a merge refuses partials whose loops differ in count or
// size, and partials of another experiment, profile, configuration, seed or commit.
// A trial_loop called inside another trial_loop's body (or from a worker of one) runs as a plain
// parallel_for: only the outermost loop is sharded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "repro/archive.hpp"

namespace keel::core {
class Progress;
}

namespace keel::repro {

using core::Progress;

// "k/N" with 0 <= k < N; throws std::invalid_argument with the accepted form otherwise.
struct Slice {
  std::size_t index = 0, count = 1;
  static Slice parse(const std::string& text);
  // The contiguous index range of this slice of n trials: [⌊k·n/N⌋, ⌊(k+1)·n/N⌋).
  std::size_t begin(std::size_t n) const;
  std::size_t end(std::size_t n) const;
};

// What identifies the run a partial belongs to; a merge refuses partials that differ in any of these.
struct PartialHeader {
  std::string id, profile, git_sha;
  std::uint64_t config_hash = 0, seed = 0;
  Slice slice;
};

// The first field in which two headers differ, with both values as text ("experiment", "profile", "commit",
// "configuration hash", "seed"; the slice is not compared): what a merge names when it refuses partials.
struct HeaderDifference {
  std::string what, a, b;
};
std::optional<HeaderDifference> header_difference(const PartialHeader& a, const PartialHeader& b);

// One trial loop's records in a partial: n trials in all, [begin, end) saved.
struct LoopRecords {
  std::uint64_t n = 0, begin = 0, end = 0;
  std::string bytes;
};

struct Partial {
  PartialHeader header;
  std::string source;  // the file it was read from (for messages)
  std::vector<LoopRecords> loops;
  void write(const std::filesystem::path& path) const;  // atomically (temporary file + rename)
  static Partial read(const std::filesystem::path& path);
};

// The mode of this process's trial loops. set_slice and set_merge are called by experiment_main.
enum class ShardMode { whole, slice, merge };
ShardMode shard_mode();
void set_slice(const Slice& slice);
// Checks that the partials are shards 0..N−1 of one run (names the missing or repeated shards) and orders
// them.
void set_merge(std::vector<Partial> partials);
void set_whole();
// Merge mode: the header the partials share.
const PartialHeader& merged_header();
// Slice mode: the records of the loops run so far. Merge mode: throws if loops of the partials were not used.
std::vector<LoopRecords> take_slice_records();
void check_merge_complete();
// Number of trial loops run (or merged) since the mode was set.
std::size_t trial_loops_run();

// Runs body(i) for the trials of [0, n) that this process computes (all in whole mode), on `threads` threads,
// advancing `progress` by one per trial; `save(w, i)` writes trial i's record and `load(r, i)` reads a record
// into slot i. See the header comment for the three modes.
void trial_loop(std::size_t n, const std::function<void(std::size_t)>& body,
                const std::function<void(Writer&, std::size_t)>& save,
                const std::function<void(Reader&, std::size_t)>& load, unsigned threads = 0,
                Progress* progress = nullptr);

// trial_loop whose records are slot i of each of the given per-trial vectors (std::vector<T>, T savable by
// repro::save).
template <class... Vectors>
void trial_loop(std::size_t n, const std::function<void(std::size_t)>& body, unsigned threads,
                Progress* progress, Vectors&... per_trial) {
  trial_loop(
      n, body, [&](Writer& w, std::size_t i) { (save(w, per_trial[i]), ...); },
      [&](Reader& r, std::size_t i) { (load(r, per_trial[i]), ...); }, threads, progress);
}

}  // namespace keel::repro
