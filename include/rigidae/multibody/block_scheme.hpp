#pragma once
// A constraint scheme as the multibody assembler reads it: the rows of
// schemes/ per block kind (rigidae/schemes/block_rows.hpp; multibody.md,
// "Constraint blocks and kinds"), plus the two things a scheme does outside
// the rows. The rows come from the scheme's own file in src/schemes
// (rows()), not restated here.
//   rows = w_A (G v' - gamma) + w_V (velocity level) + w_P Phi
// velocity level: G v (Force) or Phi_q q' (Kinematic).
// Force blocks (joints in both forms, internal blocks in the Lagrange form)
// act through G^T lambda in the dynamics; mu (GGL) through q' = N v - Phi_q^T mu.
// Kinematic blocks (|q| = 1, R^T R = I in the Euler form) act through mu only.
#include <string>

#include "rigidae/schemes/block_rows.hpp"

namespace rigidae::multibody {

struct BlockScheme {
  std::string name;
  KindRows force, kinematic;
  bool index3 = false;      // v leaves the error test when Force blocks exist
  bool projection = false;  // the state is projected after steps
};

// The registered scheme `name` (schemes/scheme.hpp) with Baumgarte gains a, b
// (1/s; used by "baumgarte" only). InputError for an unknown name, listing
// the valid ones.
BlockScheme make_block_scheme(const std::string& name, double a, double b);

}  // namespace rigidae::multibody
