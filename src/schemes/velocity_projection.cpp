// The projection scheme's velocity step for one body (body_rows.hpp): the
// velocity nearest to v in kinetic energy with G v = 0, by the Schur
// complement of M (dense; M is the body's positive definite mass matrix):
//   v - M^-1 G^T (G M^-1 G^T)^-1 G v.
// Used by the multibody model's projection for bodies not joined to others
// (a one-body scene's body among them); the ODE form's per-body path has its
// own (BodyOde::project, which also handles a singular M).
#include "rigidae/schemes/body_rows.hpp"

namespace rigidae::schemes {

void project_velocities(const StandardTerms& terms, VecV& v) {
  const auto M = terms.M.ldlt();
  const MatCV MinvGt = M.solve(terms.G.transpose()).transpose();  // (M^-1 G^T)^T, nc x nv
  const MatCV& G = terms.G;
  const BoundedMat<kMaxConstraints, kMaxConstraints> S = G * MinvGt.transpose();
  v -= MinvGt.transpose() * S.ldlt().solve(G * v);
}

}  // namespace rigidae::schemes
