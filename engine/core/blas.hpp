// The BLAS's own threads. OpenBLAS runs its kernels on a pool of threads of its own, as many as the machine
// has cores unless OPENBLAS_NUM_THREADS says otherwise. keel parallelizes over trials (core::parallel_for)
// and runs every experiment on one BLAS thread (repro::experiment_main), for two reasons measured on a 2-core
// machine:
//  * determinism: OpenBLAS splits a product differently on 1 and 2 threads, so a result depended on the core
//  count
//    of the machine it ran on (ch4_exactness's quick profile: gap_order1.max of n4_noise050 moved in the last
//    bits between OPENBLAS_NUM_THREADS=1 and 2);
//  * oversubscription: trial threads that each start BLAS threads wait on each other (two concurrent 2-thread
//  runs
//    of that profile: 26.1 s with OpenBLAS's default, 13.1 s with one BLAS thread; one run alone: 11.6
//    vs 12.5 s).
// OpenBLAS is found at run time (the BLAS is whatever libblas.so.3 Debian's alternatives select); with
// another BLAS these calls do nothing.
#pragma once

namespace keel::core {

// OpenBLAS's thread count, or 0 when the loaded BLAS is not OpenBLAS.
int blas_threads();

// Sets OpenBLAS's thread count (n >= 1); returns the previous count, or 0 when the BLAS is not OpenBLAS. A
// process-wide setting: call it while no BLAS call is in flight.
int set_blas_threads(int n);

// One BLAS thread while any guard lives, in any thread, then the count from before the first of them again.
// The guards are counted process-wide: engine calls that each hold one (merge::robust, pgo::optimize, cov's
// factorization, the certified solver) may overlap on several threads (Python callers release the GIL), and
// the count OpenBLAS had is given back only when the last of them ends, never while another still runs.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;
};

// OpenMP's parallel regions of the libraries keel calls, serialized for the lifetime of the guard (OpenMP's
// max-active-levels set to 0 in the calling thread, then restored). CHOLMOD's supernodal factorization
// (SuiteSparse 5) opens parallel regions with a fixed team of four threads whatever OMP_NUM_THREADS says; on
// a 2-core machine that team spins and switches (about 35,000 context switches a second and 20 % of the
// time in the kernel in a certified solve of sphere2500). The OpenMP runtime is found at run time; without
// one the guard does nothing.
class SerialOpenMp {
 public:
  SerialOpenMp();
  ~SerialOpenMp();
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  int previous_ = -1;  // −1: no OpenMP runtime loaded
};

}  // namespace keel::core
