// Sharded trial loops (core/shard.hpp) and the record archive (core/archive.hpp): round trips of every
// savable kind, slices that tile [0, n), and slice-then-merge against the whole run, with the refusals a
// merge must make.
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <unistd.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "repro/archive.hpp"
#include "core/random.hpp"
#include "repro/shard.hpp"
#include "kit/scratch.hpp"
#include "core/fields.hpp"

using namespace keel::repro;
namespace fs = std::filesystem;

namespace {

enum class Kind : std::uint8_t { a, b, c };

struct Plain {  // trivially copyable: saved as bytes
  int n = 0;
  double x = 0;
  Kind kind = Kind::a;
};

struct Rich {  // saved member by member through fields()
  std::vector<int> selected;
  std::string error;
  std::optional<double> bound;
  std::map<std::string, std::vector<double>> columns;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  Eigen::MatrixXd dyn;
  std::array<Plain, 2> plain{};
  std::vector<std::pair<int, std::vector<double>>> nested;
  std::vector<bool> flags;
  KEEL_FIELDS(selected, error, bound, columns, cov, dyn, plain, nested, flags)
  bool operator==(const Rich& o) const {
    return selected == o.selected && error == o.error && bound == o.bound && columns == o.columns &&
           cov == o.cov && dyn.rows() == o.dyn.rows() && dyn.cols() == o.dyn.cols() && dyn == o.dyn &&
           plain[0].n == o.plain[0].n && plain[1].x == o.plain[1].x && plain[1].kind == o.plain[1].kind &&
           nested == o.nested && flags == o.flags;
  }
};

Rich rich_trial(std::size_t i) {
  keel::core::Rng rng = keel::core::Rng::stream(7, i);
  Rich r;
  for (std::size_t k = 0; k < i % 5; ++k) r.selected.push_back(static_cast<int>(rng.uniform(0, 100)));
  r.error = i % 3 == 0 ? "" : fmt::format("trial {} failed", i);
  if (i % 2) r.bound = rng.normal();
  r.columns["tpr"] = {rng.uniform(), rng.uniform()};
  r.cov = Eigen::Matrix3d::Identity() * rng.normal();
  r.dyn = Eigen::MatrixXd::Constant(static_cast<long>(i % 3), 2, rng.normal());
  r.plain[0] = {static_cast<int>(i), rng.normal(), Kind::b};
  r.plain[1] = {-1, rng.uniform(), Kind::c};
  r.nested = {{1, {rng.normal()}}, {2, {}}};
  r.flags = {i % 2 == 0, true, false};
  return r;
}

using keel::testkit::Scratch;

// A study with two trial loops whose second loop's size depends on the first loop's reduction, and a
// reduction whose value depends on every trial (as the experiments' do).
struct StudyOut {
  std::vector<Rich> first;
  std::vector<double> second;
  double reduction = 0;
};

StudyOut run_study(std::size_t n) {
  StudyOut out;
  out.first.resize(n);
  trial_loop(n, [&](std::size_t i) { out.first[i] = rich_trial(i); }, 2, nullptr, out.first);
  out.second.resize(n + 3);
  trial_loop(
      n + 3,
      [&](std::size_t i) {
        keel::core::Rng rng = keel::core::Rng::stream(9, i);
        out.second[i] = rng.normal();
      },
      2, nullptr, out.second);
  for (const auto& r : out.first)
    out.reduction += static_cast<double>(r.selected.size()) + r.bound.value_or(0);
  for (double v : out.second) out.reduction += v;
  return out;
}

PartialHeader header(std::size_t k, std::size_t count) {
  PartialHeader h;
  h.id = "study";
  h.profile = "quick";
  h.git_sha = "abc1234";
  h.config_hash = 42;
  h.seed = 7;
  h.slice = {k, count};
  return h;
}

std::vector<Partial> shard_run(std::size_t n, std::size_t count, const Scratch& s) {
  std::vector<Partial> read;
  for (std::size_t k = 0; k < count; ++k) {
    set_slice({k, count});
    (void)run_study(n);
    Partial p;
    p.header = header(k, count);
    p.loops = take_slice_records();
    const fs::path f = s.root / fmt::format("part-{}.bin", k);
    p.write(f);
    read.push_back(Partial::read(f));
  }
  set_whole();
  return read;
}

}  // namespace

TEST_CASE("archive round trips every savable kind, value for value") {
  for (std::size_t i = 0; i < 12; ++i) {
    const Rich r = rich_trial(i);
    Writer w;
    save(w, r);
    save(w, std::string("tail"));
    Rich back;
    back.plain[0].n = 99;
    std::string tail;
    Reader rd(w.buffer());
    load(rd, back);
    load(rd, tail);
    CHECK(rd.done());
    CHECK(back == r);
    CHECK(tail == "tail");
  }
}

TEST_CASE("archive refuses to read past the end") {
  Writer w;
  save(w, std::vector<double>{1, 2, 3});
  const std::string bytes = w.buffer().substr(0, w.buffer().size() - 4);
  Reader r(bytes);
  std::vector<double> v;
  CHECK_THROWS_WITH_AS(load(r, v), doctest::Contains("read past the end"), std::runtime_error);
}

TEST_CASE("slices tile [0, n) in order, for every n and shard count") {
  for (std::size_t count : {1u, 2u, 3u, 7u, 10u}) {
    for (std::size_t n : {0u, 1u, 2u, 5u, 7u, 100u, 1001u}) {
      std::size_t next = 0, largest = 0, smallest = n;
      for (std::size_t k = 0; k < count; ++k) {
        const Slice s{k, count};
        CHECK(s.begin(n) == next);
        next = s.end(n);
        largest = std::max(largest, s.end(n) - s.begin(n));
        smallest = std::min(smallest, s.end(n) - s.begin(n));
      }
      CHECK(next == n);
      CHECK(largest - smallest <= 1);  // balanced
    }
  }
  CHECK(Slice::parse("3/7").index == 3);
  CHECK(Slice::parse("3/7").count == 7);
  for (const char* bad : {"7/7", "1", "a/3", "-1/3", "1/0", "", "1/3/4", " 1/3"})
    CHECK_THROWS_WITH_AS(Slice::parse(bad), doctest::Contains("--slice expects k/N"), std::invalid_argument);
}

TEST_CASE("sliced and merged trial loops give the whole run's result bit for bit (N = 1, 3, 7)") {
  const std::size_t n = 23;
  set_whole();
  const StudyOut whole = run_study(n);
  CHECK(trial_loops_run() == 2);
  for (std::size_t count : {1u, 3u, 7u}) {
    Scratch s(fmt::format("merge{}", count));
    std::vector<Partial> parts = shard_run(n, count, s);
    std::reverse(parts.begin(), parts.end());  // a merge orders the partials itself
    set_merge(parts);
    const StudyOut merged = run_study(n);
    check_merge_complete();
    set_whole();
    CHECK(merged.first == whole.first);
    CHECK(merged.second == whole.second);
    CHECK(merged.reduction == whole.reduction);  // same values, same serial order: equal, not close
  }
}

TEST_CASE("a shard computes only its slice: the partial holds its own records") {
  Scratch s("slice");
  const auto parts = shard_run(10, 3, s);
  REQUIRE(parts.size() == 3);
  CHECK(parts[1].loops.size() == 2);
  CHECK(parts[1].loops[0].n == 10);
  CHECK(parts[1].loops[0].begin == 3);
  CHECK(parts[1].loops[0].end == 6);
  CHECK(parts[1].loops[1].n == 13);
  CHECK(parts[1].header.slice.index == 1);
  CHECK(parts[1].header.git_sha == "abc1234");
}

TEST_CASE("a merge refuses missing, repeated and foreign shards, and loops that do not match") {
  Scratch s("refuse");
  auto parts = shard_run(10, 3, s);

  auto missing = parts;
  missing.erase(missing.begin() + 1);
  CHECK_THROWS_WITH_AS(set_merge(missing),
                       doctest::Contains("1 of 3 shards missing: 1 (rerun them with --slice k/3)"),
                       std::invalid_argument);
  auto twice = parts;
  twice.push_back(parts[2]);
  CHECK_THROWS_WITH_AS(set_merge(twice), doctest::Contains("shard given twice"), std::invalid_argument);
  auto other = parts;
  other[2].header.config_hash = 43;
  CHECK_THROWS_WITH_AS(set_merge(other), doctest::Contains("configuration hash"), std::invalid_argument);
  other = parts;
  other[0].header.git_sha = "def5678";
  CHECK_THROWS_WITH_AS(set_merge(other), doctest::Contains("commit"), std::invalid_argument);
  CHECK_THROWS_AS(set_merge({}), std::invalid_argument);

  set_merge(parts);  // a study with other loop sizes
  std::vector<double> v(11);
  CHECK_THROWS_WITH_AS(
      trial_loop(
          11, [&](std::size_t i) { v[i] = 1.0; }, 1, nullptr, v),
      doctest::Contains("trial loop 1 covers [0, 3) of 10 trials, but this run's loop has 11"),
      std::runtime_error);
  set_merge(parts);  // a study with fewer loops
  std::vector<Rich> first(10);
  trial_loop(10, [&](std::size_t i) { first[i] = rich_trial(i); }, 1, nullptr, first);
  CHECK_THROWS_WITH_AS(check_merge_complete(),
                       doctest::Contains("the partials hold 2 trial loops but the merge ran 1"),
                       std::runtime_error);
  set_whole();
}

TEST_CASE("partial files: corrupt or foreign files are refused with their name") {
  Scratch s("files");
  const fs::path junk = s.root / "junk.bin";
  std::ofstream(junk) << "not a partial";
  CHECK_THROWS_WITH_AS(Partial::read(junk), doctest::Contains("is not a keel partial file"),
                       std::runtime_error);
  CHECK_THROWS_WITH_AS(Partial::read(s.root / "absent.bin"), doctest::Contains("cannot open partial file"),
                       std::runtime_error);
  auto parts = shard_run(10, 2, s);
  const fs::path f = s.root / "part-0.bin";
  const auto size = fs::file_size(f);
  fs::resize_file(f, size - 3);
  CHECK_THROWS_WITH_AS(Partial::read(f), doctest::Contains("is corrupt"), std::runtime_error);
}

TEST_CASE("a trial loop inside another loop's body runs whole, unsharded") {
  set_slice({1, 3});
  std::vector<int> outer(6), inner_sum(6);
  trial_loop(
      6,
      [&](std::size_t i) {
        std::vector<int> inner(4);
        trial_loop(4, [&](std::size_t j) { inner[j] = static_cast<int>(j + 1); }, 1, nullptr, inner);
        inner_sum[i] = inner[0] + inner[1] + inner[2] + inner[3];
        outer[i] = static_cast<int>(i);
      },
      1, nullptr, outer, inner_sum);
  const auto rec = take_slice_records();
  CHECK(trial_loops_run() == 1);
  REQUIRE(rec.size() == 1);
  CHECK(inner_sum[2] == 10);  // computed by this shard, the inner loop complete
  CHECK(inner_sum[0] == 10);  // another shard's slot: a copy of trial 2
  CHECK(outer[0] == 2);
  set_whole();
}

TEST_CASE("a shard with no trials of a loop (N > n) still gives the other slots a computed stand-in") {
  set_slice({0, 3});  // of n = 2: shard 0 covers [0, 0)
  std::vector<int> v(2, -1);
  std::size_t calls = 0;
  trial_loop(
      2,
      [&](std::size_t i) {
        ++calls;
        v[i] = static_cast<int>(i) + 10;
      },
      1, nullptr, v);
  const auto rec = take_slice_records();
  REQUIRE(rec.size() == 1);
  CHECK(rec[0].begin == 0);
  CHECK(rec[0].end == 0);
  CHECK(rec[0].bytes.empty());  // nothing saved
  CHECK(calls == 1);            // trial 0, computed only as the stand-in
  CHECK(v[0] == 10);
  CHECK(v[1] == 10);
  set_whole();
}
