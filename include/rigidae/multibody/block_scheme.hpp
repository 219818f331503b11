#pragma once
// The six constraint schemes of schemes/ stated per block kind, for an
// assembler that loops over constraint blocks (multibody.md, "Constraint
// blocks and kinds"). A scheme says, for each kind, which multiplier groups a
// block carries and which levels its rows combine:
//   rows = w_P Phi + w_V (velocity level) + w_A (G v' - gamma)
// velocity level: G v (Force) or Phi_q q' (Kinematic).
// Force blocks (joints in both forms, internal blocks in the Lagrange form)
// act through G^T lambda in the dynamics; mu (GGL) through q' = N v - Phi_q^T mu.
// Kinematic blocks (|q| = 1, R^T R = I in the Euler form) act through mu only.
//
//   scheme      Force: lambda rows          mu rows   Kinematic: mu rows
//   index3      Phi                         -         Phi
//   index2      G v                         -         Phi_q q'
//   index1      G v' - gamma                -         (none: the ODE)
//   baumgarte   G v'-gamma + 2a G v + b^2 Phi -       Phi_q q' + a Phi
//   ggl         G v                         Phi       Phi
//   projection  G v' - gamma                -         (none) + projection after steps
// Same meaning as src/schemes (read each file's header there).
#include <string>
#include <vector>

namespace rigidae::multibody {

struct LevelWeights {
  double position = 0.0, velocity = 0.0, acceleration = 0.0;
};

struct KindRows {
  bool lambda = false, mu = false;
  LevelWeights lambda_rows, mu_rows;
};

struct BlockScheme {
  std::string name;
  KindRows force, kinematic;
  bool index3 = false;      // v leaves the error test when Force blocks exist
  bool projection = false;  // the state is projected after steps
};

// Baumgarte gains a, b (1/s) are used by "baumgarte" only. InputError for an
// unknown name, listing the valid ones.
BlockScheme make_block_scheme(const std::string& name, double a, double b);

}  // namespace rigidae::multibody
