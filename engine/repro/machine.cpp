#include "repro/machine.hpp"

#include <dlfcn.h>
#include <gnu/libc-version.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "repro/experiment.hpp"

namespace keel::repro {
namespace {

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t\n");
  const auto e = s.find_last_not_of(" \t\n");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

// The first loaded shared object whose file name starts with `prefix` (from /proc/self/maps), resolved.
std::string loaded(const std::vector<std::string>& prefixes) {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    const std::string name = std::filesystem::path(path).filename().string();
    for (const auto& p : prefixes) {
      if (name.rfind(p, 0) == 0) {
        std::error_code ec;
        const auto real = std::filesystem::canonical(path, ec);
        return ec ? path : real.string();
      }
    }
  }
  return "";
}

Machine describe() {
  Machine m;
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line, flags;
  while (std::getline(cpuinfo, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = trim(line.substr(0, colon));
    if (key == "model name" && m.cpu_model.empty()) m.cpu_model = trim(line.substr(colon + 1));
    if (key == "flags" && flags.empty()) flags = " " + trim(line.substr(colon + 1)) + " ";
  }
  for (const char* f : {"sse4_2", "avx", "avx2", "fma", "avx512f"}) {
    if (flags.find(std::string(" ") + f + " ") != std::string::npos) {
      m.cpu_features += (m.cpu_features.empty() ? "" : " ") + std::string(f);
    }
  }
  m.glibc = gnu_get_libc_version();
  m.blas = loaded({"libopenblas", "libblas", "libmkl_rt", "libblis"});
  m.lapack = loaded({"liblapack"});
  // Present only when OpenBLAS is loaded; its kernel family follows the CPU unless OPENBLAS_CORETYPE
  // overrides it.
  using CoreName = char* (*)();
  if (auto* f = reinterpret_cast<CoreName>(::dlsym(RTLD_DEFAULT, "openblas_get_corename"))) {
    if (const char* name = f()) m.blas_core = name;
  }
  for (const char* var : {"GLIBC_TUNABLES", "OPENBLAS_CORETYPE"}) {
    if (const char* v = std::getenv(var)) {
      m.overrides += (m.overrides.empty() ? "" : " ") + std::string(var) + "=" + v;
    }
  }
  // The libraries whose arithmetic reaches the results: libc/libm, the BLAS and LAPACK, and the solvers.
  std::istringstream versions(run_capture(
      "dpkg-query -W -f='${binary:Package} ${Version} ${db:Status-Abbrev}\\n' libc6 libopenblas0-pthread "
      "libopenblas0-openmp libopenblas0-serial libblas3 liblapack3 libatlas3-base libceres3 libcholmod3 "
      "coinor-libclp1 libdsdp-5.8gf libsdpa-dev libqhull-r8.0 libcgal-dev libgmp10 libmpfr6 libeigen3-dev "
      "2>/dev/null"));
  while (std::getline(versions, line)) {
    std::istringstream fields(line);
    std::string package, version, status;
    if (fields >> package >> version >> status && status.rfind("ii", 0) == 0) {
      const auto arch = package.find(':');
      m.packages[arch == std::string::npos ? package : package.substr(0, arch)] = version;
    }
  }
  return m;
}

}  // namespace

const Machine& this_machine() {
  static const Machine m = describe();
  return m;
}

}  // namespace keel::repro
