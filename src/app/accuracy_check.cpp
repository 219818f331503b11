// The accuracy check every run gets: see include/rigidae/app/accuracy_check.hpp.
#include "rigidae/app/accuracy_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Limits, as multiples of the tolerance tau. Measured on
// problems/dzhanibekov.toml (tests/unit/test_accuracy_check.cpp) and the
// shipped scenes; docs/accuracy_check.md gives the numbers.
//
// Invariants (energy, momenta): a run that keeps the local error of every
// step below tau changes an invariant by about tau per step only when the
// errors add up coherently; BDF's errors are mostly coherent (it damps), so
// the drift grows with the number of steps. Runs whose answers were right
// drifted up to PLACEHOLDER tau; the runs that lost the flip phase drifted
// PLACEHOLDER tau and more.
constexpr double kInvariantLimit = 1e3;
// Constraints: PLACEHOLDER
constexpr double kConstraintLimit = 1e3;

}  // namespace

InvariantMonitor::InvariantMonitor(const DaeSystem& dae, const Scene& scene, RecordingSink& recorder)
    : recorder_(recorder), body_(dae.body()) {
  d_ = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  checked_ = !scene.multibody.has_value();
  constrained_ = dae.representation().nc() > 0;
  const RigidBodyModel& b = body_;
  const double T0 = b.kinetic_energy(scene.omega0_B);
  const double exchange = b.mass * b.gravity_W.norm() * b.c_B.norm();
  e_scale_ = T0 + exchange > 0 ? T0 + exchange : 1.0;
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(b.J_B);
  const double j_min = eig.eigenvalues().minCoeff(), j_max = eig.eigenvalues().maxCoeff();
  l_scale_ = std::sqrt(2.0 * j_max * e_scale_);
  w_scale_ = std::sqrt(2.0 * e_scale_ / j_min);
  e0_ = T0 + b.potential_energy(scene.R0_WB);
  L0_W_ = scene.R0_WB * (b.J_B * scene.omega0_B);
  lz0_ = b.up_W.dot(L0_W_);
  // No torque about the reference point: gravity absent or acting at it.
  full_momentum_ = exchange == 0.0;
  d_.tolerance = scene.solver.rtol + scene.solver.atol / std::min(1.0, w_scale_);
  if (checked_) {
    d_.energy = 0.0;
    (full_momentum_ ? d_.angular_momentum : d_.vertical_angular_momentum) = 0.0;
    if (constrained_) d_.constraint_position = d_.constraint_velocity = 0.0;
  }
}

void InvariantMonitor::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  recorder_.on_step(t, h, order, y);
  if (!checked_) return;
  const Observation& o = recorder_.extremes().last;  // this step's, just observed
  d_.energy = std::max(d_.energy, std::abs(o.energy - e0_) / e_scale_);
  if (full_momentum_) {
    const Vec3 L_W = so3::quaternion_to_matrix(o.q_WB) * (body_.J_B * o.omega_B);
    d_.angular_momentum = std::max(d_.angular_momentum, (L_W - L0_W_).norm() / l_scale_);
  } else {
    d_.vertical_angular_momentum =
        std::max(d_.vertical_angular_momentum, std::abs(o.vertical_momentum - lz0_) / l_scale_);
  }
  if (constrained_) {
    d_.constraint_position = std::max(d_.constraint_position, o.drift.position);
    d_.constraint_velocity = std::max(d_.constraint_velocity, o.drift.velocity / w_scale_);
  }
}

std::vector<AccuracyWarning> InvariantMonitor::warnings() const {
  std::vector<AccuracyWarning> w;
  auto check = [&](const char* quantity, double drift, double factor, const char* what) {
    if (std::isnan(drift)) return;
    const double limit = factor * d_.tolerance;
    if (!(drift > limit) && std::isfinite(drift)) return;
    w.push_back({quantity, drift, limit, factor, d_.tolerance,
                 fmt::format("{} drifted {:.2e} ({}), {:.3g} x the tolerance {:.2e} (limit {:g} x); the "
                             "results may be far less accurate than the tolerance suggests",
                             quantity, drift, what, drift / d_.tolerance, d_.tolerance, factor)});
  };
  check("energy", d_.energy, kInvariantLimit, "relative to the kinetic plus exchangeable energy");
  check("angular_momentum", d_.angular_momentum, kInvariantLimit, "|L - L0| relative to the largest momentum");
  check("vertical_angular_momentum", d_.vertical_angular_momentum, kInvariantLimit,
        "relative to the largest momentum");
  check("constraint_position", d_.constraint_position, kConstraintLimit, "|Phi(q)|");
  check("constraint_velocity", d_.constraint_velocity, kConstraintLimit,
        "|dPhi/dt| relative to the largest angular speed");
  return w;
}

std::string warnings_cell(const std::vector<AccuracyWarning>& w) {
  std::string s;
  for (const AccuracyWarning& a : w)
    s += fmt::format("{}{} {:.2g} tol", s.empty() ? "" : "; ", a.quantity, a.drift / a.tolerance);
  return s;
}

}  // namespace rigidae
