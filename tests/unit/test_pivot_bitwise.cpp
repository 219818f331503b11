// A one-body scene as a system of one pivoted body (model/one_body_system.hpp)
// is evaluated by the multibody model with the one-body model's arithmetic:
// the consistent start, the residual and the exact iteration matrix at the
// same (t, y, y') are equal bit for bit, for every coordinates x equations x
// scheme combination on a top (pivoted at its fixed point) and a free body
// (pivoted at its centre of mass). The two assemblers are written apart
// (src/schemes + src/dae against src/multibody); equality to the last bit
// holds only if every sum is taken in the same order (schemes/body_rows.hpp),
// which is what makes the single-body pins reproduce through the multibody
// model (test_pivot_pins.cpp).
#include <doctest/doctest.h>

#include <random>
#include <string>

#include "multibody_differences.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/dae/single_body_problem.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

// Entries of a and b that are not the same double.
int differing(const double* a, const double* b, int n) {
  int count = 0;
  for (int i = 0; i < n; ++i) count += a[i] == b[i] ? 0 : 1;
  return count;
}

}  // namespace

TEST_CASE("pivot: a one-body system's start, residual and iteration matrix are the one-body model's bit for bit") {
  int combinations = 0;
  for (const char* file : {"problems/heavy_top.toml", "problems/free_body.toml"})
    for (const char* coords : {"quaternion", "linear", "euler"})
      for (const Equations eq : {Equations::Lagrange, Equations::Euler})
        for (const char* scheme : {"index3", "index2", "index1", "baumgarte", "ggl", "projection"}) {
          Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/" + file);
          s.formulation.coordinates = Coordinates(coords);
          s.formulation.equations = eq;
          s.formulation.scheme = scheme;
          CAPTURE(file);
          CAPTURE(coords);
          CAPTURE(eq == Equations::Euler ? "euler" : "lagrange");
          CAPTURE(scheme);
          const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
          SingleBodyProblem one(*dae, s.formulation.euler, s.R0_WB, s.omega0_B, s.source);
          multibody::MultibodyProblem system(one_body_system(s));
          const int n = one.size();
          REQUIRE(system.size() == n);
          Eigen::VectorXd y1, yp1, y2, yp2;
          one.initial_state(0.0, y1, yp1);
          system.initial_state(0.0, y2, yp2);
          CHECK(differing(y1.data(), y2.data(), n) == 0);
          CHECK(differing(yp1.data(), yp2.data(), n) == 0);
          // Off the start and off the manifold (each entry moved by up to 5 %).
          std::mt19937 rng(7);
          Eigen::VectorXd y = y1, yp = yp1;
          test::perturb_state(rng, y, yp);
          Eigen::VectorXd F1(n), F2(n);
          one.residual(0.3, y.data(), yp.data(), F1.data());
          system.residual(0.3, y.data(), yp.data(), F2.data());
          CHECK(F1.cwiseAbs().maxCoeff() > 0.0);
          CHECK(differing(F1.data(), F2.data(), n) == 0);
          Eigen::MatrixXd J1(n, n), J2(n, n);
          one.iteration_matrix_dense(0.3, 123.4, y.data(), yp.data(), J1.data());
          system.iteration_matrix_dense(0.3, 123.4, y.data(), yp.data(), J2.data());
          CHECK(differing(J1.data(), J2.data(), n * n) == 0);
          // The projection from the perturbed state (project_coordinates, v
          // onto G v = 0 in the Lagrange form, then the consistent start).
          Eigen::VectorXd yq1 = y, ypq1 = yp, yq2 = y, ypq2 = yp;
          dae->project(one.chart(), 0.3, yq1, ypq1);
          system.project(0.3, yq2, ypq2);
          CHECK(differing(yq1.data(), yq2.data(), n) == 0);
          CHECK(differing(ypq1.data(), ypq2.data(), n) == 0);
          ++combinations;
        }
  CHECK(combinations == 72);
}

TEST_SUITE_END();
