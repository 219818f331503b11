#pragma once
// A constraint scheme: how a representation's standard-form terms become the
// residual rows F(t, y, y') = 0 that IDA integrates.
//
// Unknowns are laid out as y = (q | v | lambda | mu):
//   q, v     differential (IDA id 1)
//   lambda   force multipliers, one per constraint of a Force-kind representation
//   mu       kinematic multipliers (q' = N v - Phi_q^T mu), GGL-style
// Both multiplier groups are algebraic (id 0). The constraints come in
// blocks, each of one kind (block_rows.hpp); a scheme states per kind which
// multiplier groups a block carries and which levels its rows combine
// (rows()), and the assembler here loops over the blocks. A scheme also
// decides whether multipliers stay in the error test.
#include <memory>
#include <string>
#include <vector>

#include "rigidae/coords/representation.hpp"
#include "rigidae/schemes/block_rows.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae {

// When a drifting scheme maps the state back onto the constraint manifold.
struct ProjectionPolicy {
  bool enabled = false;
  bool every_step = false;  // after every accepted step, or only when the drift passes threshold
  double threshold = 0.0;   // on |Phi| and |G v| (or |dPhi/dt|)
};

// One block of constraints: its kind, its number of rows, what the scheme
// writes for that kind, and where its multiplier rows start (-1: no group).
struct ConstraintBlockLayout {
  ConstraintKind kind = ConstraintKind::None;
  int nr = 0;
  KindRows rows;
  int lambda_row = -1, mu_row = -1;
};

struct UnknownLayout {
  int nq = 0, nv = 0, n_lambda = 0, n_mu = 0;
  // One body has at most one block (none for Euler angles, and none when the
  // scheme writes no rows for its kind: index 1 in the Euler form).
  static constexpr int kMaxBlocks = 1;
  int n_blocks = 0;
  ConstraintBlockLayout blocks[kMaxBlocks];
  int q_offset() const { return 0; }
  int v_offset() const { return nq; }
  int lambda_offset() const { return nq + nv; }
  int mu_offset() const { return nq + nv + n_lambda; }
  int size() const { return nq + nv + n_lambda + n_mu; }
};

using VecRef = Eigen::Ref<Eigen::VectorXd>;
using ConstVecRef = Eigen::Ref<const Eigen::VectorXd>;
using MatRef = Eigen::Ref<Eigen::MatrixXd>;

// Where a scheme writes its iteration matrix. Multipliers enter only
// through G^T lambda (the dynamic rows) and Phi_q^T mu (the kinematic rows),
// and no constraint row depends on them, so the matrix is the columns of the
// state (q, v), which every row may touch, and two blocks. Views of a dense
// n x n matrix or of a sparse matrix's values on that pattern
// (the deleted DaeSystem's), so a sparse solver gets its values without a dense
// copy.
struct IterationMatrixView {
  MatRef state;   // n x (nq + nv): every row, the columns of q and v
  MatRef lambda;  // nv x n_lambda: the dynamic rows, the columns of lambda
  MatRef mu;      // nq x n_mu: the kinematic rows, the columns of mu
};

// What a scheme reads to assemble its exact iteration matrix at (t, y, y').
struct JacobianInputs {
  const Representation& rep;
  const StandardTerms& terms;    // at (q, v) of y
  const TermDerivatives& derivs;  // at (q, v) of y, M's with a = v' of y'
  const UnknownLayout& lay;
  const ConstVecRef& y;
  const ConstVecRef& yp;
  double cj;  // IDA's dF/dy' coefficient
};

// A number a scheme runs with, for reports (e.g. Baumgarte's gain "a", 1/s).
struct SchemeParameter {
  std::string name;
  double value = 0.0;
};

class ConstraintScheme {
 public:
  virtual ~ConstraintScheme() = default;

  virtual std::string name() const = 0;
  // The rows this scheme writes for a block of each kind.
  virtual SchemeRows rows() const = 0;
  // The unknowns for a representation: its constraints as one block of its
  // kind, with the multiplier groups rows() states for that kind.
  UnknownLayout layout(const Representation& rep) const;
  // True when multipliers must leave IDA's error test (index 2 and above).
  virtual bool suppress_multiplier_error_test() const = 0;
  // True when the velocities must leave it too (index 3 with blocks of this
  // kind, where v is index 2).
  virtual bool suppress_velocity_error_test(ConstraintKind /*kind*/) const { return false; }
  // The numbers this scheme runs with, as it uses them (defaults resolved).
  virtual std::vector<SchemeParameter> parameters() const { return {}; }
  // Whether and when the driver projects the state onto the manifold.
  virtual ProjectionPolicy projection() const { return {}; }
  // A note for the report when the scheme does something unusual for this
  // representation. Without constraints (Euler angles) every scheme is the
  // same ODE, and the note says so; otherwise it is constrained_note().
  std::string note(const Representation& rep) const;

  // The hot path: F(t, y, y') from the terms evaluated at (q, v) of y: the
  // kinematic and dynamic rows, then each block's rows as its kind says.
  void residual(const StandardTerms& terms, const UnknownLayout& lay, const ConstVecRef& y, const ConstVecRef& yp,
                VecRef F) const;

  // The hot path: the exact iteration matrix dF/dy + cj dF/dy' of residual()
  // (n x n), added into J, which the caller has zeroed.
  void iteration_matrix(const JacobianInputs& in, IterationMatrixView& J) const;

  // Given q, v in y (already on the constraint manifold), fills the
  // multipliers of y and all of yp so that the residual vanishes to round-off:
  // (v', lambda) from the constrained-acceleration system
  //   [M G^T; G 0] (v', lambda) = (f, gamma),
  // mu from d/dt Phi = Phi_q (N v - Phi_q^T mu) = 0 (zero on exact data),
  // q' = N v - Phi_q^T mu. A scheme with feedback starts on its own rows:
  // with lambda rows w_A (G v' - gamma) + w_V G v + w_P Phi = 0, the target
  // of G v' is gamma - (w_V G v + w_P Phi) / w_A; with mu rows of a
  // Kinematic block w_V Phi_q q' + w_P Phi = 0, Phi_q q' = -w_P Phi / w_V.
  void consistent_start(const StandardTerms& terms, const UnknownLayout& lay, VecRef y, VecRef yp) const;

 protected:
  // The note for a representation with constraints (empty by default).
  virtual std::string constrained_note(const Representation& /*rep*/) const { return {}; }
};

// What the schemes read of a run's settings, defaults resolved: a scheme's
// factory receives this, not the scene.
struct SchemeSettings {
  double baumgarte_a = 1.0, baumgarte_b = 1.0;  // 1/s (baumgarte)
  bool project_every_step = false;              // projection
  double projection_threshold = 0.0;            // projection: on |Phi| and |G v| (or |dPhi/dt|)
};
// A scene's, with the defaults of baumgarte_gains and projection_threshold (model/scene.hpp).
SchemeSettings scheme_settings(const Scene& scene);

// The registered schemes, by name.
std::unique_ptr<ConstraintScheme> make_scheme(const std::string& name, const SchemeSettings& settings);
// Every registered name, in the registry's order.
std::vector<std::string> scheme_names();

}  // namespace rigidae
