// Exact iteration matrices of a one-body scene (as every scene runs: a
// system of one pivoted body, MultibodyProblem(one_body_system(scene))):
// equal to central differences in every representation x scheme, in
// consistent and inconsistent states and near an Euler-angle chart switch;
// the sparse values are the dense matrix's on the pattern, which holds every
// nonzero; what they change in a run (same trajectory, fewer residual
// evaluations); KLU gives the dense trajectory; the hot path allocates
// nothing.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "alloc_counter.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

// Every registered coordinates: a new representation is checked here unchanged.
const std::vector<Coordinates> kAllCoordinates = all_coordinates();
const Equations kAllEquations[] = {Equations::Lagrange, Equations::Euler};

// Largest entry-wise difference of two n x n matrices, relative to the
// largest entry of the same row (rows are equations with their own units).
double row_relative_difference(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  double worst = 0.0;
  for (int i = 0; i < A.rows(); ++i) {
    const double scale = std::max({A.row(i).cwiseAbs().maxCoeff(), B.row(i).cwiseAbs().maxCoeff(), 1e-300});
    worst = std::max(worst, (A.row(i) - B.row(i)).cwiseAbs().maxCoeff() / scale);
  }
  return worst;
}

struct MatrixPair {
  Eigen::MatrixXd exact, central;
};

// The reference: dF/dy + cj dF/dy' by central differences, Richardson-
// extrapolated, (4 D(d/2) - D(d)) / 3 with D(d) = (F(+d) - F(-d)) / 2d,
// independent of the DAE's own difference quotients. Its error is O(d^4)
// truncation plus ~eps |F| / d round-off: with d = 1e-3 max(1, |y_j|) both
// are ~1e-12 of a row's scale where the derivatives vary on a scale of 1,
// and grow like (d / margin)^4 near an Euler-angle singularity.
// Near a singularity the step shrinks with `scale` (the margin).
Eigen::MatrixXd richardson_matrix(multibody::MultibodyProblem& p, double t, double cj, const Eigen::VectorXd& y,
                                  const Eigen::VectorXd& yp, double scale) {
  const int n = p.size();
  Eigen::MatrixXd J(n, n);
  Eigen::VectorXd Fp(n), Fm(n);
  const auto difference = [&](Eigen::VectorXd& x, int j, double d, bool in_yp) {
    const double xj = x(j);
    x(j) = xj + d;
    REQUIRE(p.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fp.data()));
    x(j) = xj - d;
    REQUIRE(p.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fm.data()));
    x(j) = xj;
    return Eigen::VectorXd((Fp - Fm) / (2.0 * d));
  };
  Eigen::VectorXd yy = y, yyp = yp;
  for (int j = 0; j < n; ++j) {
    const double d = 1e-3 * scale * std::max(1.0, std::abs(y(j)));
    J.col(j) = (4.0 * difference(yy, j, 0.5 * d, false) - difference(yy, j, d, false)) / 3.0;
    const double dp = 1e-3 * scale * std::max(1.0, std::abs(yp(j)));
    J.col(j) += cj * (4.0 * difference(yyp, j, 0.5 * dp, true) - difference(yyp, j, dp, true)) / 3.0;
  }
  return J;
}

// The sparse values spread onto an n x n matrix (zero off the pattern).
Eigen::MatrixXd spread(const SparsityPattern& pattern, const Eigen::VectorXd& values, int n) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c)
    for (std::int64_t k = pattern.col_start[c]; k < pattern.col_start[c + 1]; ++k) M(pattern.rows[k], c) = values(k);
  return M;
}

// The exact dense matrix against differences; the sparse values must be the
// dense matrix's entries on the pattern, bit for bit, and zero off it.
MatrixPair both_matrices(multibody::MultibodyProblem& p, double t, double cj, const Eigen::VectorXd& y,
                         const Eigen::VectorXd& yp, double scale) {
  const int n = p.size();
  MatrixPair m{Eigen::MatrixXd(n, n), richardson_matrix(p, t, cj, y, yp, scale)};
  p.iteration_matrix_dense(t, cj, y.data(), yp.data(), m.exact.data());
  Eigen::VectorXd values(p.sparsity().nnz());
  p.iteration_matrix_sparse(t, cj, y.data(), yp.data(), values.data());
  CHECK((spread(p.sparsity(), values, n) - m.exact).cwiseAbs().maxCoeff() == 0.0);
  return m;
}

// Measured largest row-relative difference: 1.2e-11 over every
// representation and scheme, 1.1e-10 near the Euler-angle singularities.
// 1e-8 leaves a factor ~100 above that and stays far below what a wrong term
// does (dropping one term of d(M a)/dq changed its rows by 0.5 relative).
constexpr double kMatrixTolerance = 1e-8;

// Random states around a consistent start of the asymmetric top: the start
// itself, then q, v, multipliers, q' and v' moved by up to 0.05, 0.1, 0.15
// times `scale` (off the manifold and inconsistent), at several cj.
void check_states(multibody::MultibodyProblem& p, std::mt19937& rng, double scale, double& worst) {
  Eigen::VectorXd y0, yp0;
  p.initial_state(0.0, y0, yp0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = p.size();
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd y = y0, yp = yp0;
    if (k > 0) {
      const double size = 0.05 * k * scale;
      for (int i = 0; i < n; ++i) {
        y(i) += size * u(rng) * std::max(1.0, std::abs(y0(i)));
        yp(i) += size * u(rng) * std::max(1.0, std::abs(yp0(i)));
      }
    }
    for (const double cj : {0.0, 3.7, 2.5e3}) {
      CAPTURE(k);
      CAPTURE(cj);
      const MatrixPair m = both_matrices(p, 0.3, cj, y, yp, scale);
      const double d = row_relative_difference(m.exact, m.central);
      worst = std::max(worst, d);
      CHECK(d < kMatrixTolerance);
    }
  }
}

// Records orientation (as a quaternion) on the output grid.
class OrientationSink final : public StepSink {
 public:
  explicit OrientationSink(const multibody::MultibodyProblem& problem) : problem_(problem) {}
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double, const Eigen::VectorXd& y) override { q_.push_back(problem_.body_orientation(0, y.data())); }
  const std::vector<Vec4>& orientations() const { return q_; }

 private:
  const multibody::MultibodyProblem& problem_;
  std::vector<Vec4> q_;
};

struct Run {
  RunResult result;
  std::vector<Vec4> orientations;
  double evals_per_step() const {
    const IdaCounters& c = result.counters;
    return static_cast<double>(c.residual_evals + c.jacobian_residual_evals) / static_cast<double>(c.steps);
  }
};

Run run(Scene s, const std::string& jacobian, const std::string& linear_solver = "dense") {
  s.solver.jacobian = jacobian;
  s.solver.linear_solver = linear_solver;
  // The scene as every scene runs: a system of one pivoted body.
  multibody::MultibodyProblem problem(one_body_system(s));
  OrientationSink sink(problem);
  Run r;
  r.result = integrate(problem, s.solver, s.time, sink);
  r.orientations = sink.orientations();
  return r;
}

double largest_angle_between(const Run& a, const Run& b) {
  REQUIRE(a.orientations.size() == b.orientations.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.orientations.size(); ++i)
    worst = std::max(worst, so3::quaternion_distance(a.orientations[i], b.orientations[i]));
  return worst;
}

// Largest angle, over the output grid, to the closed-form solution.
double largest_error(const Run& r, const Scene& s) {
  const std::unique_ptr<exact::ExactSolution> truth = exact::make_exact_solution(s, nullptr);
  REQUIRE(truth);
  const std::vector<double> grid = output_grid(s.time);
  REQUIRE(grid.size() == r.orientations.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i)
    worst = std::max(worst, so3::quaternion_distance(so3::matrix_to_quaternion(truth->at(grid[i]).R_WB),
                                                     r.orientations[i]));
  return worst;
}

// The heavy top over a tenth of a second: ~15 turns of the spin.
Scene short_heavy_top(Coordinates c, Equations e, const std::string& scheme) {
  Scene s = test::heavy_top_scene(c, e, scheme);
  s.time = {0.0, 0.1, 0.01};
  s.solver.rtol = s.solver.atol = 1e-8;
  return s;
}

}  // namespace

TEST_CASE("exact iteration matrix = central differences: every representation and scheme") {
  std::mt19937 rng(20240607);
  double worst = 0.0;
  int combinations = 0;
  for (Coordinates c : kAllCoordinates)
    for (Equations e : kAllEquations)
      for (const std::string& scheme : scheme_names()) {
        Scene s = test::asymmetric_top_scene(c, e, scheme);
        s.omega0_B *= 20.0;  // rates of the heavy top's size
        multibody::MultibodyProblem p(one_body_system(s));
        CAPTURE(p.bodies()[0].rep->name());
        CAPTURE(scheme);
        check_states(p, rng, 1.0, worst);
        ++combinations;
      }
  CHECK(combinations == static_cast<int>(kAllCoordinates.size() * 2 * scheme_names().size()));
  MESSAGE("largest row-relative difference: " << worst);
}

TEST_CASE("exact iteration matrix = central differences: Euler angles near and across a chart switch") {
  std::mt19937 rng(7);
  double worst = 0.0;
  for (Equations e : kAllEquations)
    for (const std::string seq : {"zxz", "zyx"})
      for (const double margin : {0.3, 0.1, 0.03}) {
        Scene s = test::asymmetric_top_scene(Coordinates::EulerAngles, e, "ggl");
        s.formulation.euler.sequence = so3::parse_euler_sequence(seq, false);
        // Middle angle where the margin |sin b| (proper) or |cos b| (Tait-Bryan) is `margin`.
        const bool proper = seq[0] == seq[2];
        const double b = proper ? std::asin(margin) : std::acos(margin);
        s.R0_WB = so3::euler_to_matrix(*s.formulation.euler.sequence, Vec3(0.4, b, -1.1));
        // Below every margin tried: the start stays in the scene's chart.
        s.formulation.euler.switch_threshold = 0.01;
        multibody::MultibodyProblem p(one_body_system(s));
        const Representation& rep = *p.bodies()[0].rep;
        CAPTURE(rep.name());
        CAPTURE(seq);
        CAPTURE(margin);
        REQUIRE(rep.chart_name() == seq);
        Eigen::VectorXd y, yp;
        p.initial_state(0.0, y, yp);
        const multibody::UnknownGroup& qg = p.groups()[p.bodies()[0].q_group];
        REQUIRE(rep.chart_margin(y.segment(qg.offset, qg.size)) == doctest::Approx(margin));
        // Moves and difference steps in proportion to the margin.
        check_states(p, rng, margin, worst);

        // Across the switch: above every margin tried, the start is written
        // in the most regular chart; the matrices again, there.
        s.formulation.euler.switch_threshold = 0.99;
        multibody::MultibodyProblem other(one_body_system(s));
        Eigen::VectorXd y2, yp2;
        other.initial_state(0.0, y2, yp2);
        CHECK(other.bodies()[0].rep->chart_name() != seq);
        // The same orientation in the new chart.
        CHECK(so3::quaternion_distance(other.body_orientation(0, y2.data()), p.body_orientation(0, y.data())) < 1e-12);
        for (const double cj : {0.0, 40.0}) {
          const MatrixPair m = both_matrices(other, 0.0, cj, y2, yp2, margin);
          const double d = row_relative_difference(m.exact, m.central);
          worst = std::max(worst, d);
          CHECK(d < kMatrixTolerance);
        }
      }
  MESSAGE("largest row-relative difference: " << worst);
}

TEST_CASE("residual and exact iteration matrix allocate nothing") {
  for (Coordinates c : kAllCoordinates)
    for (Equations e : kAllEquations)
      for (const std::string& scheme : scheme_names()) {
        const Scene s = test::asymmetric_top_scene(c, e, scheme);
        multibody::MultibodyProblem p(one_body_system(s));
        Eigen::VectorXd y, yp;
        p.initial_state(0.0, y, yp);
        const int n = p.size();
        Eigen::VectorXd F(n);
        Eigen::MatrixXd J(n, n);
        Eigen::VectorXd values(p.sparsity().nnz());
        test::start_counting_allocations();
        p.residual(0.1, y.data(), yp.data(), F.data());
        p.iteration_matrix_dense(0.1, 50.0, y.data(), yp.data(), J.data());
        p.iteration_matrix_sparse(0.1, 50.0, y.data(), yp.data(), values.data());
        const long allocations = test::stop_counting_allocations();
        CAPTURE(p.bodies()[0].rep->name());
        CAPTURE(scheme);
        CHECK(allocations == 0);
        // The counter does see allocations (so that 0 means something).
        test::start_counting_allocations();
        const Eigen::VectorXd copy = F;
        CHECK(test::stop_counting_allocations() == 1);
      }
}

TEST_CASE("exact Jacobians: the trajectory of central differences, with fewer residual evaluations per step") {
  long steps[2] = {0, 0}, evals[2] = {0, 0};  // central, exact
  for (Coordinates c : kAllCoordinates)
    for (Equations e : kAllEquations)
      for (const std::string& scheme : scheme_names()) {
        if (!has_constraints(c) && scheme != "ggl") continue;
        const Scene s = short_heavy_top(c, e, scheme);
        const Run central = run(s, "central");
        const Run exact = run(s, "exact");
        CAPTURE(to_string(c) + "/" + to_string(e) + "/" + scheme);
        REQUIRE(central.result.status == RunStatus::Success);
        REQUIRE(exact.result.status == RunStatus::Success);
        const double error_central = largest_error(central, s);
        // Newton converges to the same solution whatever the iteration
        // matrix; the runs differ only where IDA's step and order choices
        // do. They differ by no more than 100 rtol or twice the central
        // run's own error against the closed form (measured: up to 7e-7 rad;
        // 2.4e-3 for the uncontrolled index-3 Lagrange form, whose own error
        // is 1.6e-3).
        const double angle = largest_angle_between(central, exact);
        CHECK(angle <= std::max(100 * s.solver.rtol, 2.0 * error_central));
        // No residual evaluation is spent on the matrix, and Newton does not
        // need more iterations: measured per-combination ratios 0.07 to 0.69,
        // the largest for the ODE forms, which rarely refresh the matrix.
        CHECK(exact.result.counters.jacobian_residual_evals == 0);
        CHECK(exact.evals_per_step() <= 0.75 * central.evals_per_step());
        steps[0] += central.result.counters.steps;
        steps[1] += exact.result.counters.steps;
        evals[0] += central.result.counters.residual_evals + central.result.counters.jacobian_residual_evals;
        evals[1] += exact.result.counters.residual_evals;
      }
  // Over all combinations: measured 9.7 -> 2.0 residual evaluations per step.
  const double per_step_central = static_cast<double>(evals[0]) / static_cast<double>(steps[0]);
  const double per_step_exact = static_cast<double>(evals[1]) / static_cast<double>(steps[1]);
  CHECK(per_step_exact <= 0.5 * per_step_central);
}

TEST_CASE("KLU on the exact Jacobian's sparse pattern: the dense trajectory") {
  for (const auto& [c, e] : {std::pair{Coordinates::Linear, Equations::Lagrange},
                             std::pair{Coordinates::Quaternion, Equations::Euler},
                             std::pair{Coordinates::EulerAngles, Equations::Lagrange}}) {
    const Scene s = short_heavy_top(c, e, "ggl");
    CAPTURE(to_string(c) + "/" + to_string(e));
    const Run dense = run(s, "exact", "dense");
    const Run klu = run(s, "exact", "klu");
    REQUIRE(dense.result.status == RunStatus::Success);
    REQUIRE(klu.result.status == RunStatus::Success);
    // Another pivoting order changes round-off only, but index-2 iteration
    // matrices (condition ~1/h^2) amplify it into other step choices: the
    // same bound as for exact vs central (measured 3e-12 and 5e-10 rad, and
    // 3e-6 in linear/lagrange, whose own error is 5e-6).
    const double angle = largest_angle_between(dense, klu);
    CHECK(angle <= std::max(100 * s.solver.rtol, 2.0 * largest_error(dense, s)));
    CHECK(klu.result.counters.jacobian_evals > 0);
  }
}

TEST_CASE("the sparse pattern holds every nonzero of the exact iteration matrix") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Coordinates c : kAllCoordinates)
    for (Equations e : kAllEquations)
      for (const std::string& scheme : scheme_names()) {
        const Scene s = test::asymmetric_top_scene(c, e, scheme);
        multibody::MultibodyProblem p(one_body_system(s));
        const int n = p.size();
        Eigen::VectorXd y, yp;
        p.initial_state(0.0, y, yp);
        for (int i = 0; i < n; ++i) y(i) += 0.1 * u(rng), yp(i) += 0.1 * u(rng);
        const Eigen::MatrixXd J = richardson_matrix(p, 0.0, 7.0, y, yp, 1.0);
        CAPTURE(p.bodies()[0].rep->name());
        CAPTURE(scheme);
        // In the pattern: 1 where an entry may be nonzero.
        const Eigen::MatrixXd in_pattern =
            spread(p.sparsity(), Eigen::VectorXd::Ones(p.sparsity().nnz()), n);
        int outside = 0;
        for (int r = 0; r < n; ++r)
          for (int col = 0; col < n; ++col)
            if (in_pattern(r, col) == 0.0 && J(r, col) != 0.0) ++outside;
        CHECK(outside == 0);
      }
}

TEST_CASE("scene keys solver.jacobian and solver.linear_solver") {
  const std::string base =
      "schema_version = 1\n[body]\nmass = 2.0\ninertia_principal = [2.0, 3.0, 4.0]\n"
      "[initial]\nquaternion = [1.0, 0.0, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 1.0]\n[time]\nend = 1.0\n";
  const Scene s = io::parse_scene(base + "[solver]\njacobian = \"exact\"\nlinear_solver = \"klu\"\n", "scene.toml");
  CHECK(s.solver.jacobian == "exact");
  CHECK(s.solver.linear_solver == "klu");
  const auto error_of = [&](const std::string& solver) -> std::string {
    try {
      io::parse_scene(base + "[solver]\n" + solver, "scene.toml");
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string bad_jacobian = error_of("jacobian = \"analytic\"\n");
  CHECK(bad_jacobian.rfind("scene.toml:11:12: error:", 0) == 0);
  CHECK(bad_jacobian.find("exact") != std::string::npos);
  const std::string bad_solver = error_of("linear_solver = \"lapack\"\n");
  CHECK(bad_solver.rfind("scene.toml:11:17: error:", 0) == 0);
  CHECK(bad_solver.find("klu") != std::string::npos);
  const std::string dq_klu = error_of("jacobian = \"ida_dq\"\nlinear_solver = \"klu\"\n");
  CHECK(dq_klu.rfind("scene.toml:12:17: error:", 0) == 0);
  CHECK(dq_klu.find("\"exact\" or \"central\"") != std::string::npos);
}

TEST_SUITE_END();
