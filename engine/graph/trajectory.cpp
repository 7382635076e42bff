#include "graph/trajectory.hpp"

#include <fmt/format.h>
#include <array>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "graph/build.hpp"
#include "graph/parse_error.hpp"
#include "graph/text_records.hpp"

namespace keel::graph {

using lie::SO3;
using lie::Vec3;

namespace {

constexpr std::array<const char*, 3> kPose2 = {"x", "y", "theta"};
constexpr std::array<const char*, 4> kIdPose2 = {"id", "x", "y", "theta"};
constexpr std::array<const char*, 3> kIdLandmark2 = {"id", "x", "y"};
constexpr std::array<const char*, 8> kIdPose3 = {"id", "x", "y", "z", "qx", "qy", "qz", "qw"};
constexpr std::array<const char*, 8> kTum = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};

// Files whose records are `id v1 .. vn` (untagged): field 1 is the id, fields 2..n+1 the values.
template <class T, std::size_t N, class Make>
std::vector<T> read_id_records(std::string_view text, const std::string& name, const char* kind,
                               const std::array<const char*, N + 1>& names, Make make) {
  RecordScanner sc(text, name, kind);
  struct Rec {
    int id;
    T value;
    int line;
  };
  std::vector<Rec> recs;
  while (sc.next()) {
    sc.expect(names);
    const int id = sc.id(1);
    std::array<double, N> v{};
    sc.numbers(2, N + 1, v.data());
    T value;
    make(sc, v, value);
    recs.push_back({id, value, sc.line()});
  }
  if (recs.empty()) fail_at(name, 0, fmt::format("no {} records (empty file?)", kind));
  const std::size_t n = recs.size();
  std::unordered_map<int, int> seen;
  for (const auto& r : recs) {
    auto [it, fresh] = seen.emplace(r.id, r.line);
    if (!fresh) {
      fail_at(name, r.line,
              fmt::format("{} field 1 (id): duplicate id {} (first on line {})", kind, r.id, it->second));
    }
  }
  for (const auto& r : recs) {
    if (static_cast<std::size_t>(r.id) >= n) {
      std::size_t missing = 0;
      while (seen.count(static_cast<int>(missing))) ++missing;
      fail_at(name, r.line,
              fmt::format("{} field 1 (id): ids must be contiguous from 0, but id {} is missing ({} records, "
                          "this one has id {})",
                          kind, missing, n, r.id));
    }
  }
  std::vector<T> out(n);
  for (const auto& r : recs) out[static_cast<std::size_t>(r.id)] = r.value;
  return out;
}

void make_pose2(const RecordScanner&, const std::array<double, 3>& v, SE2& T) { T = SE2(v[0], v[1], v[2]); }
void make_landmark2(const RecordScanner&, const std::array<double, 2>& v, Vec2& p) { p = Vec2(v[0], v[1]); }
void make_pose3(const RecordScanner& sc, const std::array<double, 7>& v, SE3& T) {
  Mat3 R;
  std::string why;
  if (!rotation_from_quaternion(v.data() + 3, R, why)) sc.fail_fields(5, 8, why);
  T = SE3(SO3::from_matrix_unchecked(R), Vec3(v[0], v[1], v[2]));
}

std::vector<SE2> parse_pose_list_2d(std::string_view text, const std::string& name) {
  RecordScanner sc(text, name, "pose");
  std::vector<SE2> out;
  while (sc.next()) {
    sc.expect(kPose2);
    double v[3];
    sc.numbers(1, 3, v);
    out.emplace_back(v[0], v[1], v[2]);
  }
  if (out.empty()) fail_at(name, 0, "no pose records (empty file?)");
  return out;
}

std::vector<TumPose> parse_tum(std::string_view text, const std::string& name) {
  RecordScanner sc(text, name, "TUM");
  std::vector<TumPose> out;
  while (sc.next()) {
    sc.expect(kTum);
    double v[8];
    sc.numbers(1, 8, v);
    Mat3 R;
    std::string why;
    if (!rotation_from_quaternion(v + 4, R, why)) sc.fail_fields(5, 8, why);
    out.push_back({v[0], SE3(SO3::from_matrix_unchecked(R), Vec3(v[1], v[2], v[3]))});
  }
  if (out.empty()) fail_at(name, 0, "no TUM records (empty file?)");
  return out;
}

void put(std::string& s, double v) {
  s += ' ';
  s += fmt17(v);
}

std::string poses_2d_text(const std::vector<SE2>& poses) {
  std::string s;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    s += fmt::format("{}", k);
    put(s, poses[k].translation().x());
    put(s, poses[k].translation().y());
    put(s, poses[k].angle());
    s += '\n';
  }
  return s;
}

std::string landmarks_2d_text(const std::vector<Vec2>& landmarks) {
  std::string s;
  for (std::size_t k = 0; k < landmarks.size(); ++k) {
    s += fmt::format("{}", k);
    put(s, landmarks[k].x());
    put(s, landmarks[k].y());
    s += '\n';
  }
  return s;
}

std::string poses_3d_text(const std::vector<SE3>& poses) {
  std::string s;
  double q[4];
  for (std::size_t k = 0; k < poses.size(); ++k) {
    s += fmt::format("{}", k);
    for (int a = 0; a < 3; ++a) put(s, poses[k].translation()(a));
    quaternion_from_rotation(poses[k].rotation(), q);
    for (double x : q) put(s, x);
    s += '\n';
  }
  return s;
}

// TUM lines are `timestamp tx ty tz qx qy qz qw`; with the pose index as timestamp that is exactly the 3D
// pose list.
std::string tum_text(const std::vector<SE3>& poses) { return poses_3d_text(poses); }

std::string tum_text(const std::vector<SE2>& poses) {
  std::string s;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const double half = 0.5 * poses[k].angle();  // angle in (−π, π] → w = cos(θ/2) ≥ 0
    s += fmt::format("{}", k);
    put(s, poses[k].translation().x());
    put(s, poses[k].translation().y());
    s += " 0 0 0";
    put(s, std::sin(half));
    put(s, std::cos(half));
    s += '\n';
  }
  return s;
}

}  // namespace

std::vector<SE2> read_poses_2d(const std::filesystem::path& file) {
  return read_id_records<SE2, 3>(read_file_text(file), file.string(), "pose", kIdPose2, make_pose2);
}
std::vector<SE2> read_poses_2d(std::istream& in, const std::string& name) {
  return read_id_records<SE2, 3>(read_stream_text(in, name), name, "pose", kIdPose2, make_pose2);
}
std::vector<Vec2> read_landmarks_2d(const std::filesystem::path& file) {
  return read_id_records<Vec2, 2>(read_file_text(file), file.string(), "landmark", kIdLandmark2,
                                  make_landmark2);
}
std::vector<Vec2> read_landmarks_2d(std::istream& in, const std::string& name) {
  return read_id_records<Vec2, 2>(read_stream_text(in, name), name, "landmark", kIdLandmark2, make_landmark2);
}
std::vector<SE3> read_poses_3d(const std::filesystem::path& file) {
  return read_id_records<SE3, 7>(read_file_text(file), file.string(), "pose", kIdPose3, make_pose3);
}
std::vector<SE3> read_poses_3d(std::istream& in, const std::string& name) {
  return read_id_records<SE3, 7>(read_stream_text(in, name), name, "pose", kIdPose3, make_pose3);
}
std::vector<SE2> read_pose_list_2d(const std::filesystem::path& file) {
  return parse_pose_list_2d(read_file_text(file), file.string());
}
std::vector<SE2> read_pose_list_2d(std::istream& in, const std::string& name) {
  return parse_pose_list_2d(read_stream_text(in, name), name);
}
std::vector<TumPose> read_tum(const std::filesystem::path& file) {
  return parse_tum(read_file_text(file), file.string());
}
std::vector<TumPose> read_tum(std::istream& in, const std::string& name) {
  return parse_tum(read_stream_text(in, name), name);
}

void write_poses_2d(const std::vector<SE2>& poses, std::ostream& out) { out << poses_2d_text(poses); }
void write_poses_2d(const std::vector<SE2>& poses, const std::filesystem::path& file) {
  write_file_atomically(file, poses_2d_text(poses));
}
void write_landmarks_2d(const std::vector<Vec2>& landmarks, std::ostream& out) {
  out << landmarks_2d_text(landmarks);
}
void write_landmarks_2d(const std::vector<Vec2>& landmarks, const std::filesystem::path& file) {
  write_file_atomically(file, landmarks_2d_text(landmarks));
}
void write_poses_3d(const std::vector<SE3>& poses, std::ostream& out) { out << poses_3d_text(poses); }
void write_poses_3d(const std::vector<SE3>& poses, const std::filesystem::path& file) {
  write_file_atomically(file, poses_3d_text(poses));
}
void write_tum(const std::vector<SE2>& poses, std::ostream& out) { out << tum_text(poses); }
void write_tum(const std::vector<SE3>& poses, std::ostream& out) { out << tum_text(poses); }
void write_tum(const std::vector<SE2>& poses, const std::filesystem::path& file) {
  write_file_atomically(file, tum_text(poses));
}
void write_tum(const std::vector<SE3>& poses, const std::filesystem::path& file) {
  write_file_atomically(file, tum_text(poses));
}

}  // namespace keel::graph
