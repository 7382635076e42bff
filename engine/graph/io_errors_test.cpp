// Malformed input to the graph readers: one ParseError per rule, each checked for file, line and field in its
// message (g2o 2D and 3D, iSAM, pose lists and TUM files). The round trips are io_test.cpp's.
#include <doctest/doctest.h>

#include <string>

#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/isam.hpp"
#include "graph/parse_error.hpp"
#include "graph/trajectory.hpp"
#include "kit/graph_input.hpp"
#include "kit/test_kit.hpp"

using namespace keel::graph;
using keel::testkit::error_of;
using keel::testkit::g2o2;
using keel::testkit::g2o3;
using keel::testkit::isam2;
using keel::testkit::isam3;
using keel::testkit::kE01;
using keel::testkit::kEdge3Tail;
using keel::testkit::kInfo2;
using keel::testkit::kSqrt2;
using keel::testkit::kV2;

TEST_CASE("malformed g2o 2D input: every rule gives a ParseError with file, line and field") {
  std::string m;
  m = g2o2(kV2 + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0\n");
  CHECK_CONTAINS(m,
                 "bad.g2o:3: EDGE_SE2: expected 11 fields after the tag, found 10 (truncated line?): field "
                 "11 (I33) is missing");
  m = g2o2(kV2 + "EDGE_SE2 0 1 1 0 abc" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE2 field 5 (dtheta): 'abc' is not a number");
  m = g2o2(kV2 + "EDGE_SE2 0 1 nan 0 0" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE2 field 3 (dx): 'nan' is not a finite number");
  m = g2o2(kV2 + "EDGE_SE2 0 1 1 -inf 0" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE2 field 4 (dy): '-inf' is not a finite number");
  m = g2o2(kV2 + "EDGE_SE2 0 1 1 1e999 0" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE2 field 4 (dy): '1e999' is out of the range of a double");
  m = g2o2(kV2 + "EDGE_SE2 0 1 1 0 0" + kInfo2 + " 7\n");
  CHECK_CONTAINS(
      m, "bad.g2o:3: EDGE_SE2: expected 11 fields after the tag, found 12: field 12 '7' is one too many");
  m = g2o2(kV2 + "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n");
  CHECK_CONTAINS(
      m, "bad.g2o:3: EDGE_SE2 fields 6-11 (I11..I33): the information matrix is not positive definite");
  m = g2o2(kV2 + "EDGE_SE2 0 1 1 0 0 1 2 0 1 0 1\n");  // positive diagonal, indefinite
  CHECK_CONTAINS(
      m, "bad.g2o:3: EDGE_SE2 fields 6-11 (I11..I33): the information matrix is not positive definite");
  m = g2o2(kV2 + kE01 + "FIX 2\n");
  CHECK_CONTAINS(m, "bad.g2o:4: FIX field 1: '2': no pose 2 in the graph (its 2 poses have ids 0 to 1)");
  m = g2o2(kV2 + kE01 + "FIX 1\nFIX 0\n");
  CHECK_CONTAINS(
      m,
      "bad.g2o:5: FIX field 1: '0': keel holds one pose fixed (the gauge), and FIX field 1 on line 4 "
      "already fixes pose 1; this one names pose 0");
  m = g2o2(kV2 + kE01 + "FIX 1 1 0\n");
  CHECK_CONTAINS(
      m,
      "bad.g2o:4: FIX field 3: '0': keel holds one pose fixed (the gauge), and FIX field 1 on line 4 "
      "already fixes pose 1; this one names pose 0");
  m = g2o2(kV2 + kE01 + "FIX\n");
  CHECK_CONTAINS(m, "bad.g2o:4: FIX: expected the id of the fixed vertex");
  m = g2o2(kV2 + "EDGE_SE2 0 5 1 0 0" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE2 field 2 (j): pose 5 has no VERTEX_SE2 line");
  m = g2o2("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 0 1 0 0\n" + kE01);
  CHECK_CONTAINS(m, "bad.g2o:2: VERTEX_SE2 field 1 (id): duplicate vertex id 0 (first defined on line 1)");
  m = g2o2("VERTEX_SE2 -1 0 0 0\n");
  CHECK_CONTAINS(m, "bad.g2o:1: VERTEX_SE2 field 1 (id): '-1' is negative");
  m = g2o2(kV2 + "EDGE_SE2 0 -1 1 0 0" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE2 field 2 (j): '-1' is negative");
  m = g2o2("VERTEX_SE2 1.5 0 0 0\n");
  CHECK_CONTAINS(
      m, "bad.g2o:1: VERTEX_SE2 field 1 (id): '1.5' is not an integer id (expected a decimal integer");
  m = g2o2("VERTEX_SE2 99999999999999999999 0 0 0\n");
  CHECK_CONTAINS(
      m, "bad.g2o:1: VERTEX_SE2 field 1 (id): '99999999999999999999' is too large: expected an integer id");
  m = g2o2("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 2 1 0 0\nEDGE_SE2 0 2 1 0 0" + kInfo2 + "\n");
  CHECK_CONTAINS(
      m, "bad.g2o:2: VERTEX_SE2 field 1 (id): vertex ids must be contiguous from 0, but id 1 is missing");
  m = g2o2(kV2 + "VERTEX_SE2 2 0 0 0\n" + kE01);
  CHECK_CONTAINS(m, "bad.g2o:3: VERTEX_SE2 field 1 (id): vertex 2 is used by no edge");
  m = g2o2(kV2 + "EDGE_SE2 1 1 1 0 0" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE2 field 2 (j): the edge connects pose 1 to itself");
  m = g2o2(kV2 + "EDGE_SE3:QUAT 0 1 0 0 0 0 0 0 1" + kEdge3Tail + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: 'EDGE_SE3:QUAT' is a 3D record, but this is the 2D g2o reader");
  // No vertices: the odometry chain must be complete.
  m = g2o2(kE01 + "EDGE_SE2 2 3 1 0 0" + kInfo2 + "\n");
  CHECK_CONTAINS(m, "bad.g2o: no odometry edge (1, 2)");
  CHECK_CONTAINS(m, "pose 2 first appears on line 2 (EDGE_SE2 field 1 (i))");
  m = g2o2("# nothing here\n\n");
  CHECK_CONTAINS(m, "bad.g2o: no VERTEX_SE2 or edge records (empty file?)");
  m = g2o2(std::string("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 \x01\x7f\n"));
  CHECK_CONTAINS(m, "bad.g2o:2: VERTEX_SE2 field 4 (theta): '\\x01\\x7f' is not a number");
}

TEST_CASE("malformed g2o 3D input") {
  const std::string v = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n";
  std::string m;
  m = g2o3("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 2\n");
  CHECK_CONTAINS(m, "bad.g2o:1: VERTEX_SE3:QUAT fields 5-8 (qx..qw): quaternion norm 2 is not 1");
  m = g2o3(v + "EDGE_SE3:QUAT 0 1 0 0 0 0 0 0 0" + kEdge3Tail + "\n");
  CHECK_CONTAINS(m, "bad.g2o:3: EDGE_SE3:QUAT fields 6-9 (qx..qw): quaternion norm 0 is not 1");
  m = g2o3(v + "EDGE_SE3:QUAT 0 1 0 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 0\n");
  CHECK_CONTAINS(
      m, "bad.g2o:3: EDGE_SE3:QUAT fields 10-30 (I11..I66): the information matrix is not positive definite");
  m = g2o3(v + "EDGE_SE3:QUAT 0 1 0 0 0 0 0 0 1 1 0 0\n");
  CHECK_CONTAINS(m,
                 "bad.g2o:3: EDGE_SE3:QUAT: expected 30 fields after the tag, found 12 (truncated line?): "
                 "field 13 (I14) is missing");
  m = g2o3(v + kE01);
  CHECK_CONTAINS(m, "bad.g2o:3: 'EDGE_SE2' is a 2D record, but this is the 3D g2o reader");
}

TEST_CASE("malformed iSAM input") {
  std::string m;
  m = isam2("EDGE2 0 1 1 0 0 10 0 0 0 0 100\n");
  CHECK_CONTAINS(m,
                 "bad.txt:1: EDGE2 fields 6-11 (r_xx..r_tt): the information RᵀR of the square-root numbers "
                 "is not positive definite");
  m = isam2("ODOMETRY 0 1 1 0 0" + kSqrt2 + "\nLANDMARK 1 0 1 2 10 0\n");
  CHECK_CONTAINS(m,
                 "bad.txt:2: LANDMARK: expected 7 fields after the tag, found 6 (truncated line?): field 7 "
                 "(r_yy) is missing");
  m = isam2("ODOMETRY 0 1 1 0 0" + kSqrt2 + "\nLANDMARK 1 0 1 2 10 0 0\n");
  CHECK_CONTAINS(m,
                 "bad.txt:2: LANDMARK fields 5-7 (r_xx..r_yy): the information RᵀR of the square-root "
                 "numbers is not positive definite");
  m = isam2("ODOMETRY 0 1 1 0 0" + kSqrt2 + "\nLANDMARK 1 1 1 2 10 0 10\n");
  CHECK_CONTAINS(m,
                 "bad.txt:2: LANDMARK field 2 (l): landmark ids must be contiguous from 0, but landmark 0 is "
                 "never observed");
  m = isam2("ODOMETRY 0 1 1 0 0" + kSqrt2 + "\nLANDMARK 5 0 1 2 10 0 10\n");
  CHECK_CONTAINS(m, "bad.txt: no odometry edge (1, 2)");
  CHECK_CONTAINS(m, "the largest, 5, is on line 2 (LANDMARK field 1 (i))");
  m = isam2("ODOMETRY 0 1 1 0 0" + kSqrt2 + "\nLANDMARK 2 0 1 2 10 0 10\n");
  CHECK_CONTAINS(m, "bad.txt: no odometry edge (1, 2)");
  CHECK_CONTAINS(m, "pose 2 first appears on line 2 (LANDMARK field 1 (i))");
  m = isam2("ODOMETRY 0 1 1 0 0" + kSqrt2 + "\nEDGE2 0 7 1 0 0" + kSqrt2 + "\n");
  CHECK_CONTAINS(m, "bad.txt: no odometry edge (1, 2)");
  CHECK_CONTAINS(
      m,
      "pose 2 is named by no record, though pose ids must be contiguous from 0 (the largest, 7, is on "
      "line 2 (edge field 2 (j)))");
  m = isam2("ODOMETRY 0 1 1 0 0" + kSqrt2 + "\nEDGE2 3 x 1 0 0" + kSqrt2 + "\n");
  CHECK_CONTAINS(m, "bad.txt:2: EDGE2 field 2 (j): 'x' is not an integer id");
  m = isam2("POSE2 0 1 2 3\n");
  CHECK_CONTAINS(
      m,
      "bad.txt:1: unknown tag 'POSE2' (the 2D iSAM reader knows ODOMETRY, EDGE2, Constraint2 and LANDMARK)");
  m = isam2("EDGE3 0 1 0 0 0 0 0 0" + kEdge3Tail + "\n");
  CHECK_CONTAINS(m, "bad.txt:1: 'EDGE3' is a 3D record, but this is the 2D iSAM reader");
  m = isam3("EDGE3 0 1 0 0 0 0 0 0" + kEdge3Tail + " 1\n");
  CHECK_CONTAINS(
      m, "bad.txt:1: EDGE3: expected 29 fields after the tag, found 30: field 30 '1' is one too many");
  m = isam3("EDGE3 0 1 0 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 0\n");
  CHECK_CONTAINS(m,
                 "bad.txt:1: EDGE3 fields 9-29 (R11..R66): the information RᵀR of the square-root numbers is "
                 "not positive definite");
  m = isam3("EDGE3 0 1 0 0 0 0 0 0" + kEdge3Tail + "\nEDGE3 1 2 0 0 0 0 zz 0" + kEdge3Tail + "\n");
  CHECK_CONTAINS(m, "bad.txt:2: EDGE3 field 7 (pitch): 'zz' is not a number");
  m = isam3("");
  CHECK_CONTAINS(m, "bad.txt: no VERTEX or edge records (empty file?)");
  // Ground-truth readers parse the noise numbers strictly but do not check them (they are placeholders).
  std::istringstream gt("EDGE2 0 1 1 0 0 0 0 0 0 0 0\n");
  CHECK(read_isam_ground_truth_2d(gt, "gt.txt").poses.size() == 2);
  std::istringstream bad_gt("EDGE2 0 1 1 0 0 0 0 0 0 0 q\n");
  CHECK_CONTAINS(error_of([&] { read_isam_ground_truth_2d(bad_gt, "gt.txt"); }),
                 "gt.txt:1: EDGE2 field 11 (r_tt): 'q' is not a number");
}

TEST_CASE("malformed pose lists and TUM files") {
  auto poses2 = [](const std::string& t) {
    return error_of([&] {
      std::istringstream in(t);
      read_poses_2d(in, "p.txt");
    });
  };
  CHECK_CONTAINS(poses2("0 0 0 0\n0 1 0 0\n"),
                 "p.txt:2: pose field 1 (id): duplicate id 0 (first on line 1)");
  CHECK_CONTAINS(poses2("0 0 0 0\n2 1 0 0\n"),
                 "p.txt:2: pose field 1 (id): ids must be contiguous from 0, but id 1 is missing");
  CHECK_CONTAINS(poses2("0 0 0\n"),
                 "p.txt:1: pose: expected 4 fields, found 3 (truncated line?): field 4 (theta) is missing");
  CHECK_CONTAINS(poses2("0 0 0 x\n"), "p.txt:1: pose field 4 (theta): 'x' is not a number");
  CHECK_CONTAINS(poses2(""), "p.txt: no pose records");
  std::istringstream q("0 0 0 0 0 0 0 3\n");
  CHECK_CONTAINS(error_of([&] { read_poses_3d(q, "q.txt"); }),
                 "q.txt:1: pose fields 5-8 (qx..qw): quaternion norm 3 is not 1");
  std::istringstream t("0 1 2 3 0 0 0\n");
  CHECK_CONTAINS(error_of([&] { read_tum(t, "t.tum"); }),
                 "t.tum:1: TUM: expected 8 fields, found 7 (truncated line?): field 8 (qw) is missing");
  std::istringstream empty("# header only\n");
  CHECK_CONTAINS(error_of([&] { read_tum(empty, "e.tum"); }), "e.tum: no TUM records");
  std::istringstream l("0 1 2 3\n");
  CHECK_CONTAINS(error_of([&] { read_pose_list_2d(l, "n.dat"); }),
                 "n.dat:1: pose: expected 3 fields, found 4: field 4 '3' is one too many");
}
