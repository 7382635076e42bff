// libFuzzer target: the keel grid reader (sim::parse_terrain_grid, what `keel align-world --terrain` reads)
// on arbitrary bytes. It may only succeed or throw keel::graph::ParseError; a grid it accepts must be what
// the file format promises: at least 3 × 3 nodes, x and y strictly increasing, rows × cols finite values.
#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "graph/parse_error.hpp"
#include "sim/terrain.hpp"

namespace {

[[noreturn]] void fail(const std::string& detail) {
  fmt::print(stderr, "fuzz_terrain: {}\n", detail);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto g =
        keel::sim::parse_terrain_grid(std::string(reinterpret_cast<const char*>(data), size), "f.grid");
    if (g.x.size() < 3 || g.y.size() < 3) fail("fewer than 3 × 3 nodes");
    if (g.z.size() != g.x.size() * g.y.size()) fail("values are not rows × cols");
    for (std::size_t k = 1; k < g.x.size(); ++k)
      if (!(g.x[k] > g.x[k - 1])) fail("x not strictly increasing");
    for (std::size_t k = 1; k < g.y.size(); ++k)
      if (!(g.y[k] > g.y[k - 1])) fail("y not strictly increasing");
    for (double v : g.z)
      if (!std::isfinite(v)) fail("a non-finite value");
  } catch (const keel::graph::ParseError&) {
  } catch (const std::exception& e) {
    fail(fmt::format("unexpected exception: {}", e.what()));
  }
  return 0;
}
