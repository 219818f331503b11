#pragma once
// A mechanism (MultibodyProblem) as an ODE x' = f(t, x) for CVODE and
// ARKODE, x = the DAE's state (q | v) of every body, in the DAE's order.
//
// The MultibodyProblem must be assembled with an acceleration-level scheme
// (index1 or projection): its unknowns are then y = (q | v | lambda), no mu,
// and its residual is linear in (y'_state, lambda) with no lambda':
//   F(t, y, y') = A(q, v) [y'_state; lambda] + F(t, (q, v, 0), 0)
//   A = [I 0 0; 0 M G^T; 0 G 0]   (rows q, v, lambda; columns q', v', lambda)
// (MultibodyProblem::linear_part_sparse; src/multibody/linear_part.cpp). So
//   q'          = -F_q(t, (q, v, 0), 0)          = N(q) v
//   [M  G^T] [v'    ]   [-F_v(t, (q, v, 0), 0)]   [f    ]
//   [G  0  ] [lambda] = [-F_l(t, (q, v, 0), 0)] = [gamma]
// the saddle-point (KKT) system over every body's velocities and every
// joint's (and, Lagrange form, every body's internal) multipliers, solved at
// each evaluation: dense LU with partial pivoting or, sparse, by the Schur
// complement of the block-diagonal M (S = G M^-1 G^T by a sparse LDL^T:
// src/multibody/schur_saddle.hpp) with sparse LU of the whole matrix (KLU:
// pattern analysed once, refactorised in place) where that fails, chosen
// like the DAE's linear solver (solver.linear_solver; "auto" by the DAE's
// size). The sparse path writes its KKT block in place through the
// problem's sink remapped (JacobianSink::remapped), not through the whole
// iteration matrix's pattern. Measured on the 1000-link spherical chain
// (quaternion/euler/projection on ARKODE, callgrind): 36.5 M instructions
// per right-hand side with KLU through the whole pattern, 17.5 M now. The dense
// LU is a fixed-capacity loop (src/multibody/small_lu.hpp) up to 48 KKT
// unknowns (a few bodies: the pendulum's 11, the four-bar's 35), else
// Eigen's PartialPivLU, preallocated; both pivot alike and agree to round-off.
// The Euler form's |q| = 1, R^T R = I carry no multiplier in index1: the
// kinematics keep them up to the integration error.
//
// Rank: [M G^T; G 0] is regular while G has full row rank and M is positive
// definite on ker G. When a factorisation has a pivot below 1e-13 of the
// largest (KLU: after a refactorisation with the old pivot order, a fresh
// one with new pivots is tried first) or the solution is not finite, rhs()
// returns false: the integrator retries a smaller step, and fails with its
// own message if the loss of rank persists. Never a least-squares answer.
//
// Invariants (when there are constraint rows): Phi(q) = 0 of every block and
// G v = 0 of the Force blocks. drift() and project() are MultibodyProblem's
// (Gauss-Newton onto Phi = 0 with the least change in the mass metric, then
// v onto G v = 0 in the mass metric); project() allocates (sparse QR and LU),
// unlike the rest of the interface. project_error() is project()'s
// linearisation at x by a difference of two projections, (P(x + s e) -
// P(x)) / s with s |e| = 1e-6 max(1, |x|) (position and velocity parts
// alike; only at projections). Without the position part CVODE-BDF's error
// test keeps the correction of a threshold-triggered projection (up to
// 100 atol, normal to the manifold) and cuts the step to nothing.
//
// Decoupled bodies (MultibodyProblem::bodies_decoupled: no joints or
// drivers, every body pivoted, no force element acting on one; a one-body
// scene as one_body_system(scene) is such a system): the KKT matrix is block
// diagonal, one block per body, and the whole ODE form is taken body by body
// with the one-body arithmetic (schemes::BodyOde, schemes/body_ode.hpp):
// the Euler form through the representation's fixed-size kernel, the
// Lagrange form by the Schur complement of M (the saddle-point solve when M
// is singular), the projection onto each body's own manifold and its exact
// linearisation, the drift as the one-body rule (per body the 2-norms |Phi|,
// |G v|, the largest over bodies). A one-body scene then integrates bit for
// bit as the deleted one-body ODE form did (SingleBodyOde; same steps, same
// final state: tests/guard/pinned.json's ode_runs) at its cost (1.00x to 1.02x
// its instructions on the heavy top, where the KKT path costs up to 3.2x:
// docs/benchmarks.md). The right-hand sides of the two paths agree to
// round-off; their drift rules differ (the KKT path's max norms: drift()).
// A wider condition would also be safe, free bodies under gravity alone
// (their translation x'' = g decouples too), but it is not taken: a free
// body's rows are not one representation's, and the KKT path serves it.
//
// observe() gives the DAE layout (q | v | lambda) with lambda of the KKT
// solve at x (per body when decoupled), so the recorder and the
// accuracy monitor read ODE runs unchanged (joint reactions from lambda).
//
// Work (drivers and loads without a potential: MultibodyProblem::has_work):
// the state carries W, x = (q | v | W) with W' = P(t, x) the power of the
// drivers and loads (MultibodyProblem::work_rate at the KKT solution's
// multipliers), W(t0) = 0, integrated by the integrator's own stages and
// left out of its error test (atol 1e100: its weight is 1e-100), so the
// steps are those of (q | v). observe() appends W to the DAE layout, as
// entry n of y (WorkIntegral::follow), for the energy balance H - H0 - W.
// A quadrature of P over the accepted steps (what the DAE path does) is
// only as good as a degree-5 polynomial over the steps: on ARKODE's order-8
// steps on crank_slider_driven (31 steps per second) it reported an energy
// error of 2.2e-5 on a run 1e-13 from the closed form.
// Events (Euler-angle charts, one root function per body in Euler angles)
// and the torsion angles' branches are MultibodyProblem's, with the
// multipliers padded by zeros, on both paths.
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/body_ode.hpp"
#include "rigidae/solver/ode_problem.hpp"

namespace rigidae::multibody {

class KluSaddle;  // the sparse factorisation (multibody_ode.cpp)
class SmallLu;    // the small dense one (src/multibody/small_lu.hpp)
class SchurSaddle;  // the sparse Schur complement (src/multibody/schur_saddle.hpp)

class MultibodyOde final : public OdeProblem {
 public:
  // problem: assembled with index1 or projection (else InputError naming
  // `where` and the valid schemes); it must outlive this object.
  // sparse: KLU, else dense LU: a fixed-capacity one (small_lu.hpp) when
  // the KKT system has at most 48 unknowns and small_dense is set, else
  // Eigen's dynamic-size PartialPivLU (the general path; tests compare the two).
  // by_body: the per-body path when the bodies are decoupled (see above);
  // false keeps the KKT path whatever the system (tests compare the two).
  // schur: on the sparse path, the Schur complement of M (schur_saddle.hpp)
  // where M is block diagonal and positive definite, KLU elsewhere; false:
  // KLU always (tests compare the two).
  MultibodyOde(MultibodyProblem& problem, bool sparse, const std::string& where, bool small_dense = true,
               bool by_body = true, bool schur = true);
  ~MultibodyOde() override;

  int size() const override { return n_state_ + (integrates_work_ ? 1 : 0); }
  void initial_state(double t0, Eigen::VectorXd& x) override;
  void absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& x0,
                           Eigen::Ref<Eigen::VectorXd> out) const override;
  bool rhs(double t, const double* x, double* xdot) override;

  bool has_invariants() const override { return n_lambda_ > 0 || has_internal_; }
  OdeDrift drift(double t, const double* x) const override;
  void project(double t, double* x) override;
  void project_error(double t, const double* x, double* e) override;

  int observed_size() const override { return n_ + (integrates_work_ ? 1 : 0); }
  // Whether the state (and the observation) carries the work W.
  bool integrates_work() const { return integrates_work_; }
  void observe(double t, const double* x, Eigen::VectorXd& y) override;

  int event_count() const override { return problem_.event_count(); }
  void event_functions(double t, const double* x, double* g) override;
  StepAction on_event(double t, Eigen::VectorXd& x) override;
  void after_step(double t, const double* x) override;
  double stop_time_hint() const override;
  double bridge(double t, Eigen::VectorXd& x) override;
  void bridged_observation(double t, Eigen::VectorXd& y) override;
  std::vector<EventNote> take_events() override { return problem_.take_events(); }
  // The DAE's report at the state (x with zero multipliers): the formulation
  // and the rank of the constraint rows there.
  std::string describe_stall(double t, const double* x) override;

  // The multipliers of the last rhs() (DAE order), for tests: the KKT path only.
  const Eigen::VectorXd& multipliers() const { return lambda_; }
  // The per-body path runs (decoupled bodies and by_body).
  bool by_body() const { return by_body_; }
  bool sparse() const { return klu_ != nullptr; }
  // The fixed-capacity dense LU runs the KKT solve.
  bool small_dense() const { return small_ != nullptr; }
  // Size of the KKT system (velocities + multipliers).
  int saddle_size() const { return ns_; }
  // The last factorisation was the Schur complement's.
  bool schur() const { return schur_used_; }
  // The KKT solve's name for reports: "schur", "klu" or "dense".
  const char* kkt_solver() const { return schur_used_ ? "schur" : klu_ ? "klu" : "dense"; }
  // KLU: full factorisations (new pivot order) so far; 0 for dense.
  long fresh_factorisations() const;

 private:
  // Assembles and factorises the KKT matrix at (t, x) and sets rhs_ to its
  // right side, F0_ to F(t, (x, 0), 0). False if F0 is not finite or the
  // matrix is singular.
  bool factorise(double t, const double* x);
  // solution_ = K^-1 b with the last factorisation; false if not finite.
  bool solve(const Eigen::VectorXd& b);
  // rhs() but for one decoupled body: kept out of line (see rhs()).
  [[gnu::noinline]] bool rhs_general(double t, const double* x, double* xdot);

  // The per-body path: per body its one-body arithmetic, the offset of its
  // (q, v) in x (contiguous for a pivoted body: nx = 0) and of its own
  // block's multipliers in y (-1: none).
  bool by_body_ = false;
  bool single_body_ = false;  // by_body_ with one body, its (q, v) first in x
  mutable std::vector<schemes::BodyOde> body_ode_;  // mutable: drift() evaluates into its scratch
  std::vector<int> body_offset_, body_lambda_offset_;
  const Representation& body_rep(std::size_t i) const { return *problem_.bodies()[i].rep; }

  MultibodyProblem& problem_;
  int n_ = 0, n_state_ = 0, nv_ = 0, n_lambda_ = 0, ns_ = 0;
  bool integrates_work_ = false;  // x = (q | v | W): see above
  double last_work_ = 0.0;        // W of the last observation (for a bridged one)
  bool has_internal_ = false;
  std::vector<int> q_index_;  // the q entries of y
  std::vector<int> s_index_;  // the KKT unknowns' entries of y: velocities, then multipliers (ascending)
  // The pattern's entries that fall in the KKT block: position in the
  // pattern's values, and the (row, column) inside the KKT matrix.
  std::vector<std::int64_t> k_from_;
  std::vector<int> k_row_, k_col_;
  Eigen::VectorXd values_;      // A on the problem's pattern
  Eigen::VectorXd kkt_values_;  // the KKT block, compressed columns (KLU), then a scratch range
  Eigen::VectorXd solution_;    // (v', lambda) or a projection's (dv, nu)
  Eigen::VectorXd y_, yp_zero_, F0_, rhs_, lambda_;
  // Dense path.
  Eigen::MatrixXd K_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  // Small dense path (KKT order <= SmallLu::kCapacity).
  std::unique_ptr<SmallLu> small_;
  // Sparse path: the Schur complement while it applies, else KLU.
  void make_schur(const std::vector<int>& pos, const std::vector<int>& col_start, const std::vector<int>& rows);
  std::unique_ptr<KluSaddle> klu_;
  std::unique_ptr<JacobianSink> kkt_sink_;  // the problem's sink, writing the KKT block of kkt_values_ in place
  std::unique_ptr<SchurSaddle> schur_;
  bool schur_used_ = false;
  std::vector<int> lambda_block_, lambda_row_;  // per KKT multiplier: its block and row in it
  std::vector<char> active_;                    // per KKT multiplier: integrated (1) or set aside
  std::vector<double> inv_weight_;              // per KKT multiplier: 1 / w_A of its block
  // Scratch of drift() (const in the interface: MultibodyProblem's memo).
  mutable Eigen::VectorXd y_drift_;
  Eigen::VectorXd y_big_, yp_big_;  // project(), on_event()
  Eigen::VectorXd xdot_scratch_;
  Eigen::VectorXd error_base_, error_moved_;  // project_error()
};

}  // namespace rigidae::multibody
