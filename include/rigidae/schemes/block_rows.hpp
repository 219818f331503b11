#pragma once
// What a constraint scheme writes for a block of constraints, per kind of
// block (multibody.md, "Constraint blocks and kinds"): what the schemes
// (src/schemes) state and the multibody assembler reads.
//
// A block's constraints Phi(q) = 0 are of one kind:
//   Force      held by forces: G^T lambda in the dynamics M v' = f - G^T lambda
//              (the Lagrange form's internal constraint, every joint);
//   Kinematic  kept by the kinematics q' = N v, with Phi_q N = 0 on the
//              manifold (the Euler form's |q| = 1, R^T R = I).
// A multiplier group (lambda, or GGL's mu in q' = N v - Phi_q^T mu) carries
// one row per constraint of the block, and its rows combine three levels:
//   rows = w_A (G v' - gamma) + w_V (velocity level) + w_P Phi
// velocity level: G v (Force kind) or Phi_q q' (Kinematic kind, d/dt Phi).
// Assemblers evaluate the levels in that order (acceleration, velocity,
// position), the order of Baumgarte's G v' - gamma + 2a G v + b^2 Phi.
#include "rigidae/coords/representation.hpp"

namespace rigidae {

struct LevelWeights {
  double position = 0.0, velocity = 0.0, acceleration = 0.0;
};

// Which multiplier groups a block of one kind carries, and their rows.
struct KindRows {
  bool lambda = false, mu = false;
  LevelWeights lambda_rows, mu_rows;
};

// A scheme's rows for each kind of block.
struct SchemeRows {
  KindRows force, kinematic;
};

}  // namespace rigidae
