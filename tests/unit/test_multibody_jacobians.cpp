// Multibody: the exact iteration matrix (dense and sparse) equals
// Richardson-extrapolated central differences of the residual for every joint
// kind x representation x form x scheme, at the consistent start and at a
// perturbed, inconsistent state; the residual vanishes at the start; the
// residual and both iteration matrices allocate nothing.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <string>

#include "multibody_differences.hpp"
#include "alloc_counter.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyProblem;
using test::richardson_matrix;
using test::row_relative_difference;

namespace {

const Coordinates kCoordinates[] = {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear};
const Equations kEquations[] = {Equations::Lagrange, Equations::Euler};
Eigen::MatrixXd sparse_to_dense(const SparsityPattern& p, const Eigen::VectorXd& values, int n) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c)
    for (std::int64_t k = p.col_start[c]; k < p.col_start[c + 1]; ++k) J(p.rows[k], c) = values(k);
  return J;
}

// 1e-8 as for one body: measured differences are ~1e-10 (see the MESSAGE),
// while a wrong term changes its rows by O(1).
constexpr double kMatrixTolerance = 1e-8;

}  // namespace

TEST_CASE("multibody: exact iteration matrix = differences, every joint x representation x form x scheme" * doctest::test_suite("slow")) {
  std::mt19937 rng(4242);
  double worst = 0.0, worst_start_residual = 0.0;
  for (const JointType* jt : joint_types())  // every registered type (model/joint_type.hpp)
    for (Coordinates c : kCoordinates)
      for (Equations e : kEquations)
        for (const std::string& scheme : scheme_names()) {
          const Scene s = test::two_body_chain(jt, c, e, scheme);
          MultibodyProblem p(s);
          const int n = p.size();
          CAPTURE(jt->name);
          CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
          Eigen::VectorXd y, yp;
          p.initial_state(0.0, y, yp);
          // The start is consistent: the residual vanishes to round-off.
          Eigen::VectorXd F(n);
          REQUIRE(p.residual(0.0, y.data(), yp.data(), F.data()));
          const double scale = std::max({1.0, y.cwiseAbs().maxCoeff(), yp.cwiseAbs().maxCoeff()});
          worst_start_residual = std::max(worst_start_residual, F.cwiseAbs().maxCoeff() / scale);
          CHECK(F.cwiseAbs().maxCoeff() < 1e-10 * scale);
          for (int k = 0; k < 2; ++k) {
            Eigen::VectorXd yk = y, ypk = yp;
            if (k == 1) test::perturb_state(rng, yk, ypk);
            const double cj = k == 0 ? 3.7 : 250.0;
            Eigen::MatrixXd dense(n, n);
            p.iteration_matrix_dense(0.2, cj, yk.data(), ypk.data(), dense.data());
            Eigen::VectorXd values(p.sparsity().nnz());
            p.iteration_matrix_sparse(0.2, cj, yk.data(), ypk.data(), values.data());
            const Eigen::MatrixXd sparse = sparse_to_dense(p.sparsity(), values, n);
            const Eigen::MatrixXd reference = richardson_matrix(p, 0.2, cj, yk, ypk);
            const double d = row_relative_difference(dense, reference);
            worst = std::max(worst, d);
            CAPTURE(k);
            CHECK(d < kMatrixTolerance);
            // The sparse values are the dense matrix on the pattern, and the
            // pattern holds every nonzero.
            CHECK((sparse - dense).cwiseAbs().maxCoeff() == 0.0);
          }
        }
  MESSAGE("largest row-relative difference: " << worst << "; largest start residual: " << worst_start_residual);
}

namespace {

// Point masses (multibody/point_mass.hpp) in every role: a rigid body A on a
// spherical joint to the ground; particle P on a rod (distance joint) from a
// point of A; particle Q on a rod from P and at a point of A by a spherical
// joint; springs between P and Q and from the ground to P; a space force on
// P. General poses and velocities (projected by the start).
Scene particle_chain(Coordinates c, Equations e, const std::string& scheme) {
  Scene s = test::multibody_base(c, e, scheme);
  MultibodySpec& m = *s.multibody;
  BodySpec a;
  a.name = "A";
  a.mass = 2.0;
  a.inertia_com << 0.4, 0.05, -0.02, 0.05, 0.7, 0.03, -0.02, 0.03, 0.9;
  a.x0_W = Vec3(0.3, -0.2, -0.5);
  a.R0_WB = so3::axis_angle_to_matrix(Vec3(1, 2, 3).normalized(), 0.7);
  a.v0_W = Vec3(0.5, -0.4, 0.3);
  a.omega0_B = Vec3(1.5, -2.0, 3.0);
  BodySpec pp;
  pp.name = "P";
  pp.particle = true;
  pp.mass = 0.7;
  pp.inertia_com.setZero();
  pp.x0_W = Vec3(0.9, 0.3, -1.0);
  pp.v0_W = Vec3(-0.3, 0.8, 0.2);
  BodySpec q = pp;
  q.name = "Q";
  q.mass = 1.1;
  q.x0_W = a.x0_W + a.R0_WB * Vec3(0.2, -0.3, 0.1);
  q.v0_W = Vec3(0.4, 0.1, -0.6);
  m.bodies = {a, pp, q};
  const auto joint = [&](const char* type, int ba, int bb, const Vec3& pa_W, const Vec3& pb_W, const char* name) {
    JointSpec j;
    j.name = name;
    j.type = &joint_type(type);
    j.body_a = ba;
    j.body_b = bb;
    const auto to_body = [&](int i, const Vec3& p) -> Vec3 {
      return i == kGround ? p : Vec3(m.bodies[i].R0_WB.transpose() * (p - m.bodies[i].x0_W));
    };
    j.point_a = to_body(ba, pa_W);
    j.point_b = to_body(bb, pb_W);
    j.length = (pb_W - pa_W).norm();
    return j;
  };
  const Vec3 tip = a.x0_W + a.R0_WB * Vec3(-0.3, 0.2, 0.4);
  m.joints.push_back(joint("spherical", kGround, 0, Vec3(0.1, 0.0, 0.0), Vec3(0.1, 0.0, 0.0), "pivot"));
  m.joints.push_back(joint("distance", 0, 1, tip, pp.x0_W, "rodAP"));
  m.joints.push_back(joint("distance", 1, 2, pp.x0_W, q.x0_W, "rodPQ"));
  m.joints.push_back(joint("spherical", 0, 2, q.x0_W, q.x0_W, "ballAQ"));
  SpringSpec sp;
  sp.name = "springPQ";
  sp.body_a = 1;
  sp.body_b = 2;
  sp.stiffness = 40.0;
  sp.damping = 1.5;
  sp.rest_length = 0.3;
  SpringSpec sg = sp;
  sg.name = "springGP";
  sg.body_a = kGround;
  sg.body_b = 1;
  sg.point_a = Vec3(1.0, 1.0, 0.5);
  m.springs = {sp, sg};
  BodyLoadSpec load;
  load.body = 1;
  load.force = Vec3(1.0, -2.0, 0.5);
  m.loads = {load};
  return s;
}

}  // namespace

TEST_CASE("multibody: particles: exact iteration matrix = differences, every representation x form x scheme") {
  std::mt19937 rng(2211);
  double worst = 0.0;
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations)
      for (const std::string& scheme : scheme_names()) {
        MultibodyProblem p(particle_chain(c, e, scheme));
        CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
        const int n = p.size();
        // A particle adds 3 + 3 unknowns; A its representation's.
        CHECK(p.bodies()[1].nqr == 0);
        CHECK(p.bodies()[2].nvr == 0);
        // Gruebler-Kutzbach: 6 + 3 + 3 - (3 + 1 + 1 + 3) = 4 = the rank mobility.
        CHECK(p.redundancy().gruebler_dof == 4);
        CHECK(p.redundancy().rank_dof == 4);
        Eigen::VectorXd y, yp, F(n);
        p.initial_state(0.0, y, yp);
        REQUIRE(p.residual(0.0, y.data(), yp.data(), F.data()));
        const double scale = std::max({1.0, y.cwiseAbs().maxCoeff(), yp.cwiseAbs().maxCoeff()});
        CHECK(F.cwiseAbs().maxCoeff() < 1e-10 * scale);
        for (int k = 0; k < 2; ++k) {
          Eigen::VectorXd yk = y, ypk = yp;
          if (k == 1) test::perturb_state(rng, yk, ypk);
          const double cj = k == 0 ? 3.7 : 250.0;
          Eigen::MatrixXd dense(n, n);
          p.iteration_matrix_dense(0.2, cj, yk.data(), ypk.data(), dense.data());
          Eigen::VectorXd values(p.sparsity().nnz());
          p.iteration_matrix_sparse(0.2, cj, yk.data(), ypk.data(), values.data());
          const double d = row_relative_difference(dense, richardson_matrix(p, 0.2, cj, yk, ypk));
          worst = std::max(worst, d);
          CAPTURE(k);
          CHECK(d < kMatrixTolerance);
          CHECK((sparse_to_dense(p.sparsity(), values, n) - dense).cwiseAbs().maxCoeff() == 0.0);
        }
      }
  MESSAGE("particles: largest row-relative difference " << worst);
}

TEST_CASE("multibody: residual and iteration matrices allocate nothing") {
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations)
      for (const std::string& scheme : scheme_names()) {
        const Scene s = test::two_body_chain(&joint_type("revolute"), c, e, scheme);
        MultibodyProblem p(s);
        const int n = p.size();
        Eigen::VectorXd y, yp, F(n), values(p.sparsity().nnz());
        Eigen::MatrixXd J(n, n);
        p.initial_state(0.0, y, yp);
        test::start_counting_allocations();
        p.residual(0.1, y.data(), yp.data(), F.data());
        p.iteration_matrix_dense(0.1, 50.0, y.data(), yp.data(), J.data());
        p.iteration_matrix_sparse(0.1, 50.0, y.data(), yp.data(), values.data());
        const long allocations = test::stop_counting_allocations();
        CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
        CHECK(allocations == 0);
      }
}

TEST_CASE("multibody: the sparse pattern of a chain grows linearly with the number of links") {
  for (Coordinates c : kCoordinates)
    for (Equations e : kEquations) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      std::int64_t nnz[3];
      const int n[3] = {10, 20, 40};
      for (int k = 0; k < 3; ++k) {
        const MultibodyProblem p(test::spherical_chain(n[k], c, e, "ggl"));
        nnz[k] = p.sparsity().nnz();
      }
      // nnz = a N + b exactly: each link adds its own blocks and one joint's.
      CHECK(nnz[2] - nnz[1] == 2 * (nnz[1] - nnz[0]));
      MESSAGE(to_string(c) << "/" << to_string(e) << ": nonzeros per link " << (nnz[1] - nnz[0]) / 10);
    }
}

TEST_SUITE_END();
