#include "core/blas.hpp"

#include <dlfcn.h>

#include <mutex>

namespace keel::core {

namespace {

using SetThreads = void (*)(int);
using GetThreads = int (*)();

// The OpenBLAS entry points, looked up once in the loaded libraries (null when the BLAS is not OpenBLAS).
struct OpenBlas {
  SetThreads set = nullptr;
  GetThreads get = nullptr;
};

const OpenBlas& openblas() {
  static const OpenBlas o{reinterpret_cast<SetThreads>(::dlsym(RTLD_DEFAULT, "openblas_set_num_threads")),
                          reinterpret_cast<GetThreads>(::dlsym(RTLD_DEFAULT, "openblas_get_num_threads"))};
  return o;
}

// OpenMP's max-active-levels entry points (null without an OpenMP runtime in the process).
struct OpenMp {
  SetThreads set_levels = nullptr;
  GetThreads get_levels = nullptr;
};

const OpenMp& openmp() {
  static const OpenMp o{reinterpret_cast<SetThreads>(::dlsym(RTLD_DEFAULT, "omp_set_max_active_levels")),
                        reinterpret_cast<GetThreads>(::dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"))};
  return o;
}

}  // namespace

SerialOpenMp::SerialOpenMp() {
  const OpenMp& o = openmp();
  if (!o.set_levels || !o.get_levels) return;
  previous_ = o.get_levels();
  o.set_levels(0);  // every parallel region inactive: run by the encountering thread alone
}

SerialOpenMp::~SerialOpenMp() {
  if (previous_ >= 0) openmp().set_levels(previous_);
}

namespace {
// The live SingleThreadedBlas guards and the count OpenBLAS had before the first of them.
struct Guards {
  std::mutex mutex;
  int live = 0;
  int previous = 0;
};
Guards& guards() {
  static Guards g;
  return g;
}
}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  Guards& g = guards();
  const std::lock_guard lock(g.mutex);
  if (g.live++ == 0) g.previous = set_blas_threads(1);
}

SingleThreadedBlas::~SingleThreadedBlas() {
  Guards& g = guards();
  const std::lock_guard lock(g.mutex);
  if (--g.live == 0 && g.previous > 1) set_blas_threads(g.previous);
}

int blas_threads() {
  const OpenBlas& o = openblas();
  return o.get ? o.get() : 0;
}

int set_blas_threads(int n) {
  const OpenBlas& o = openblas();
  if (!o.set || !o.get || n < 1) return 0;
  const int previous = o.get();
  if (previous != n) o.set(n);
  return previous;
}

}  // namespace keel::core
