// The machine a result was computed on, recorded in every result's provenance (docs/GRADING.md "Results on
// another machine"): the same code and seed can round differently in the last bits on another CPU, because
// glibc's libm and the BLAS pick code paths by CPU feature (AVX2, FMA, AVX-512), so a result names what it
// ran on.
#pragma once

#include <map>
#include <string>

namespace keel::repro {

struct Machine {
  std::string cpu_model;  // /proc/cpuinfo "model name"
  std::string
      cpu_features;   // of the features libm and the BLAS dispatch on, those the CPU has: "avx avx2 fma"
  std::string glibc;  // gnu_get_libc_version()
  std::string blas,
      lapack;             // the shared objects the BLAS and LAPACK symbols resolve to (Debian alternatives)
  std::string blas_core;  // OpenBLAS's kernel family (openblas_get_corename), when OpenBLAS is loaded
  std::string overrides;  // GLIBC_TUNABLES and OPENBLAS_CORETYPE of this run, when set
  std::map<std::string, std::string> packages;  // Debian package -> version: libc, BLAS/LAPACK, the solvers
};

// What this process runs on; computed once (reads /proc and asks dpkg-query), then cached.
const Machine& this_machine();

}  // namespace keel::repro
