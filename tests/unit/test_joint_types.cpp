// The joint-type registry (model/joint_type.hpp): every registered type has
// 6 - freedoms rows, its rows hold at a pose where the joint is assembled,
// and the freedoms it states are the relative motions its rows allow: the
// rows' derivative along the six relative twists of b (by central
// differences of the rows evaluated here from their dot-product terms, not
// by the assembler) has rank 6 - freedoms, with the stated split into
// rotations and translations. Each row's RowReaction matches its terms.
#include <doctest/doctest.h>

#include <set>
#include <stdexcept>
#include <string>

#include "rigidae/model/joint_type.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 x = Vec3::Zero();
};

// A row's value with body 0 at pa and body 1 at pb (the ground is space).
double row_value(const ConstraintRow& r, const Pose& pa, const Pose& pb) {
  const auto in_space = [&](const BodyVector& v) -> Vec3 {
    if (v.body == kGround) return v.s;
    const Pose& p = v.body == 0 ? pa : pb;
    return v.point ? Vec3(p.R * v.s + p.x) : Vec3(p.R * v.s);
  };
  double value = r.constant;
  for (int t = 0; t < r.n_terms; ++t) value += r.terms[t].coeff * in_space(r.terms[t].a).dot(in_space(r.terms[t].b));
  return value;
}

// Two bodies at general poses and a joint of `type` between them at P.
MultibodySpec two_bodies(const JointType& type) {
  MultibodySpec m;
  BodySpec a, b;
  a.name = "a";
  a.x0_W = Vec3(0.3, -0.2, 0.5);
  a.R0_WB = so3::axis_angle_to_matrix(Vec3(1, 2, 3).normalized(), 0.7);
  b.name = "b";
  b.x0_W = Vec3(0.9, 0.4, -0.1);
  b.R0_WB = so3::axis_angle_to_matrix(Vec3(-2, 1, 0.5).normalized(), 1.1);
  m.bodies = {a, b};
  const Vec3 z = Vec3(0.2, 0.3, 1.0).normalized();
  m.joints.push_back(test::joint_at(m, &type, 0, 1, Vec3(0.5, 0.1, 0.2), z, z.cross(Vec3::UnitX()).normalized(), "j"));
  return m;
}

// Singular values above 1e-6: the rows' derivatives are O(1) (lengths of
// about 0.5 m, unit directions), the differences' error about 1e-10.
int rank(const Eigen::MatrixXd& A) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A);
  int r = 0;
  for (Eigen::Index k = 0; k < svd.singularValues().size(); ++k) r += svd.singularValues()(k) > 1e-6;
  return r;
}

}  // namespace

TEST_CASE("joint types: names are unique and found, an unknown name is refused") {
  std::set<std::string_view> names;
  for (const JointType* t : joint_types()) {
    CHECK(names.insert(t->name).second);
    CHECK(find_joint_type(t->name) == t);
    CHECK(&joint_type(t->name) == t);
    CHECK(static_cast<bool>(t->rows));
    CHECK_FALSE(t->description.empty());
    CHECK_FALSE(t->reaction.empty());
    CHECK(t->coordinates.size() <= static_cast<std::size_t>(kMaxJointCoordinates));
  }
  CHECK(joint_type_names().size() == joint_types().size());
  CHECK(find_joint_type("hinge") == nullptr);
  CHECK_THROWS_AS(joint_type("hinge"), std::invalid_argument);
}

TEST_CASE("joint types: 6 - freedoms rows that hold at the assembled pose, each reaction as its terms say") {
  for (const JointType* t : joint_types()) {
    CAPTURE(t->name);
    const MultibodySpec m = two_bodies(*t);
    std::vector<ConstraintRow> rows;
    t->rows(m.joints[0], rows);
    CHECK(static_cast<int>(rows.size()) == 6 - t->freedoms.total());
    const Pose pa{m.bodies[0].R0_WB, m.bodies[0].x0_W}, pb{m.bodies[1].R0_WB, m.bodies[1].x0_W};
    std::set<std::string> row_names;
    for (const ConstraintRow& r : rows) {
      CAPTURE(r.name);
      CHECK(row_names.insert(r.name).second);
      CHECK(std::abs(row_value(r, pa, pb)) < 1e-14);
      switch (r.reaction) {
        case RowReaction::Point:  // p_a . e_k - p_b . e_k
          CHECK(r.n_terms == 2);
          CHECK((r.terms[0].a.point && r.terms[1].a.point && r.terms[0].b.body == kGround));
          break;
        case RowReaction::Line:  // p_b . n - p_a . n, n fixed in a
          CHECK(r.n_terms == 2);
          CHECK((r.terms[0].a.point && !r.terms[0].b.point && r.terms[0].b.body == 0));
          break;
        case RowReaction::Turn:  // d_a . d_b
          CHECK(r.n_terms == 1);
          CHECK((!r.terms[0].a.point && !r.terms[0].b.point));
          break;
        case RowReaction::Distance:  // (|p_b - p_a|^2 - L^2) / (2L): three terms and a constant
          CHECK(r.n_terms == 3);
          CHECK((r.terms[0].a.point && r.terms[0].b.point && r.constant < 0.0));
          break;
        case RowReaction::Coordinate: FAIL("a constraint row marked as a coordinate"); break;
      }
    }
  }
}

TEST_CASE("joint types: the stated freedoms are the relative motions the rows allow") {
  for (const JointType* t : joint_types()) {
    CAPTURE(t->name);
    const MultibodySpec m = two_bodies(*t);
    std::vector<ConstraintRow> rows;
    t->rows(m.joints[0], rows);
    const Pose pa{m.bodies[0].R0_WB, m.bodies[0].x0_W};
    const Vec3 P = m.bodies[0].R0_WB * m.joints[0].point_a + m.bodies[0].x0_W;
    // Twist k of b about the joint point: k < 3 translations, else rotations.
    const auto moved = [&](int k, double h) {
      Pose pb{m.bodies[1].R0_WB, m.bodies[1].x0_W};
      if (k < 3) {
        pb.x += h * Vec3::Unit(k);
      } else {
        const Mat3 dR = so3::axis_angle_to_matrix(Vec3::Unit(k - 3), h);
        pb.R = dR * pb.R;
        pb.x = P + dR * (pb.x - P);
      }
      return pb;
    };
    const double h = 1e-6;
    Eigen::MatrixXd A(static_cast<Eigen::Index>(rows.size()), 6);
    for (std::size_t r = 0; r < rows.size(); ++r)
      for (int k = 0; k < 6; ++k)
        A(static_cast<Eigen::Index>(r), k) =
            (row_value(rows[r], pa, moved(k, h)) - row_value(rows[r], pa, moved(k, -h))) / (2 * h);
    CHECK(rank(A) == 6 - t->freedoms.total());
    // The rows restricted to translations have rank 3 - translational, to
    // rotations about the joint point 3 - rotational.
    CHECK(rank(A.leftCols(3)) == 3 - t->freedoms.translational);
    CHECK(rank(A.rightCols(3)) == 3 - t->freedoms.rotational);
  }
}

TEST_SUITE_END();
