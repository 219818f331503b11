// Exact iteration matrices: equal to central differences in every
// representation x scheme, in consistent and inconsistent states and near an
// Euler-angle chart switch; what they change in a run (same trajectory,
// fewer residual evaluations); KLU gives the dense trajectory; the hot path
// allocates nothing.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "rigidae/dae/dae_system.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "test_scenes.hpp"

// Counts heap allocations on this thread while `g_count_allocations` is set.
// Interposes glibc's malloc family (Eigen allocates through std::malloc and
// operator new ends there too), forwarding to glibc's own entry points.
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
namespace {
thread_local bool g_count_allocations = false;
thread_local long g_allocations = 0;
}  // namespace
extern "C" void* malloc(std::size_t n) {
  if (g_count_allocations) ++g_allocations;
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t n, std::size_t size) {
  if (g_count_allocations) ++g_allocations;
  return __libc_calloc(n, size);
}
extern "C" void* realloc(void* p, std::size_t n) {
  if (g_count_allocations) ++g_allocations;
  return __libc_realloc(p, n);
}

using namespace rigidae;

namespace {

const Coordinates kAllCoordinates[] = {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear};
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
Eigen::MatrixXd richardson_matrix(const DaeSystem& dae, double t, double cj, const Eigen::VectorXd& y,
                                  const Eigen::VectorXd& yp, double scale) {
  const int n = dae.size();
  Eigen::MatrixXd J(n, n);
  Eigen::VectorXd Fp(n), Fm(n);
  const auto difference = [&](Eigen::VectorXd& x, int j, double d, bool in_yp) {
    const double xj = x(j);
    x(j) = xj + d;
    dae.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fp.data());
    x(j) = xj - d;
    dae.residual(t, in_yp ? y.data() : x.data(), in_yp ? x.data() : yp.data(), Fm.data());
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

MatrixPair both_matrices(const DaeSystem& dae, double t, double cj, const Eigen::VectorXd& y,
                         const Eigen::VectorXd& yp, double scale) {
  const int n = dae.size();
  MatrixPair m{Eigen::MatrixXd(n, n), richardson_matrix(dae, t, cj, y, yp, scale)};
  dae.iteration_matrix(t, cj, y.data(), yp.data(), m.exact.data());
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
void check_states(DaeSystem& dae, const Scene& s, std::mt19937& rng, double scale, double& worst) {
  Eigen::VectorXd y0, yp0;
  dae.consistent_state(0.0, s.R0_WB, s.omega0_B, y0, yp0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = dae.size();
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
      const MatrixPair m = both_matrices(dae, 0.3, cj, y, yp, scale);
      const double d = row_relative_difference(m.exact, m.central);
      worst = std::max(worst, d);
      CHECK(d < kMatrixTolerance);
    }
  }
}

// Records orientation (as a quaternion) on the output grid.
class OrientationSink final : public StepSink {
 public:
  explicit OrientationSink(const DaeSystem& dae) : dae_(dae) {}
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double, const Eigen::VectorXd& y) override {
    q_.push_back(dae_.representation().orientation(dae_.coordinates(y.data())));
  }
  void on_chart_switch(const ChartSwitch&) override {}
  void on_projection(double, const ConstraintDrift&) override {}
  const std::vector<Vec4>& orientations() const { return q_; }

 private:
  const DaeSystem& dae_;
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
  const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
  OrientationSink sink(*dae);
  Run r;
  r.result = integrate(*dae, s, sink);
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
  for (Coordinates c : kAllCoordinates)
    for (Equations e : kAllEquations)
      for (const std::string& scheme : scheme_names()) {
        Scene s = test::asymmetric_top_scene(c, e, scheme);
        s.omega0_B *= 20.0;  // rates of the heavy top's size
        const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
        CAPTURE(dae->representation().name());
        CAPTURE(scheme);
        check_states(*dae, s, rng, 1.0, worst);
      }
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
        const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
        CAPTURE(dae->representation().name());
        CAPTURE(seq);
        CAPTURE(margin);
        Eigen::VectorXd y, yp;
        dae->consistent_state(0.0, s.R0_WB, s.omega0_B, y, yp);
        REQUIRE(dae->representation().chart_margin(dae->coordinates(y.data())) == doctest::Approx(margin));
        // Moves and difference steps in proportion to the margin.
        check_states(*dae, s, rng, margin, worst);

        // Switch to the most regular chart, then the matrices again, there.
        VecQ q = dae->coordinates(y.data());
        VecV v = dae->velocities(y.data());
        const std::string before = dae->representation().chart_name();
        REQUIRE(dae->representation().change_chart(q, v));
        CHECK(dae->representation().chart_name() != before);
        y.head(3) = q;
        y.segment(3, 3) = v;
        dae->make_consistent(0.0, y, yp);
        for (const double cj : {0.0, 40.0}) {
          const MatrixPair m = both_matrices(*dae, 0.0, cj, y, yp, margin);
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
        const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
        Eigen::VectorXd y, yp;
        dae->consistent_state(0.0, s.R0_WB, s.omega0_B, y, yp);
        const int n = dae->size();
        Eigen::VectorXd F(n);
        Eigen::MatrixXd J(n, n);
        g_allocations = 0;
        g_count_allocations = true;
        dae->residual(0.1, y.data(), yp.data(), F.data());
        dae->iteration_matrix(0.1, 50.0, y.data(), yp.data(), J.data());
        g_count_allocations = false;
        CAPTURE(dae->representation().name());
        CAPTURE(scheme);
        CHECK(g_allocations == 0);
        // The counter does see allocations (so that 0 means something).
        g_allocations = 0;
        g_count_allocations = true;
        const Eigen::VectorXd copy = F;
        g_count_allocations = false;
        CHECK(g_allocations == 1);
      }
}
