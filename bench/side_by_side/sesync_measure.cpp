// SE-Sync's measurement driver for bench/side_by_side/certified.sh: one g2o file, SE-Sync's default options
// with one thread, and two timings that count different things, printed as key=value lines.
//
//   sesync_total_s   SE-Sync's own timer (SESyncResult::total_computation_time): initialization, staircase,
//                    rounding; not its problem construction (the data matrices and the two Cholesky
//                    factorizations: translation projection, preconditioner).
//   process_s        from the start of main to the end of the solve: reading the file, the construction and
//   the
//                    timed part; certified.sh times keel's whole process beside it.
//
// keel's own file; it includes only SE-Sync's public headers and is built outside the repository against an
// externally built SE-Sync (shared/notes/peers.md has the command).
//
//   sesync_measure FILE.g2o [max_computation_time_s]
//
// SESYNC_SERIAL_OPENMP=1 makes every OpenMP region inactive (omp_set_max_active_levels(0)), as keel does for
// CHOLMOD's supernodal teams (engine/core/blas.cpp), so that neither tool spins threads on a two-core
// machine.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <omp.h>

#include "SESync/SESync.h"
#include "SESync/SESync_utils.h"

namespace {

const char* status_name(SESync::SESyncStatus s) {
  switch (s) {
    case SESync::GlobalOpt:
      return "GlobalOpt";
    case SESync::SaddlePoint:
      return "SaddlePoint";
    case SESync::EigImprecision:
      return "EigImprecision";
    case SESync::MaxRank:
      return "MaxRank";
    case SESync::ElapsedTime:
      return "ElapsedTime";
  }
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  const auto start = std::chrono::steady_clock::now();
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s FILE.g2o [max_computation_time_s]\n", argv[0]);
    return 2;
  }
  if (const char* s = std::getenv("SESYNC_SERIAL_OPENMP"); s && std::string(s) == "1")
    omp_set_max_active_levels(0);
  size_t num_poses = 0;
  const SESync::measurements_t measurements = SESync::read_g2o_file(argv[1], num_poses);
  if (measurements.empty()) {
    std::fprintf(stderr, "sesync_measure: no measurements read from %s\n", argv[1]);
    return 3;
  }
  const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  SESync::SESyncOpts opts;  // SE-Sync's defaults: simplified formulation, chordal initialization, r0 = 5
  opts.num_threads = 1;
  opts.verbose = false;
  if (argc == 3) opts.max_computation_time = std::strtod(argv[2], nullptr);
  const SESync::SESyncResult r = SESync::SESync(measurements, opts);
  const double process_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("poses=%zu\nmeasurements=%zu\n", num_poses, measurements.size());
  std::printf("F_xhat=%.12g\nSDPval=%.12g\nsuboptimality_bound=%.6g\n", r.Fxhat, r.SDPval,
              r.suboptimality_bound);
  std::printf("final_rank=%ld\nstatus=%s\n", static_cast<long>(r.Yopt.rows()), status_name(r.status));
  std::printf("read_s=%.6f\nsesync_total_s=%.6f\nprocess_s=%.6f\n", read_s, r.total_computation_time,
              process_s);
  return 0;
}
