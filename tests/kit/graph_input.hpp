// Malformed-input helpers of the graph readers' tests (engine/graph/io_test.cpp, io_errors_test.cpp): the
// ParseError message of reading `text` as g2o or iSAM, 2D or 3D, and the small records those tests build.
#pragma once

#include <doctest/doctest.h>

#include <sstream>
#include <string>

#include "graph/g2o.hpp"
#include "graph/isam.hpp"
#include "graph/parse_error.hpp"

namespace keel::testkit {

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const graph::ParseError& e) {
    return e.what();
  }
  return "(no ParseError)";
}

inline std::string g2o2(const std::string& text) {
  return error_of([&] {
    std::istringstream in(text);
    graph::read_g2o_2d(in, "bad.g2o");
  });
}
inline std::string g2o3(const std::string& text) {
  return error_of([&] {
    std::istringstream in(text);
    graph::read_g2o_3d(in, "bad.g2o");
  });
}
inline std::string isam2(const std::string& text) {
  return error_of([&] {
    std::istringstream in(text);
    graph::read_isam_2d(in, "bad.txt");
  });
}
inline std::string isam3(const std::string& text) {
  return error_of([&] {
    std::istringstream in(text);
    graph::read_isam_3d(in, "bad.txt");
  });
}

inline const std::string kV2 = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
inline const std::string kInfo2 = " 1 0 0 1 0 1";
inline const std::string kE01 = "EDGE_SE2 0 1 1 0 0" + kInfo2 + "\n";
inline const std::string kSqrt2 = " 10 0 0 10 0 100";
inline const std::string kEdge3Tail =
    " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1";  // identity (upper triangle, 21)

}  // namespace keel::testkit

// CHECK that `msg` contains `part`, printing both when it does not.
#define CHECK_CONTAINS(msg, part) \
  CHECK_MESSAGE((msg).find(part) != std::string::npos, (msg), " lacks: ", (part))
