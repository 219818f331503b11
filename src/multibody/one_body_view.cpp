// A one-body scene's run read as its records read it (see
// include/rigidae/multibody/one_body_view.hpp).
#include "rigidae/multibody/one_body_view.hpp"

#include <fmt/format.h>

#include "rigidae/core/error.hpp"

namespace rigidae {

OneBodyView::OneBodyView(multibody::MultibodyProblem& system, const Scene& scene)
    : system_(system), body_(make_rigid_body_model(scene)) {
  if (system.bodies().size() != 1 || !system.bodies().front().pivoted() || system.blocks().size() > 1)
    throw SolverError("OneBodyView: the system is not one pivoted body without joints");
  const multibody::BodyModel& b = system.bodies().front();
  q_offset_ = system.groups()[b.q_group].offset;
  v_offset_ = system.groups()[b.v_group].offset;
  multiplier_offset_ = system.state_size();
  const std::vector<std::string> rows = b.rep->constraint_names();
  for (const multibody::ConstraintBlock& blk : system.blocks()) {
    // The groups follow the state in y: lambda's, then mu's.
    if (blk.lambda_group >= 0)
      for (int k = 0; k < system.groups()[blk.lambda_group].size; ++k) names_.push_back("lambda_" + rows[k]);
    if (blk.mu_group >= 0)
      for (int k = 0; k < system.groups()[blk.mu_group].size; ++k) names_.push_back("mu_" + rows[k]);
    if (blk.lambda_group >= 0 && blk.mu_group >= 0 &&
        system.groups()[blk.mu_group].offset < system.groups()[blk.lambda_group].offset)
      throw SolverError("OneBodyView: the body's mu come before its lambda in y");
  }
  if (multiplier_offset_ + static_cast<int>(names_.size()) != system.size())
    throw SolverError(fmt::format("OneBodyView: {} unknowns, {} state and {} multipliers", system.size(),
                                  multiplier_offset_, names_.size()));
}

VecQ OneBodyView::coordinates(const double* y) const {
  return Eigen::Map<const Eigen::VectorXd>(y + q_offset_, representation().nq());
}

VecV OneBodyView::velocities(const double* y) const {
  return Eigen::Map<const Eigen::VectorXd>(y + v_offset_, representation().nv());
}

ConstraintDrift OneBodyView::drift(double t, const double* y) const {
  if (representation().nc() == 0) return {};
  const auto [position, velocity] = system_.projection_drift(t, y);
  return {position, velocity};
}

void OneBodyView::consistent_state(double t, const Mat3& R_WB, const Vec3& omega_B, Eigen::VectorXd& y,
                                   Eigen::VectorXd& yp) const {
  VecQ q;
  VecV v;
  representation().from_physical(R_WB, omega_B, q, v);
  y.setZero(system_.size());
  yp.setZero(system_.size());
  y.segment(q_offset_, q.size()) = q;
  y.segment(v_offset_, v.size()) = v;
  system_.make_consistent(t, y, yp);
}

}  // namespace rigidae
