#pragma once
// A one-body scene's run read as its records read it.
//
// A schema-1 scene runs as a system of one pivoted body
// (model/one_body_system.hpp) through MultibodyProblem, by IDA or by the
// ODE form. Its records (steps.csv's qw..qz, omega_B, the multipliers by
// the body's constraint names, drift, energy and the vertical momentum
// about the reference point) read the system through this view:
//   q, v        the body's rotation block, written in the chart it is in
//               now (the Euler-angle sequence changes at chart switches)
//   multipliers lambda (its own Force rows) then mu (its Kinematic or GGL
//               rows), named lambda_<row> and mu_<row> after the
//               representation's constraint names
//   drift       |Phi(q)| and |G v| (Force kind) or |Phi_q N v| (Kinematic),
//               Euclidean norms of the body's own block
//               (MultibodyProblem::projection_drift, which for a body
//               without joints is exactly that)
//   body()      the one-body model (inertia about the reference point,
//               gravity torque) that the energy and momentum are read with.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rigidae/coords/representation.hpp"
#include "rigidae/model/rigid_body.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/schemes/constraint_drift.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae {


class OneBodyView {
 public:
  // system: built from one_body_system(scene) and outliving the view;
  // scene: the one-body scene itself.
  OneBodyView(multibody::MultibodyProblem& system, const Scene& scene);

  multibody::MultibodyProblem& system() const { return system_; }
  // The rotation block in the chart the run is in now.
  const Representation& representation() const { return *system_.bodies().front().rep; }
  const RigidBodyModel& body() const { return body_; }

  VecQ coordinates(const double* y) const;
  VecV velocities(const double* y) const;
  int multiplier_offset() const { return multiplier_offset_; }
  int multiplier_count() const { return static_cast<int>(names_.size()); }
  const std::vector<std::string>& multiplier_names() const { return names_; }
  ConstraintDrift drift(double t, const double* y) const;

  // A consistent (y, y') of the system at t for a physical state (R_WB,
  // omega_B) written in the current chart: the multipliers and y' solved.
  void consistent_state(double t, const Mat3& R_WB, const Vec3& omega_B, Eigen::VectorXd& y,
                        Eigen::VectorXd& yp) const;

 private:
  multibody::MultibodyProblem& system_;
  RigidBodyModel body_;
  int q_offset_ = 0, v_offset_ = 0, multiplier_offset_ = 0;
  std::vector<std::string> names_;
};

}  // namespace rigidae
