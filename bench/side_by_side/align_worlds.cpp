// keel's side of the alignment side-by-side (bench/side_by_side/align.sh): times one method (Proposed unless
// told) of thesis ch. 3 (eight sector LPs, shrinking regions) on the worlds of ch3_table3_1_alignment's
// generator (default AlignmentWorldOptions), one thread, the way the study times it: round 0's hulls
// (global_regions) plus align(). Written against headers every keel commit since the tier split has, so the
// same source is built at every revision the script compares.
//
// Usage: keel_align_worlds FIRST COUNT [SEED [METHOD]]   (worlds FIRST … FIRST + COUNT − 1; SEED defaults to
// 20181022, METHOD to proposed: proposed, so_conv_hull, symmetric or affine)
// Output: one tab-separated line per world, the answer at full precision so that revisions can be checked
// against each other:
//   world  time_s  rounds  sector  cost  a11  a12  a21  a22  tx  ty
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "align/align.hpp"
#include "sim/alignment_world.hpp"

namespace align = keel::align;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: keel_align_worlds FIRST COUNT [SEED [METHOD]]\n");
    return 2;
  }
  const long first = std::stol(argv[1]), count = std::stol(argv[2]);
  const std::uint64_t seed = argc > 3 ? std::stoull(argv[3]) : 20181022ULL;
  const align::Method method = argc > 4 ? align::method_from_string(argv[4]) : align::Method::proposed;
  for (long w = first; w < first + count; ++w) {
    const keel::sim::AlignmentWorld world =
        keel::sim::make_alignment_world({}, seed, static_cast<std::uint64_t>(w));
    align::AlignmentProblem p;
    p.ref_x = world.ref_x, p.ref_y = world.ref_y;
    p.query_x = world.query_x, p.query_y = world.query_y;
    p.dissimilarity =
        align::euclidean_dissimilarity(world.ref_features, world.query_features, world.feature_dim);
    align::AlignOptions o;
    o.method = method;
    o.threads = 1;
    const auto t0 = std::chrono::steady_clock::now();
    const align::Regions global = align::global_regions(p, o);
    const align::AlignResult r = align::align(p, o, &global);
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%ld\t%.6f\t%zu\t%d\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\n", w, t,
                r.rounds.size(), r.sector, r.cost, r.raw.a11, r.raw.a12, r.raw.a21, r.raw.a22, r.raw.tx,
                r.raw.ty);
    std::fflush(stdout);
  }
  return 0;
}
