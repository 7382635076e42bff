#include "graph/g2o.hpp"

#include <fmt/format.h>
#include <array>
#include <sstream>
#include <stdexcept>

#include "core/parse.hpp"
#include "graph/build.hpp"
#include "graph/parse_error.hpp"
#include "graph/text_records.hpp"

namespace keel::graph {

using lie::SO3;
using lie::Vec3;

namespace {

constexpr std::array<const char*, 4> kVertexSE2 = {"id", "x", "y", "theta"};
constexpr std::array<const char*, 11> kEdgeSE2 = {"i",   "j",   "dx",  "dy",  "dtheta", "I11",
                                                  "I12", "I13", "I22", "I23", "I33"};
constexpr std::array<const char*, 8> kVertexSE3 = {"id", "x", "y", "z", "qx", "qy", "qz", "qw"};
constexpr std::array<const char*, 30> kEdgeSE3 = {
    "i",   "j",   "x",   "y",   "z",   "qx",  "qy",  "qz",  "qw",  "I11", "I12", "I13", "I14", "I15", "I16",
    "I22", "I23", "I24", "I25", "I26", "I33", "I34", "I35", "I36", "I44", "I45", "I46", "I55", "I56", "I66"};

bool is_3d_tag(std::string_view t) { return t == "VERTEX_SE3:QUAT" || t == "EDGE_SE3:QUAT" || t == "EDGE3"; }
bool is_2d_tag(std::string_view t) {
  return t == "VERTEX_SE2" || t == "EDGE_SE2" || t == "ODOMETRY" || t == "EDGE2" || t == "Constraint2" ||
         t == "LANDMARK";
}

// g2o's "FIX id ..." holds the listed vertices constant. keel holds exactly one pose fixed, the gauge: "FIX
// k" makes pose k the graph's gauge_pose (every solve keeps it at its input value; marginals are reported
// with it fixed). FIX lines may repeat that id; a second, different id is refused (several fixed poses would
// be another problem). Vertex ids are keel's pose indices (assemble() takes them contiguous from 0, as for
// the edges), so the id must name a vertex of the graph: checked by check_fix() once every vertex is read.
struct FixRecord {
  int id = -1;  // -1: no FIX line
  int line = 0;
  std::string field;  // "FIX field k"
  std::string token;  // the id as written
};

void parse_fix(const RecordScanner& sc, FixRecord& fix) {
  if (sc.size() == 0) sc.fail("FIX: expected the id of the fixed vertex (e.g. 'FIX 0')");
  for (std::size_t k = 1; k <= sc.size(); ++k) {
    const int id = sc.id(k);
    if (fix.id < 0) {
      fix = {id, sc.line(), sc.describe_field(k), std::string(sc.field(k))};
    } else if (id != fix.id) {
      sc.fail_field(k,
                    fmt::format("{}: keel holds one pose fixed (the gauge), and {} on line {} already fixes "
                                "pose {}; this one names pose {} (give one FIX id)",
                                core::quote_token(sc.field(k)), fix.field, fix.line, fix.id, id));
    }
  }
}

template <class Graph>
void check_fix(Graph& g, const FixRecord& fix) {
  if (fix.id < 0) return;
  if (static_cast<std::size_t>(fix.id) >= g.poses.size()) {
    fail_at(g.source, fix.line,
            fmt::format("{}: {}: no pose {} in the graph (its {} poses have ids 0 to {})", fix.field,
                        core::quote_token(fix.token), fix.id, g.poses.size(),
                        static_cast<long long>(g.poses.size()) - 1));
  }
  g.gauge_pose = fix.id;
}

void check_edge_ids(const RecordScanner& sc, int i, int j) {
  if (i == j) sc.fail_field(2, fmt::format("the edge connects pose {} to itself", i));
}

// Under InformationCheck::diagonal_blocks: the problem of the translation or rotation block, or empty (then
// `indefinite` says whether the whole matrix fails).
template <int N>
std::string block_problem(const Eigen::Matrix<double, N, N>& W, int nt, bool& indefinite) {
  const int nr = N - nt;
  std::string why;
  if (nt == 2) {
    why = information_problem(Mat2(W.template topLeftCorner<2, 2>()));
  } else {
    why = information_problem(Mat3(W.template topLeftCorner<3, 3>()));
  }
  if (!why.empty()) return "translation block " + why;
  if (nr == 1) {
    if (!(std::isfinite(W(N - 1, N - 1)) && W(N - 1, N - 1) > 0.0))
      return fmt::format("rotation entry {:.6g} is not positive", W(N - 1, N - 1));
  } else {
    why = information_problem(Mat3(W.template bottomRightCorner<3, 3>()));
    if (!why.empty()) return "rotation block " + why;
  }
  indefinite = !information_problem(W).empty();
  return {};
}

Edge2 parse_edge_se2(RecordScanner& sc, InformationCheck check, int& indefinite) {
  sc.expect(kEdgeSE2);
  Edge2 e;
  e.i = sc.id(1);
  e.j = sc.id(2);
  double v[9];
  sc.numbers(3, 11, v);
  e.measurement = SE2(v[0], v[1], v[2]);
  e.information = detail::symmetric_from_upper<3>(v + 3);
  if (check == InformationCheck::positive_definite) {
    if (auto why = information_problem(e.information); !why.empty()) {
      sc.fail_fields(6, 11, fmt::format("the information matrix {}", why));
    }
  } else {
    bool bad = false;
    if (auto why = block_problem<3>(e.information, 2, bad); !why.empty())
      sc.fail_fields(6, 11, fmt::format("the information matrix's {}", why));
    indefinite += bad ? 1 : 0;
  }
  e.line = sc.line();
  return e;
}

Edge3 parse_edge_se3(RecordScanner& sc, InformationCheck check, int& indefinite) {
  sc.expect(kEdgeSE3);
  Edge3 e;
  e.i = sc.id(1);
  e.j = sc.id(2);
  double v[28];
  sc.numbers(3, 30, v);
  Mat3 R;
  std::string why;
  if (!rotation_from_quaternion(v + 3, R, why)) sc.fail_fields(6, 9, why);
  e.measurement = SE3(SO3::from_matrix_unchecked(R), Vec3(v[0], v[1], v[2]));
  const Mat6 w_g2o = detail::symmetric_from_upper<6>(v + 7);
  bool bad = false;
  if (check == InformationCheck::positive_definite) {
    if (auto p = information_problem(w_g2o); !p.empty())
      sc.fail_fields(10, 30, fmt::format("the information matrix {}", p));
  } else if (auto p = block_problem<6>(w_g2o, 3, bad); !p.empty()) {
    sc.fail_fields(10, 30, fmt::format("the information matrix's {}", p));
  }
  // (t, q_vec) -> (t, φ): q_vec ≈ φ/2, J = diag(I, ½I), Ω = Jᵀ Ω_g2o J.
  Mat6 W = w_g2o;
  W.block<3, 3>(0, 3) *= 0.5;
  W.block<3, 3>(3, 0) *= 0.5;
  W.block<3, 3>(3, 3) *= 0.25;
  if (check == InformationCheck::positive_definite) {
    if (auto p = information_problem(W); !p.empty()) {
      sc.fail_fields(10, 30, fmt::format("the information matrix in (t, φ) {}", p));
    }
  } else {
    indefinite += bad ? 1 : 0;
  }
  e.information = W;
  e.line = sc.line();
  return e;
}

PoseGraph2D parse_g2o_2d(std::string_view text, const std::string& name, InformationCheck check) {
  RecordScanner sc(text, name);
  PoseGraph2D g;
  g.source = name;
  std::vector<detail::Vertex2> vertices;
  FixRecord fix;
  while (sc.next()) {
    const std::string_view tag = sc.tag();
    if (tag == "VERTEX_SE2") {
      sc.expect(kVertexSE2);
      const int id = sc.id(1);
      double v[3];
      sc.numbers(2, 4, v);
      vertices.push_back({id, SE2(v[0], v[1], v[2]), sc.line()});
    } else if (tag == "EDGE_SE2") {
      const Edge2 e = parse_edge_se2(sc, check, g.indefinite_information);
      check_edge_ids(sc, e.i, e.j);
      g.edges.push_back(e);
    } else if (tag == "FIX") {
      parse_fix(sc, fix);
    } else if (is_3d_tag(tag)) {
      sc.fail(fmt::format(
          "{} is a 3D record, but this is the 2D g2o reader (use read_g2o_3d or read_pose_graph_3d)",
          core::quote_token(tag)));
    } else {
      sc.fail(fmt::format("unknown tag {} (the 2D g2o reader knows VERTEX_SE2, EDGE_SE2 and FIX)",
                          core::quote_token(tag)));
    }
  }
  detail::assemble(g, vertices, "VERTEX_SE2", "EDGE_SE2");
  check_fix(g, fix);
  return g;
}

PoseGraph3D parse_g2o_3d(std::string_view text, const std::string& name, InformationCheck check) {
  RecordScanner sc(text, name);
  PoseGraph3D g;
  g.source = name;
  std::vector<detail::Vertex3> vertices;
  FixRecord fix;
  std::string why;
  while (sc.next()) {
    const std::string_view tag = sc.tag();
    if (tag == "VERTEX_SE3:QUAT") {
      sc.expect(kVertexSE3);
      const int id = sc.id(1);
      double v[7];
      sc.numbers(2, 8, v);
      Mat3 R;
      if (!rotation_from_quaternion(v + 3, R, why)) sc.fail_fields(5, 8, why);
      vertices.push_back({id, SE3(SO3::from_matrix_unchecked(R), Vec3(v[0], v[1], v[2])), sc.line()});
    } else if (tag == "EDGE_SE3:QUAT") {
      const Edge3 e = parse_edge_se3(sc, check, g.indefinite_information);
      check_edge_ids(sc, e.i, e.j);
      g.edges.push_back(e);
    } else if (tag == "FIX") {
      parse_fix(sc, fix);
    } else if (is_2d_tag(tag)) {
      sc.fail(fmt::format(
          "{} is a 2D record, but this is the 3D g2o reader (use read_g2o_2d or read_pose_graph_2d)",
          core::quote_token(tag)));
    } else {
      sc.fail(fmt::format("unknown tag {} (the 3D g2o reader knows VERTEX_SE3:QUAT, EDGE_SE3:QUAT and FIX)",
                          core::quote_token(tag)));
    }
  }
  detail::assemble(g, vertices, "VERTEX_SE3:QUAT", "EDGE_SE3:QUAT");
  check_fix(g, fix);
  return g;
}

void put(std::string& s, double v) {
  s += ' ';
  s += fmt17(v);
}

void put_edge(std::string& s, const Edge2& e) {
  s += fmt::format("EDGE_SE2 {} {}", e.i, e.j);
  put(s, e.measurement.translation().x());
  put(s, e.measurement.translation().y());
  put(s, e.measurement.angle());
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) put(s, e.information(r, c));
  s += '\n';
}

void put_edge(std::string& s, const Edge3& e) {
  double q[4];
  s += fmt::format("EDGE_SE3:QUAT {} {}", e.i, e.j);
  for (int a = 0; a < 3; ++a) put(s, e.measurement.translation()(a));
  quaternion_from_rotation(e.measurement.rotation(), q);
  for (double x : q) put(s, x);
  // (t, φ) -> (t, q_vec): Ω_g2o = K Ω K, K = diag(I, 2I).
  Mat6 W = e.information;
  W.block<3, 3>(0, 3) *= 2.0;
  W.block<3, 3>(3, 0) *= 2.0;
  W.block<3, 3>(3, 3) *= 4.0;
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c) put(s, W(r, c));
  s += '\n';
}

// Edge-only files (read_g2o_edges_*): every record is an edge of the one tag; ids are not checked against
// each other (the two ids live in different id spaces).
template <class Edge>
std::vector<Edge> parse_g2o_edges(std::string_view text, const std::string& name, std::string_view edge_tag,
                                  Edge (*parse)(RecordScanner&, InformationCheck, int&)) {
  RecordScanner sc(text, name);
  std::vector<Edge> edges;
  while (sc.next()) {
    const std::string_view tag = sc.tag();
    if (tag != edge_tag) {
      sc.fail(
          fmt::format("unexpected tag {}: an edge file holds {} records only (no vertices, no other edges)",
                      core::quote_token(tag), edge_tag));
    }
    int unused = 0;
    edges.push_back(parse(sc, InformationCheck::positive_definite, unused));
  }
  if (edges.empty()) fail_at(name, 0, fmt::format("no {} record (an empty edge file)", edge_tag));
  return edges;
}

std::string g2o_text(const PoseGraph2D& g, const G2oWriteOptions& o) {
  if (!g.landmarks.empty() || !g.landmark_measurements.empty()) {
    throw std::invalid_argument(
        "write_g2o: the graph has landmarks, which the g2o writer does not support "
        "(use write_isam)");
  }
  detail::check_indices(g, "write_g2o");
  std::string s;
  s.reserve(64 * (g.poses.size() + 2 * g.edges.size()));
  if (o.write_vertices) {
    for (std::size_t k = 0; k < g.poses.size(); ++k) {
      const SE2& T = g.poses[k];
      s += fmt::format("VERTEX_SE2 {}", k);
      put(s, T.translation().x());
      put(s, T.translation().y());
      put(s, T.angle());
      s += '\n';
    }
  }
  if (g.gauge_pose != 0) s += fmt::format("FIX {}\n", g.gauge_pose);
  for (const auto& e : g.edges) put_edge(s, e);
  return s;
}

std::string g2o_text(const PoseGraph3D& g, const G2oWriteOptions& o) {
  detail::check_indices(g, "write_g2o");
  std::string s;
  s.reserve(128 * (g.poses.size() + 3 * g.edges.size()));
  double q[4];
  if (o.write_vertices) {
    for (std::size_t k = 0; k < g.poses.size(); ++k) {
      const SE3& T = g.poses[k];
      s += fmt::format("VERTEX_SE3:QUAT {}", k);
      for (int a = 0; a < 3; ++a) put(s, T.translation()(a));
      quaternion_from_rotation(T.rotation(), q);
      for (double x : q) put(s, x);
      s += '\n';
    }
  }
  if (g.gauge_pose != 0) s += fmt::format("FIX {}\n", g.gauge_pose);
  for (const auto& e : g.edges) put_edge(s, e);
  return s;
}

}  // namespace

PoseGraph2D read_g2o_2d(const std::filesystem::path& file, InformationCheck information) {
  return parse_g2o_2d(read_file_text(file), file.string(), information);
}
PoseGraph2D read_g2o_2d(std::istream& in, const std::string& name, InformationCheck information) {
  return parse_g2o_2d(read_stream_text(in, name), name, information);
}
PoseGraph3D read_g2o_3d(const std::filesystem::path& file, InformationCheck information) {
  return parse_g2o_3d(read_file_text(file), file.string(), information);
}
PoseGraph3D read_g2o_3d(std::istream& in, const std::string& name, InformationCheck information) {
  return parse_g2o_3d(read_stream_text(in, name), name, information);
}

std::vector<Edge2> read_g2o_edges_2d(const std::filesystem::path& file) {
  return parse_g2o_edges<Edge2>(read_file_text(file), file.string(), "EDGE_SE2", parse_edge_se2);
}
std::vector<Edge2> read_g2o_edges_2d(std::istream& in, const std::string& name) {
  return parse_g2o_edges<Edge2>(read_stream_text(in, name), name, "EDGE_SE2", parse_edge_se2);
}
std::vector<Edge3> read_g2o_edges_3d(const std::filesystem::path& file) {
  return parse_g2o_edges<Edge3>(read_file_text(file), file.string(), "EDGE_SE3:QUAT", parse_edge_se3);
}
std::vector<Edge3> read_g2o_edges_3d(std::istream& in, const std::string& name) {
  return parse_g2o_edges<Edge3>(read_stream_text(in, name), name, "EDGE_SE3:QUAT", parse_edge_se3);
}
void write_g2o_edges(const std::vector<Edge2>& edges, const std::filesystem::path& file) {
  std::string s;
  for (const auto& e : edges) put_edge(s, e);
  write_file_atomically(file, s);
}
void write_g2o_edges(const std::vector<Edge3>& edges, const std::filesystem::path& file) {
  std::string s;
  for (const auto& e : edges) put_edge(s, e);
  write_file_atomically(file, s);
}

void write_g2o(const PoseGraph2D& graph, std::ostream& out, const G2oWriteOptions& options) {
  out << g2o_text(graph, options);
}
void write_g2o(const PoseGraph3D& graph, std::ostream& out, const G2oWriteOptions& options) {
  out << g2o_text(graph, options);
}
void write_g2o(const PoseGraph2D& graph, const std::filesystem::path& file, const G2oWriteOptions& options) {
  write_file_atomically(file, g2o_text(graph, options));
}
void write_g2o(const PoseGraph3D& graph, const std::filesystem::path& file, const G2oWriteOptions& options) {
  write_file_atomically(file, g2o_text(graph, options));
}

}  // namespace keel::graph
