// The ODE form's small dense KKT path (src/multibody/small_lu.hpp) against
// independent truth:
// - SmallLu solves random regular systems to round-off (residual, and
//   Eigen's full-pivoting LU's answer) and reports a singular matrix by its
//   pivot ratio;
// - on every shipped mechanism small enough for it (every coordinate set
//   and form, at the start and at random off-manifold states), the ODE's x'
//   and multipliers equal those of the general path (Eigen's dynamic
//   PartialPivLU) to round-off;
// - its rhs() allocates nothing.
#include <doctest/doctest.h>

#include <Eigen/LU>
#include <algorithm>
#include <filesystem>
#include <random>
#include <string>

#include "alloc_counter.hpp"
#include "multibody_differences.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_ode.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "multibody/small_lu.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using multibody::MultibodyOde;
using multibody::MultibodyProblem;
using multibody::SmallLu;

namespace {

// Every shipped scene with joints (schema 2) whose KKT system is small.
std::vector<std::string> small_mechanisms() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(std::string(RIGIDAE_SOURCE_DIR) + "/problems")) {
    if (e.path().extension() != ".toml") continue;
    const Scene s = io::load_scene(e.path().string());
    if (s.multibody && !s.multibody->joints.empty()) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("small kkt: SmallLu solves random regular systems as Eigen's full-pivoting LU does") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {1, 2, 5, 11, 24, SmallLu::kCapacity}) {
    CAPTURE(n);
    Eigen::MatrixXd A(n, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) A(i, j) = u(rng);
    // A saddle-like zero block in the corner, as the KKT matrix has.
    const int z = n / 3;
    A.bottomRightCorner(z, z).setZero();
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b(i) = u(rng);
    SmallLu lu;
    lu.resize(n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) lu(i, j) = A(i, j);
    REQUIRE(lu.factorise() > 1e-8);
    Eigen::VectorXd x = b;
    lu.solve(x.data());
    const Eigen::VectorXd truth = A.fullPivLu().solve(b);
    const double cond_bound = 1e-10 * (1.0 + truth.cwiseAbs().maxCoeff());
    CHECK((A * x - b).cwiseAbs().maxCoeff() < 1e-12 * n);
    CHECK((x - truth).cwiseAbs().maxCoeff() < cond_bound);
    // The matrix is kept: a second factorisation gives the same answer.
    REQUIRE(lu.factorise() > 1e-8);
    Eigen::VectorXd x2 = b;
    lu.solve(x2.data());
    CHECK((x2 - x).cwiseAbs().maxCoeff() == 0.0);
  }
}

TEST_CASE("small kkt: a singular matrix has pivot ratio below 1e-13") {
  SmallLu lu;
  lu.resize(3);
  // Row 3 = row 1 + row 2.
  const double rows[3][3] = {{1.0, 2.0, 3.0}, {0.5, -1.0, 4.0}, {1.5, 1.0, 7.0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) lu(i, j) = rows[i][j];
  CHECK(lu.factorise() < 1e-13);
  lu.resize(2);  // all zero
  CHECK(lu.factorise() == 0.0);
}

TEST_CASE("small kkt: x' and multipliers equal the general dense path's on every shipped mechanism") {
  const Coordinates coordinates[] = {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear};
  const Equations equations[] = {Equations::Lagrange, Equations::Euler};
  int compared = 0;
  for (const std::string& file : small_mechanisms())
    for (Coordinates c : coordinates)
      for (Equations e : equations) {
        CAPTURE(file);
        CAPTURE(to_string(c));
        CAPTURE(to_string(e));
        Scene s = io::load_scene(file);
        s.formulation.coordinates = c;
        s.formulation.equations = e;
        s.formulation.scheme = "index1";
        for (BodySpec& b : s.multibody->bodies) b.coordinates.reset();
        MultibodyProblem p(s);
        MultibodyOde small(p, false, s.source, true), general(p, false, s.source, false);
        CHECK_FALSE(general.small_dense());
        if (!small.small_dense()) {
          CHECK(small.saddle_size() > SmallLu::kCapacity);
          continue;
        }
        Eigen::VectorXd x;
        small.initial_state(s.time.start, x);
        std::mt19937 rng(11);
        for (int trial = 0; trial < 4; ++trial) {
          Eigen::VectorXd xs = x, unused = Eigen::VectorXd::Zero(x.size());
          if (trial > 0) test::perturb_state(rng, xs, unused);
          const double t = s.time.start + 0.1 * trial;
          Eigen::VectorXd xd_small(small.size()), xd_general(general.size());
          REQUIRE(small.rhs(t, xs.data(), xd_small.data()));
          REQUIRE(general.rhs(t, xs.data(), xd_general.data()));
          const double scale_x = 1.0 + xd_general.cwiseAbs().maxCoeff();
          CHECK((xd_small - xd_general).cwiseAbs().maxCoeff() <= 1e-12 * scale_x);
          const Eigen::VectorXd& l_small = small.multipliers();
          const Eigen::VectorXd& l_general = general.multipliers();
          const double scale_l = 1.0 + l_general.cwiseAbs().maxCoeff();
          CHECK((l_small - l_general).cwiseAbs().maxCoeff() <= 1e-12 * scale_l);
          ++compared;
        }
      }
  // The pendulums, the four-bars, the slider, the Bricard loop...: most of them.
  CHECK(compared >= 4 * 6 * 8);
}

TEST_CASE("small kkt: rhs on the small path allocates nothing") {
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/double_pendulum.toml");
  s.formulation.scheme = "index1";
  MultibodyProblem p(s);
  MultibodyOde ode(p, false, s.source);
  REQUIRE(ode.small_dense());
  Eigen::VectorXd x, xdot(ode.size());
  ode.initial_state(0.0, x);
  REQUIRE(ode.rhs(0.0, x.data(), xdot.data()));
  x.array() += 1e-4;
  test::start_counting_allocations();
  const bool ok = ode.rhs(0.1, x.data(), xdot.data());
  const long n = test::stop_counting_allocations();
  CHECK(ok);
  CHECK(n == 0);
}

TEST_SUITE_END();
