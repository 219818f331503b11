#pragma once
// Constraint residuals of a state: position level |Phi(q)|, velocity level
// |G v| (Force kind) or |Phi_q N v| = |d/dt Phi| along the kinematics
// (Kinematic kind). Euclidean norms; zero when there are no constraints.

namespace rigidae {

struct ConstraintDrift {
  double position = 0.0;
  double velocity = 0.0;
};

}  // namespace rigidae
