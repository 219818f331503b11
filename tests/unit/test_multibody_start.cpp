// Multibody consistent starts: the heavy top in absolute coordinates starts
// with the pivoted model's acceleration and the reaction m (a_c - g) of the
// literature (450.28 N); joint misses above the tolerance are a positioned
// error, smaller ones are projected with a warning; an overconstrained loop
// runs with its dependent rows set aside and named.
#include <doctest/doctest.h>

#include <string>

#include "rigidae/core/error.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "test_multibody_scenes.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyProblem;

namespace {

const Coordinates kCoordinates[] = {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear};
const Equations kEquations[] = {Equations::Lagrange, Equations::Euler};

std::string error_of(const Scene& s) {
  try {
    MultibodyProblem p(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// A four-bar loop ground - crank - coupler - rocker - ground in the plane
// z = 0, every joint of the given types, axes along z.
Scene four_bar(const JointType* const types[4]) {
  Scene s = test::multibody_base(Coordinates::Quaternion, Equations::Euler, "ggl");
  MultibodySpec& m = *s.multibody;
  const Vec3 O1(0, 0, 0), P1(0.3, 1.0, 0), P2(2.1, 1.4, 0), O2(2.0, 0, 0);
  const Vec3 ends[3][2] = {{O1, P1}, {P1, P2}, {P2, O2}};
  const char* names[3] = {"crank", "coupler", "rocker"};
  for (int i = 0; i < 3; ++i) {
    BodySpec b;
    b.name = names[i];
    b.mass = 1.0 + 0.2 * i;
    b.inertia_com = Vec3(0.1, 0.12, 0.2).asDiagonal();
    b.x0_W = 0.5 * (ends[i][0] + ends[i][1]);
    m.bodies.push_back(b);
  }
  const int a[4] = {kGround, 0, 1, 2}, b[4] = {0, 1, 2, kGround};
  const Vec3 at[4] = {O1, P1, P2, O2};
  for (int k = 0; k < 4; ++k)
    m.joints.push_back(test::joint_at(m, types[k], a[k], b[k], at[k], Vec3::UnitZ(), Vec3::UnitX(),
                                      "J" + std::to_string(k + 1)));
  return s;
}

}  // namespace

TEST_CASE("multibody heavy top: the start's acceleration is the pivoted model's, the reaction m (a_c - g)") {
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      const Scene s = test::absolute_heavy_top(c, e, "ggl");
      MultibodyProblem p(s);
      CHECK(p.warnings().empty());
      Eigen::VectorXd y, yp;
      p.initial_state(0.0, y, yp);
      const int vo = p.groups()[p.bodies()[0].v_group].offset;
      const Vec3 a_c = yp.segment<3>(vo);
      // The pivoted top (today's model): omega' at the start, then
      // a_c = R (omega' x c + omega x (omega x c)) with R = I, c = (0, 1, 0).
      // The schema-1 top, one body pivoted at the fixed point (one_body_system);
      // quaternions in the Euler form: v = omega_B.
      const Scene top = test::heavy_top_scene(Coordinates::Quaternion, Equations::Euler, "ggl");
      MultibodyProblem pivoted(one_body_system(top));
      Eigen::VectorXd y1, yp1;
      pivoted.initial_state(0.0, y1, yp1);
      const multibody::UnknownGroup& vg = pivoted.groups()[pivoted.bodies()[0].v_group];
      REQUIRE(vg.size == 3);
      const Vec3 w = top.omega0_B, wdot = yp1.segment<3>(vg.offset), cB(0, 1, 0);
      const Vec3 a_pivoted = wdot.cross(cB) + w.cross(w.cross(cB));
      CHECK((a_c - a_pivoted).norm() < 1e-9 * a_pivoted.norm());
      const multibody::JointReaction r = p.joint_reaction(0, y.data());
      const Vec3 expected = 15.0 * (a_c - s.multibody->gravity_W);
      CHECK((r.force - expected).norm() < 1e-9 * expected.norm());
      CHECK(r.torque.norm() < 1e-9);
      // Bruls, Cardona & Arnold (2012) give |reaction| = 450.28 N at t = 0.
      CHECK(r.force.norm() == doctest::Approx(450.28).epsilon(1e-4));
      MESSAGE(to_string(c) << "/" << to_string(e) << ": |reaction| at t = 0: " << r.force.norm() << " N");
    }
}

TEST_CASE("multibody start: a miss above the tolerance names the joint, and a small one is projected") {
  Scene s = test::two_body_chain(&joint_type("revolute"), Coordinates::Quaternion, Equations::Lagrange, "ggl");
  s.multibody->joints[1].point_b += Vec3(0, 0, 1e-3);
  const std::string big = error_of(s);
  CHECK(big.find("built_in.toml:11:1") != std::string::npos);
  CHECK(big.find("joint 'j1' (revolute)") != std::string::npos);
  CHECK(big.find("miss the joint by") != std::string::npos);
  CHECK(big.find("start_tolerance") != std::string::npos);

  s = test::two_body_chain(&joint_type("revolute"), Coordinates::Linear, Equations::Euler, "index2");
  s.multibody->joints[1].point_b += Vec3(0, 0, 5e-7);
  MultibodyProblem p(s);
  REQUIRE(p.warnings().size() >= 1);
  CHECK(p.warnings()[0].find("joint 'j1'") != std::string::npos);
  Eigen::VectorXd y, yp;
  p.initial_state(0.0, y, yp);
  const auto [pos, vel] = p.drift(0.0, y.data());
  CHECK(pos < 1e-13);
  CHECK(vel < 1e-12);
}

TEST_CASE("multibody start: an overconstrained four-bar runs with its dependent rows set aside and named") {
  const JointType* revolutes[4] = {&joint_type("revolute"), &joint_type("revolute"), &joint_type("revolute"),
                                  &joint_type("revolute")};
  CHECK(error_of(four_bar(revolutes)) == "no error");
  MultibodyProblem p(four_bar(revolutes));
  // 3 bodies (18 freedoms), 20 rows, one degree of freedom left: 3 redundant.
  CHECK(p.redundancy().rank == 17);
  CHECK(p.redundancy().rank_dof == 1);
  CHECK(p.redundancy().gruebler_dof == -2);
  REQUIRE(p.redundancy().dropped.size() == 3);
  REQUIRE(!p.warnings().empty());
  CHECK(p.warnings()[0].find("3 of the 20 constraint rows are redundant") != std::string::npos);
  CHECK(p.warnings()[0].find("built_in.toml:") != std::string::npos);
  // The kept rows hold the start; the rows set aside are implied.
  Eigen::VectorXd y, yp;
  p.initial_state(0.0, y, yp);
  CHECK(p.dropped_drift(y.data()).first < 1e-12);
  CHECK(p.drift(0.0, y.data()).first < 1e-12);
  // Revolute - spherical - spherical - revolute has independent rows (and
  // the coupler's spin about its axis: 2 degrees of freedom).
  const JointType* rssr[4] = {&joint_type("revolute"), &joint_type("spherical"), &joint_type("spherical"), &joint_type("revolute")};
  MultibodyProblem q(four_bar(rssr));
  CHECK(q.redundancy().dropped.empty());
  CHECK(q.redundancy().rank_dof == 2);
  CHECK(q.redundancy().gruebler_dof == 2);
}

namespace {

// Two bodies welded by a fixed joint, moving as one rigid body with angular
// velocity w (space) and centre-of-mass velocity v_c, under gravity.
Scene welded_pair(Coordinates c, Equations e, const std::string& scheme, const Vec3& w, const Vec3& v_c) {
  Scene s = test::two_body_chain(&joint_type("fixed"), c, e, scheme);
  MultibodySpec& m = *s.multibody;
  m.springs.clear();
  m.loads.clear();
  m.joints.erase(m.joints.begin());  // free: no joint to the ground
  m.joints[0].body_a = 0;
  const double M = m.bodies[0].mass + m.bodies[1].mass;
  const Vec3 xc = (m.bodies[0].mass * m.bodies[0].x0_W + m.bodies[1].mass * m.bodies[1].x0_W) / M;
  for (BodySpec& b : m.bodies) {
    b.omega0_B = b.R0_WB.transpose() * w;
    b.v0_W = v_c + w.cross(b.x0_W - xc);
  }
  return s;
}

}  // namespace

TEST_CASE("multibody start: two welded bodies accelerate as one body with the combined inertia") {
  const Vec3 w(0.7, -1.3, 2.1), v_c(0.2, 0.1, -0.4);
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations)
      for (const std::string scheme : {"ggl", "index1", "baumgarte"}) {
        CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
        const Scene s = welded_pair(c, e, scheme, w, v_c);
        const MultibodySpec& m = *s.multibody;
        MultibodyProblem p(s);
        CHECK(p.warnings().empty());  // the rigid motion satisfies the joint
        Eigen::VectorXd y, yp;
        p.initial_state(0.0, y, yp);
        // The combined body: mass, centre of mass, inertia about it (space).
        const double M = m.bodies[0].mass + m.bodies[1].mass;
        const Vec3 xc = (m.bodies[0].mass * m.bodies[0].x0_W + m.bodies[1].mass * m.bodies[1].x0_W) / M;
        Mat3 J = Mat3::Zero();
        for (const BodySpec& b : m.bodies) {
          const Vec3 r = b.x0_W - xc;
          J += b.R0_WB * b.inertia_com * b.R0_WB.transpose() +
               b.mass * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
        }
        // Torque free about the centre of mass: J w' = -w x J w.
        const Vec3 wdot = J.ldlt().solve(-w.cross(J * w));
        Vec3 force = Vec3::Zero();
        for (int i = 0; i < 2; ++i) {
          const Vec3 r = m.bodies[i].x0_W - xc;
          const Vec3 a_rigid = m.gravity_W + wdot.cross(r) + w.cross(w.cross(r));
          const Vec3 a = yp.segment<3>(p.groups()[p.bodies()[i].v_group].offset);
          CHECK((a - a_rigid).norm() < 1e-9 * (1.0 + a_rigid.norm()));
          force += m.bodies[i].mass * a;
          if (e == Equations::Euler) {
            const Vec3 Wdot = yp.segment<3>(p.groups()[p.bodies()[i].v_group].offset + 3);
            CHECK((m.bodies[i].R0_WB * Wdot - wdot).norm() < 1e-9 * (1.0 + wdot.norm()));
          }
        }
        // Reactions balance: sum m_i a_i = total external force (gravity).
        CHECK((force - M * m.gravity_W).norm() < 1e-9 * M * m.gravity_W.norm());
        // The weld's reaction on B is B's own m (a - g).
        const multibody::JointReaction r = p.joint_reaction(0, y.data());
        const Vec3 aB = yp.segment<3>(p.groups()[p.bodies()[1].v_group].offset);
        CHECK((r.force - m.bodies[1].mass * (aB - m.gravity_W)).norm() < 1e-9);
      }
}

TEST_SUITE_END();
