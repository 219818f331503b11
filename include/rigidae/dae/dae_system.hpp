#pragma once
// The assembled DAE F(t, y, y') = 0 for one scene: a representation (the
// equations in some coordinates) combined with a constraint scheme (how the
// constraints enter). Knows nothing about IDA.
#include <memory>
#include <string>
#include <vector>

#include "rigidae/coords/representation.hpp"
#include "rigidae/model/rigid_body.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/schemes/constraint_drift.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/solver/problem.hpp"

namespace rigidae {


// Immutable once built: the representation in each of its charts, the
// scheme, the layout of unknowns and the sparse pattern. What a run changes
// besides y is the chart its coordinates are written in (Euler angles: the
// sequence), which the caller keeps (SingleBodyProblem) and passes in;
// scratch lives on the stack of each call (fixed-size, no allocation).
class DaeSystem {
 public:
  // The body, its equations in the chart the run starts in, and the scheme:
  // nothing else of the scene.
  DaeSystem(RigidBodyModel body, std::unique_ptr<Representation> rep, std::unique_ptr<ConstraintScheme> scheme);

  const UnknownLayout& layout() const { return layout_; }
  int size() const { return layout_.size(); }
  // The chart a run starts in.
  int start_chart() const { return start_chart_; }
  // The representation in chart c; representation() is the start chart's
  // (names, sizes and constraint kind are the same in every chart).
  const Representation& representation(int chart) const { return *charts_[static_cast<std::size_t>(chart)]; }
  const Representation& representation() const { return representation(start_chart_); }
  const ConstraintScheme& scheme() const { return *scheme_; }
  const RigidBodyModel& body() const { return body_; }

  // The hot path: F = F(t, y, y') with q in chart `chart`; arrays of size
  // size(). Allocates nothing.
  void residual(int chart, double t, const double* y, const double* yp, double* F) const;

  // The iteration matrix dF/dy + cj dF/dy' (column-major n x n into J),
  // exact: the representation's term derivatives assembled by the scheme.
  // Allocates nothing.
  void iteration_matrix(int chart, double t, double cj, const double* y, const double* yp, double* J) const;
  // The same matrix's values on sparsity()'s pattern, in its order: the
  // scheme writes straight into them (no dense n x n in between).
  void iteration_matrix_sparse(int chart, double t, double cj, const double* y, const double* yp,
                               double* values) const;

  // Whether entry (row, col) of the iteration matrix can be nonzero in any
  // state: multipliers enter only through Phi_q^T mu (kinematic rows) and
  // G^T lambda (dynamic rows), and no constraint row depends on them.
  bool structurally_nonzero(int row, int col) const;
  // Those entries in compressed sparse columns, built once: the columns of
  // q and v whole, then G^T's block (lambda), then Phi_q^T's (mu); the
  // layout IterationMatrixView's three blocks take in a values array.
  const SparsityPattern& sparsity() const { return pattern_; }

  // A consistent (y, y') at t for a physical state; see ConstraintScheme::consistent_start.
  void consistent_state(int chart, double t, const Mat3& R_WB, const Vec3& omega_B, Eigen::VectorXd& y,
                        Eigen::VectorXd& yp) const;
  // Keeps q, v of y and recomputes the multipliers and y' consistently.
  void make_consistent(int chart, double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const;

  // Re-expresses (y, y') at t in the chart most regular there and makes it
  // consistent. Returns that chart (`chart` itself, y untouched, when it
  // already is the most regular).
  int change_chart(int chart, double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const;

  // IDA's id vector: 1 for differential unknowns (q, v), 0 for algebraic
  // ones (multipliers). IDA reads it only to drop id-0 components from the
  // error test (IDASetSuppressAlg) and in IDACalcIC, which rigidae does not
  // call; so an index-3 scheme marks v with 0 to leave v out of the test.
  Eigen::VectorXd differential_id() const;
  // Names of the multipliers in y's order, e.g. "lambda_norm", "mu_c12".
  std::vector<std::string> multiplier_names() const;

  ConstraintDrift drift(int chart, double t, const double* y) const;

  // Maps q of y onto the constraint manifold and v onto G(q) v = 0 in the
  // metric of M (Force kind), then makes (y, y') consistent at t.
  void project(int chart, double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const;

  // Views of q and v inside y.
  VecQ coordinates(const double* y) const;
  VecV velocities(const double* y) const;

 private:
  // The scheme's assembly into a view, zeroed by the caller.
  void assemble_iteration_matrix(int chart, double t, double cj, const double* y, const double* yp,
                                 IterationMatrixView& J) const;

  RigidBodyModel body_;
  std::vector<std::unique_ptr<const Representation>> charts_;  // chart_count() of them
  int start_chart_ = 0;
  std::unique_ptr<ConstraintScheme> scheme_;
  UnknownLayout layout_;
  SparsityPattern pattern_;
  // Where G^T's and Phi_q^T's blocks start in the sparse values.
  std::int64_t lambda_values_ = 0, mu_values_ = 0;
};

// Builds the DAE a scene's formulation names (InputError if unknown).
std::unique_ptr<DaeSystem> assemble_dae(const Scene& scene);

}  // namespace rigidae
