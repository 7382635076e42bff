#include "repro/shard.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "repro/results.hpp"

namespace keel::repro {

using core::inside_parallel_for;
using core::parallel_for;
using core::Progress;

namespace {

constexpr char kMagic[8] = {'K', 'E', 'E', 'L', 'P', 'R', 'T', '1'};  // layout version 1

struct State {
  ShardMode mode = ShardMode::whole;
  Slice slice;
  std::vector<Partial> partials;     // merge: ordered by shard index
  std::vector<LoopRecords> records;  // slice: the loops run so far
  std::size_t loops = 0;             // trial loops run since the mode was set
  std::mutex mutex;
};

State& state() {
  static State s;
  return s;
}

std::string describe(const Partial& p) {
  return fmt::format("shard {}/{} ({})", p.header.slice.index, p.header.slice.count, p.source);
}

}  // namespace

Slice Slice::parse(const std::string& text) {
  const auto slash = text.find('/');
  auto number = [&](const std::string& s, std::size_t& v) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 9) return false;
    v = static_cast<std::size_t>(std::stoul(s));
    return true;
  };
  Slice s;
  if (slash == std::string::npos || !number(text.substr(0, slash), s.index) ||
      !number(text.substr(slash + 1), s.count) || s.count == 0 || s.index >= s.count)
    throw std::invalid_argument(
        fmt::format("--slice expects k/N with 0 <= k < N (shard k of N, e.g. 0/8), got '{}'", text));
  return s;
}

std::size_t Slice::begin(std::size_t n) const {
  return static_cast<std::size_t>(static_cast<unsigned __int128>(n) * index / count);
}
std::size_t Slice::end(std::size_t n) const {
  return static_cast<std::size_t>(static_cast<unsigned __int128>(n) * (index + 1) / count);
}

void Partial::write(const std::filesystem::path& path) const {
  Writer w;
  w.bytes(kMagic, sizeof kMagic);
  save(w, std::tie(header.id, header.profile, header.git_sha, header.config_hash, header.seed,
                   header.slice.index, header.slice.count));
  save(w, loops.size());
  for (const auto& l : loops) save(w, std::tie(l.n, l.begin, l.end, l.bytes));
  write_file_atomic(path, w.take());
}

Partial Partial::read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot open partial file '{}'", path.string()));
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.size() < sizeof kMagic || !std::equal(kMagic, kMagic + sizeof kMagic, data.begin()))
    throw std::runtime_error(fmt::format(
        "'{}' is not a keel partial file (written by --slice k/N --partial FILE)", path.string()));
  Partial p;
  p.source = path.string();
  try {
    Reader r(std::string_view(data).substr(sizeof kMagic));
    auto h = std::tie(p.header.id, p.header.profile, p.header.git_sha, p.header.config_hash, p.header.seed,
                      p.header.slice.index, p.header.slice.count);
    load(r, h);
    std::size_t count = 0;
    load(r, count);
    if (count > r.remaining()) throw std::runtime_error("implausible loop count");
    p.loops.resize(count);
    for (auto& l : p.loops) {
      auto t = std::tie(l.n, l.begin, l.end, l.bytes);
      load(r, t);
      if (l.begin > l.end || l.end > l.n) throw std::runtime_error("a loop's index range is out of order");
    }
    if (!r.done()) throw std::runtime_error("trailing bytes after the last loop");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("partial file '{}' is corrupt: {}", path.string(), e.what()));
  }
  return p;
}

std::optional<HeaderDifference> header_difference(const PartialHeader& a, const PartialHeader& b) {
  if (a.id != b.id) return HeaderDifference{"experiment", a.id, b.id};
  if (a.profile != b.profile) return HeaderDifference{"profile", a.profile, b.profile};
  if (a.git_sha != b.git_sha) return HeaderDifference{"commit", a.git_sha, b.git_sha};
  if (a.config_hash != b.config_hash)
    return HeaderDifference{"configuration hash", fmt::format("{:016x}", a.config_hash),
                            fmt::format("{:016x}", b.config_hash)};
  if (a.seed != b.seed) return HeaderDifference{"seed", std::to_string(a.seed), std::to_string(b.seed)};
  return std::nullopt;
}

ShardMode shard_mode() { return state().mode; }

void set_whole() {
  State& s = state();
  s.mode = ShardMode::whole;
  s.partials.clear();
  s.records.clear();
  s.loops = 0;
}

void set_slice(const Slice& slice) {
  set_whole();
  state().mode = ShardMode::slice;
  state().slice = slice;
}

void set_merge(std::vector<Partial> partials) {
  if (partials.empty()) throw std::invalid_argument("--merge needs at least one partial file");
  const PartialHeader& h = partials.front().header;
  for (const auto& p : partials) {
    const PartialHeader& o = p.header;
    std::optional<HeaderDifference> d = header_difference(h, o);
    if (!d && o.slice.count != h.slice.count)
      d = HeaderDifference{"shard count", std::to_string(h.slice.count), std::to_string(o.slice.count)};
    if (d)
      throw std::invalid_argument(fmt::format("partials of different runs: {} has {} '{}', {} has '{}'",
                                              describe(partials.front()), d->what, d->a, describe(p), d->b));
  }
  std::sort(partials.begin(), partials.end(),
            [](const Partial& a, const Partial& b) { return a.header.slice.index < b.header.slice.index; });
  std::vector<std::string> missing, repeated;
  std::size_t next = 0;
  for (const auto& p : partials) {
    if (p.header.slice.index < next) {
      repeated.push_back(describe(p));
      continue;
    }
    for (; next < p.header.slice.index; ++next) missing.push_back(std::to_string(next));
    next = p.header.slice.index + 1;
  }
  for (; next < h.slice.count; ++next) missing.push_back(std::to_string(next));
  if (!repeated.empty())
    throw std::invalid_argument(fmt::format("{}: shard given twice: {}", h.id, fmt::join(repeated, ", ")));
  if (!missing.empty())
    throw std::invalid_argument(fmt::format("{}: {} of {} shards missing: {} (rerun them with --slice k/{})",
                                            h.id, missing.size(), h.slice.count, fmt::join(missing, ", "),
                                            h.slice.count));
  set_whole();
  state().mode = ShardMode::merge;
  state().partials = std::move(partials);
}

const PartialHeader& merged_header() {
  if (state().partials.empty()) throw std::logic_error("merged_header: not in merge mode");
  return state().partials.front().header;
}

std::vector<LoopRecords> take_slice_records() { return std::move(state().records); }

std::size_t trial_loops_run() { return state().loops; }

void check_merge_complete() {
  const State& s = state();
  if (s.mode != ShardMode::merge) return;
  const std::size_t have = s.partials.front().loops.size();
  if (s.loops != have)
    throw std::runtime_error(fmt::format(
        "the partials hold {} trial loops but the merge ran {}: they were written by other code or options",
        have, s.loops));
}

void trial_loop(std::size_t n, const std::function<void(std::size_t)>& body,
                const std::function<void(Writer&, std::size_t)>& save_trial,
                const std::function<void(Reader&, std::size_t)>& load_trial, unsigned threads,
                Progress* progress) {
  State& s = state();
  if (s.mode == ShardMode::whole || inside_parallel_for()) {
    if (s.mode == ShardMode::whole && !inside_parallel_for()) ++s.loops;
    parallel_for(n, body, threads, progress);
    return;
  }
  const std::size_t loop = s.loops++;
  if (s.mode == ShardMode::slice) {
    const std::size_t b = s.slice.begin(n), e = s.slice.end(n);
    if (progress) progress->skip(n - (e - b));
    parallel_for(e - b, [&](std::size_t j) { body(b + j); }, threads, progress);
    LoopRecords rec;
    rec.n = n, rec.begin = b, rec.end = e;
    Writer w;
    for (std::size_t i = b; i < e; ++i) save_trial(w, i);
    rec.bytes = w.take();
    s.records.push_back(std::move(rec));
    // The slots of other shards get a copy of one computed trial, so that the reduction that follows
    // (discarded in a slice run) sees ordinary values rather than default-constructed ones. A shard whose
    // range is empty (N > n) computes one trial for this only; it is not saved. A record whose layout
    // depends on its index may not fit another slot: such a slot keeps what could be read.
    if (n > 0) {
      const std::size_t src = e > b ? b : std::min(b, n - 1);
      if (e == b) body(src);
      Writer first;
      save_trial(first, src);
      for (std::size_t i = 0; i < n; ++i) {
        if (i >= b && i < e) continue;
        Reader r(first.buffer());
        try {
          load_trial(r, i);
        } catch (const std::runtime_error&) {
        }
      }
    }
    return;
  }
  // merge
  for (const auto& p : s.partials) {
    if (loop >= p.loops.size())
      throw std::runtime_error(
          fmt::format("{} holds {} trial loops; the merge needs loop {}: written by other "
                      "code or options",
                      describe(p), p.loops.size(), loop + 1));
    const LoopRecords& rec = p.loops[loop];
    if (rec.n != n || rec.begin != p.header.slice.begin(n) || rec.end != p.header.slice.end(n))
      throw std::runtime_error(
          fmt::format("{}: trial loop {} covers [{}, {}) of {} trials, but this run's loop "
                      "has {} trials: written by other code or options",
                      describe(p), loop + 1, rec.begin, rec.end, rec.n, n));
  }
  parallel_for(
      s.partials.size(),
      [&](std::size_t k) {
        const Partial& p = s.partials[k];
        const LoopRecords& rec = p.loops[loop];
        Reader r(rec.bytes);
        for (std::size_t i = rec.begin; i < rec.end; ++i) load_trial(r, i);
        if (!r.done())
          throw std::runtime_error(
              fmt::format("{}: trial loop {} has {} bytes left after its last record: the "
                          "record layout differs from this build's",
                          describe(p), loop + 1, r.remaining()));
      },
      threads);
  if (progress) progress->advance(n);
}

}  // namespace keel::repro
