#pragma once
// Rigid bodies in absolute coordinates joined by joints: the assembled DAE
// F(t, y, y') = 0 behind the narrow solver interface (DaeProblem).
//
// Unknowns, body by body then block by block:
//   body i:  q_i = (x_i, q_rot,i), v_i = (x_i', v_rot,i)   (differential)
//            pivoted body (BodySpec::pivot_W): q_i = q_rot,i, v_i = v_rot,i
//            only, its rotation block the one-body model about the pivot
//            (src/multibody/pivot.cpp, body_vector.hpp)
//   block j: lambda_j, mu_j                                 (algebraic)
// Body rows: kinematics x' - x_v = 0, q_rot' - N v_rot (+ Phi_q^T mu) = 0 and
// dynamics m x_v' - f_x = 0, M v_rot' - f_rot (+ G^T lambda) = 0, where the
// rotation block (N, M, f_rot: gyroscopic and velocity terms) is the one-body
// representation with the centre of mass as reference point (no gravity
// torque, inertia about the centre of mass). Gravity, loads and springs add
// to f. Blocks: each body's internal constraints (the quaternion norm, R^T R
// = I) of its representation's kind, and each joint (a Force block in both
// forms, whose multipliers are reactions); rows per block kind as
// BlockScheme states. The iteration matrix is exact (hand-derived through
// body_vector.hpp and constraint_rows.hpp); its sparse pattern follows from
// the blocks, so nonzeros and work grow like bodies + joints.
//
// Consistent start (constructor): the joints' position misses at the given
// poses are measured; a miss above MultibodySpec::start_tolerance is an
// InputError naming the joint (file:line:col), the row and the miss; smaller
// ones are removed by Gauss-Newton with the least change in the mass metric
// (a warning says how far). Velocities are projected onto G v = 0 in the
// mass metric, then (v', lambda) come from [M G^T; G 0]. A system without
// joints (the saddle system block diagonal, one body's own constraints per
// block) is made consistent and projected body by body by the one-body
// kernels (schemes/body_rows.hpp), so a one-body scene as one pivoted body
// starts, evaluates and projects bit for bit as the one-body model.
//
// Redundant constraints (an overconstrained closed loop, e.g. a planar
// four-bar of four revolute joints: 20 rows, rank 17) are accepted, as MSC
// Adams does: before the layout is built, the Force rows (the joints' and the
// Lagrange form's internal rows) are evaluated at the given poses and G^T is
// factored by SuiteSparseQR (rank-revealing: a column whose remaining norm
// falls below the threshold is set aside). Rows are first scaled to common
// units: point rows (metres) are divided by the scene's length L, the
// largest joint-point offset from a body's centre of mass (1 m when there is
// none); angular rows are dimensionless. The threshold is 1e-9 times the
// largest |R_kk| of a first factorisation; of the dependent rows the
// best-conditioned choice is set aside (row_rank.hpp, best_set_aside). The
// rows set aside (redundancy().dropped, named per joint with the joint's
// file:line:col) stay in their blocks, inactive (ConstraintBlock::active):
// their multipliers are held at 0 by the rows lambda_r = 0, mu_r = 0, so
// every scheme and representation runs unchanged and the layout never
// changes; the kept rows' multipliers carry the whole
// load (the particular solution of the independent subset: the reactions of
// the joints in the dependency, redundancy().indeterminate_joints, are not
// determined by the constraints and are reported as computed). A dropped
// row's Phi and G v are still monitored (drift(), joint_residuals()): they
// are implied by the kept rows and stay at the integration error. After every
// accepted step the subset is re-checked and chosen again when it has turned
// ill-conditioned (row_subset.cpp: an event, a projection and a restart),
// and a rank loss of all the rows (a singular pose) is noted. After the
// start's projection a dropped row that misses by more than start_tolerance
// is an error (the loop cannot close in that direction).
// Singular start: the rank is measured again at two nearby poses (the start
// moved along its velocity and along a random admissible velocity by about
// 1% of L, each projected back onto the kept rows). Rank loss that persists
// there is redundancy; rank loss only at the start is a singular pose, and a
// warning says the assembly branch is ambiguous (the run's re-check sets
// the rows active again once they stop being implied, a relative residual
// above 1e-4 against the kept rows: row_subset.cpp; not yet tested on a
// singular start).
// Mobility: rank_dof = velocities - rank of the Force rows (6 per body in the
// Euler form), beside Gruebler-Kutzbach 6 n - sum of the joints' rows; a
// scene's expected_dof that differs from rank_dof is a warning.
#include <Eigen/QR>

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rigidae/coords/representation.hpp"
#include "rigidae/model/recorded_parts.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/multibody/angle_branch.hpp"
#include "rigidae/multibody/assembly.hpp"
#include "rigidae/multibody/block_scheme.hpp"
#include "rigidae/multibody/constraint_rows.hpp"
#include "rigidae/multibody/driver_rows.hpp"
#include "rigidae/multibody/force_element.hpp"
#include "rigidae/multibody/jacobian_sink.hpp"
#include "rigidae/solver/problem.hpp"

namespace rigidae::multibody {

struct BodyModel {
  std::string name;
  bool particle = false;  // a point mass: rep and map are the empty rotation block (point_mass.hpp)
  double mass = 1.0;
  Mat3 inertia;  // about the centre of mass, body axes
  Coordinates coordinates;
  std::unique_ptr<Representation> rep;  // the rotation block
  std::unique_ptr<RotationMap> map;
  int q_group = 0, v_group = 0;  // groups of the unknowns
  int nqr = 0, nvr = 0;
  // Pivoted (held at a fixed point, src/multibody/pivot.cpp): no x unknowns
  // (nx = 0), the rotation block about the pivot (inertia about it, gravity
  // torque through lever), lever = c the pivot -> centre of mass vector in
  // the body frame.
  int nx = 3;
  bool pivoted() const { return nx == 0; }
  Vec3 pivot = Vec3::Zero();
  Vec3 lever = Vec3::Zero();
};

struct ConstraintBlock {
  bool internal = false;  // a body's own constraints, else a joint or a driver
  int body = -1;          // internal: the body
  int joint = -1;         // joint or driver: the joint's index in the spec
  int driver = -1;        // a driver's index in the spec (one rheonomic row; driver_rows.hpp)
  ConstraintKind kind = ConstraintKind::Force;
  std::vector<ConstraintRow> rows;  // joints
  std::vector<std::string> row_names;
  int nr = 0;
  // Per row: 1 when the row is integrated, 0 when it is set aside as
  // dependent on the others (redundant, or chosen again during the run:
  // row_subset.cpp). A row set aside keeps its multipliers in y, held at 0
  // by the rows lambda_r = 0 (and mu_r = 0), so the layout and the sparse
  // pattern never change when the subset does.
  std::vector<char> active;
  int lambda_group = -1, mu_group = -1;
  LevelWeights lambda_rows, mu_rows;
  int body_of_side[2] = {kGround, kGround};
};

// A pivoted body's model (src/multibody/pivot.cpp): nx = 0, the pivot, the
// lever c = R0^T (x0 - pivot); the one-body scene of its rotation block gets
// support "fixed_point" and centre of mass c (inertia about the pivot,
// gravity torque).
void pivot_body_scene(const BodySpec& bs, Scene& one_body, BodyModel& b);

// Reaction of a joint on its body b (on a when b is the ground), in space:
// the force at b's joint point (N) and the torque about that point (N m).
struct JointReaction {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

// The start's rank analysis (see the opening comment).
struct RedundantRow {
  int joint = -1;
  int index = -1;        // the row's index among its joint's rows
  std::string row;       // the row's name, e.g. "axis_n1"
  ConstraintRow constraint;
};
struct RedundancyReport {
  int velocities = 0;    // absolute velocity coordinates (6 per body in the Euler form)
  int rows = 0;          // Force rows before the drop (internal and joints)
  int joint_rows = 0;    // the joints' rows before the drop
  int rank = 0;          // of the scaled Force rows at the start
  int rank_dof = 0;      // velocities - rank
  int gruebler_dof = 0;  // 6 bodies - sum over joints of (6 - the type's freedoms) - drivers
  double length_scale = 1.0;  // L (m): point rows divided by it
  double threshold = 0.0;     // of the rank decision (scaled units)
  std::vector<RedundantRow> dropped;
  std::vector<int> indeterminate_joints;  // joints whose reactions the constraints do not determine
  bool singular_start = false;            // rank loss only at the start pose
  int nearby_rank = -1;                   // the largest rank at the nearby poses (-1: not measured)
  std::string mobility_warning;           // expected_dof differs from rank_dof (also in warnings())
};

struct ForceRowRef;  // one Force row (src/multibody/row_rank.hpp)

// A pose passed during the run where every subset of the rows was nearly
// dependent (row_subset.cpp): assembly branches cross there.
struct SingularPose {
  double t = 0.0;
  double condition = 1.0;   // smallest min|R_kk|/max|R_kk| of the kept rows seen there, relative to the start's
  std::string joints;       // the joints in the near-dependency, space-separated
  // The branch check (branch_check.cpp): the velocity's jump across the pose
  // relative to its size, NaN until the run has left the pose behind; above
  // 0.1 the run changed assembly branch there.
  double velocity_jump = std::numeric_limits<double>::quiet_NaN();
  bool branch_switch = false;
  // Crossed by a bridge (pose_bridge.cpp), from bridged_from to bridged_to
  // (s); estimate: the extrapolation's error estimate in units of the
  // tolerance (max over the state of |difference| / (rtol |y| + atol)).
  bool bridged = false;
  double bridged_from = 0.0, bridged_to = 0.0, estimate = 0.0;
};

// The branch check's limit on the velocity's relative jump across a pose
// (branch_check.cpp). Measured on singular_linkage.toml at rtol 1e-10, every
// Euler-form combination: passages on the branch 3e-6 .. 3e-5, switches
// 0.92 .. 1.78.
inline constexpr double kBranchJump = 0.1;

// What the branch check keeps between accepted steps (branch_check.cpp): the
// last step before a singular pose's neighbourhood, its body velocities V0
// and their rates A0.
struct BranchWatch {
  bool valid = false, inside = false;
  double t0 = 0.0;
  Eigen::VectorXd V0, A0, V1, A1, y_shift, scratch;
};

// What the bridge across singular poses keeps (pose_bridge.cpp): the last
// accepted states, the conditioning's last samples, the stop time asked of
// the integrator and the last bridge's interpolant.
struct PoseBridge {
  bool enabled = true;  // [mechanism] singular_poses = "bridge"
  double t_end = std::numeric_limits<double>::infinity();
  double rtol = 1e-8, atol = 1e-8;  // the scene's, for the estimate's units
  std::vector<double> t;            // accepted states, oldest first
  std::vector<Eigen::VectorXd> y;
  double t_last = std::numeric_limits<double>::quiet_NaN(), r_last = std::numeric_limits<double>::quiet_NaN();
  double stop_hint = std::numeric_limits<double>::infinity();
  bool pending = false;  // the last check asks for a bridge now
  double pose_t = 0.0;   // the pose's time, estimated
  // The last bridge: (from, to], its nodes and Hermite coefficients over the
  // state, and the full y at both ends (the multipliers are interpolated).
  double from = 0.0, to = 0.0;
  std::vector<double> z;
  std::vector<Eigen::VectorXd> c;
  Eigen::VectorXd y_from, y_to;
};

class MultibodyProblem final : public DaeProblem {
 public:
  // scene.multibody must hold the validated spec. Throws InputError for a
  // start that misses a joint by more than the tolerance or has dependent
  // constraint rows.
  explicit MultibodyProblem(const Scene& scene);

  int size() const override { return n_; }
  int state_size() const override { return n_state_; }
  void initial_state(double t0, Eigen::VectorXd& y, Eigen::VectorXd& yp) override;
  void make_consistent(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) override;
  void differential_id(Eigen::Ref<Eigen::VectorXd> id) const override;
  bool suppress_algebraic_error_test() const override { return true; }
  void absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& y0,
                           Eigen::Ref<Eigen::VectorXd> out) const override;
  bool residual(double t, const double* y, const double* yp, double* F) override;
  void iteration_matrix_dense(double t, double cj, const double* y, const double* yp, double* J) override;
  const SparsityPattern& sparsity() const override { return pattern_; }
  void iteration_matrix_sparse(double t, double cj, const double* y, const double* yp, double* values) override;
  int event_count() const override;
  void event_functions(double t, const double* y, double* g) override;
  StepAction on_event(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) override;
  StepAction after_step(double t, double h, Eigen::VectorXd& y, Eigen::VectorXd& yp) override;
  std::vector<EventNote> take_events() override;
  // The bridge across singular poses (pose_bridge.cpp).
  double stop_time_hint() const override { return bridge_.enabled ? bridge_.stop_hint : std::numeric_limits<double>::infinity(); }
  void bridged_state(double t, Eigen::VectorXd& y) override;
  // After an accepted step (IDA's y' or the ODE's right-hand side in yp):
  // keeps the state for the extrapolation, and bridges the pose ahead when
  // the conditioning's check asked for it. Returns the landing time, or 0.
  double bridge_after_step(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp);
  bool bridges_singular_poses() const { return bridge_.enabled; }
  // The scheme and the joints whose rows lost rank (src/multibody/stall_report.cpp).
  std::string describe_stall(double t, const double* y) override;

  // --- Structure, for tests and reports.
  const std::vector<BodyModel>& bodies() const { return bodies_; }
  const std::vector<ConstraintBlock>& blocks() const { return blocks_; }
  const std::vector<UnknownGroup>& groups() const { return groups_; }
  const BlockScheme& scheme() const { return scheme_; }
  const MultibodySpec& spec() const { return spec_; }
  // Whether the bodies move independently of one another, each as the
  // one-body model about its pivot: no joint or driver blocks (only the
  // bodies' own constraints), every body a pivoted rigid body (nx = 0, not a
  // particle), and no force element acting on a pivoted body
  // (ForceElement::acts_on_pivoted_bodies: gravity's torque is already in
  // the rotation blocks). one_body_system(scene) is such a system. Then
  // MultibodyOde integrates body by body (schemes/body_ode.hpp).
  bool bodies_decoupled() const;
  // The start's rank analysis: redundant rows set aside, mobility.
  const RedundancyReport& redundancy() const { return redundancy_; }
  // What an assembled start ([mechanism] assemble / hold) did; done = false without one.
  const AssemblyReport& assembly() const { return assembly_; }
  // The rows set aside now: the start's (redundancy().dropped) until the
  // subset is chosen again during the run (row_subset.cpp).
  const std::vector<RedundantRow>& set_aside() const { return set_aside_; }
  // How often the subset was chosen again, and the largest dependency
  // coefficient |alpha| seen at an accepted step (0 without rows set aside).
  int subset_changes() const { return subset_changes_; }
  // Singular poses met during the run (only in mechanisms with rows set aside).
  const std::vector<SingularPose>& singular_poses() const { return singular_poses_; }
  double largest_dependency() const { return largest_dependency_; }
  // The largest amplification of the multipliers by the kept rows met when
  // their |alpha| had grown (row_subset.cpp; 0 when never measured).
  double largest_amplification() const { return largest_amplification_; }
  // After an accepted step at y: re-checks the independent subset (see
  // row_subset.cpp) and chooses it again when it has become ill-conditioned
  // and inflates the multipliers (read from y when multipliers_in_y; the ODE
  // form's state holds none). Returns true when the masks changed (the
  // multipliers must be made consistent again). Records a "row_subset" event.
  // yp: the state's derivative at t (IDA's y', the ODE's right-hand side),
  // for the branch check across singular poses; nullptr: not checked.
  bool check_row_subset(double t, const double* y, bool multipliers_in_y = true, const double* yp = nullptr);
  // Whether check_row_subset watches singular poses (and wants yp).
  bool watches_singular_poses() const { return !redundancy_.dropped.empty(); }
  // The multipliers of the rows set aside (held at 0): their number, the
  // same whichever rows are set aside.
  int held_unknowns() const override;
  // Parts of it: all the rows' conditioning at the start's rank, a singular
  // pose noted; the kept multipliers against the minimum-norm ones.
  void watch_singular_pose(double t, const Eigen::SparseMatrix<double, Eigen::ColMajor, long>& Gt,
                           const std::vector<ForceRowRef>& refs);
  // The branch check after an accepted step (branch_check.cpp), and its
  // parts: per body v_c and omega in space; the kinetic-energy norm at y.
  void check_branch(double t, const double* y, const double* yp);
  // The bridge's plan at a conditioning sample (pose_bridge.cpp): a stop
  // time ahead of the pose, or a bridge now (true).
  bool plan_bridge(double t, double relative);
  // The accepted states kept for the extrapolation, dropped (a chart switch
  // changed the coordinates' meaning).
  void forget_bridge_history() {
    bridge_.t.clear();
    bridge_.y.clear();
  }
  void body_velocities(const double* y, Eigen::VectorXd& V) const;
  double velocity_norm(const double* y, const Eigen::VectorXd& x) const;
  double multiplier_amplification(const Eigen::SparseMatrix<double, Eigen::ColMajor, long>& Gt,
                                  const std::vector<ForceRowRef>& refs, const std::vector<int>& block_of,
                                  const std::vector<int>& kept, const double* y) const;
  // "JOINT.ROW" of a dropped row, with the joint's file:line:col.
  std::string dropped_row_source(int k) const;
  // Largest |Phi| and |G v| of the dropped rows at y (0 when none).
  std::pair<double, double> dropped_drift(const double* y);
  // Warnings of the start (projected misses and velocities), for the report.
  const std::vector<std::string>& warnings() const { return warnings_; }

  // --- Reporting helpers (not the hot path).
  Vec4 body_orientation(int i, const double* y) const;     // unit quaternion of R_WB
  Vec3 body_omega_space(int i, const double* y) const;     // rad/s
  Vec3 body_position(int i, const double* y) const;        // m
  Vec3 body_velocity(int i, const double* y) const;        // m/s
  // The support force on pivoted body i, at its pivot, in space (N): from
  // m a_c = F_support + m g + the other forces on it (src/multibody/pivot.cpp);
  // zero for a free body. The support exerts no torque about the pivot.
  Vec3 support_force(int i, const double* y);
  // For a joint whose reaction the constraints do not determine (in
  // redundancy().indeterminate_joints), the minimum-norm split over the
  // dependency's rows (src/multibody/minimum_norm_reactions.cpp).
  JointReaction joint_reaction(int joint, const double* y);
  // |Phi| and |G v| of a joint's rows.
  std::pair<double, double> joint_residuals(int joint, const double* y);
  double kinetic_energy(const double* y) const;
  // Every force element's potential (gravity, constant space-frame forces
  // -F . x, springs, torsional springs).
  double potential_energy(const double* y);
  // The elastic elements' part of it: 1/2 k stretch^2 and 1/2 k (theta -
  // theta0)^2, theta on the branch followed from the start.
  double elastic_energy(const double* y);
  // Every force element is conservative (the energy check applies).
  bool conserves_energy() const;
  // Every non-conservative element reports its power (drivers and loads:
  // H - H0 - W balances); false with a damper, whose dissipation is not tracked.
  bool energy_balance_known() const;
  Vec3 linear_momentum(const double* y) const;
  Vec3 angular_momentum(const double* y) const;  // about the space origin
  // One output row: per body (BODY.qw .. qz, BODY.wx .. wz in space,
  // BODY.x .. z, BODY.vx .. vz; a pivoted body then BODY.pivot_force_x .. z,
  // support_force), per joint (JOINT.force_x .. z, JOINT.torque_x
  // .. z on body b in space, JOINT.residual_position = |Phi|,
  // JOINT.residual_velocity = |G v|, then per coordinate of its type
  // JOINT.<coordinate>, JOINT.<coordinate>_rate), per marker MARKER.x..z,
  // .vx..vz, .ax..az (markers.cpp; a particle: only BODY.x..z, BODY.vx..vz),
  // then energy, linear momentum p_x .. p_z and angular momentum L_x .. L_z about
  // the origin. Names and units in the same order.
  std::vector<std::string> output_names() const;
  std::vector<std::string> output_units() const;
  void output_row(double t, const double* y, double* out);
  // The same row for the chosen parts only (trajectory.csv under [output]
  // bodies / joints): their body and joint columns, then the global ones.
  std::vector<std::string> output_names(const RecordedParts& parts) const;
  std::vector<std::string> output_units(const RecordedParts& parts) const;
  void output_row(double t, const double* y, const RecordedParts& parts, double* out);
  // A step row's per-part columns (reporting.cpp), after the global ones: per
  // chosen body with constraints of its own BODY.lambda_<row> / BODY.mu_<row>
  // (its multipliers), per chosen pivoted body BODY.pivot_force_x .. z, per
  // chosen joint JOINT.lambda_<row> / JOINT.mu_<row>,
  // JOINT.force_x..z, JOINT.torque_x..z, the residuals and the coordinates
  // (as output_row). `parts` lists bodies and joints in the scene's order.
  std::vector<std::string> step_part_names(const RecordedParts& parts) const;
  std::vector<std::string> step_part_units(const RecordedParts& parts) const;
  // Fills out[0 .. step_part_names(parts).size()); allocates nothing unless
  // the scene has markers (their accelerations are solved per row), whose
  // columns MARKER.x..az come last.
  void step_part_row(double t, const double* y, const RecordedParts& parts, double* out);
  // Joint coordinates (model/joint_type.hpp): the coordinates of joint j,
  // in its type's order, at y: values (rad, unwrapped against the branch
  // followed from the start; m) and rates (rad/s; m/s). Allocates nothing.
  int joint_coordinate_count(int joint) const;
  void joint_coordinates(int joint, const double* y, double* value, double* rate);
  // Drivers (spec().drivers order): the driving torque (N m) or force (N) at
  // y, from the driver's multiplier (driver_rows.hpp). Allocates nothing.
  double driving_effort(int driver, const double* y);
  // Their power sum_d effort_d * coordinate rate_d (W) at y: the work rate of
  // the drivers on the mechanism.
  double driver_power(const double* y);
  // The power of the drivers and of the force elements without a potential
  // that report it (ForceElement::power) at (t, y), W: dW/dt of the energy
  // check's work. just_evaluated: the bodies were evaluated at y's
  // positions and velocities at t by the last residual (the ODE form's right-hand side, which
  // then writes the multipliers into the same y): the placement and the rows that residual
  // evaluated are the ones the power needs (R and its first partials in the Euler form, the
  // second ones in the Lagrange form), so they are not evaluated again.
  double work_rate(double t, const double* y, bool just_evaluated = false);
  // Whether anything does work that work_rate counts (drivers, or force
  // elements without a potential that report their power).
  bool has_work() const;
  // Markers (src/multibody/markers.cpp): per marker of the spec, in order,
  // position (m), velocity (m/s) and acceleration (m/s^2) in space, 9
  // numbers each, into out; the accelerations solved from the state y.
  // Not the hot path: one sparse factorisation per call (the output row's
  // and the step row's MARKER.x..az).
  void marker_kinematics(double t, const double* y, double* out);
  // Position- and velocity-level drift over all blocks (max norms: the
  // largest |Phi| and |G v| of any row; the records' drift columns).
  std::pair<double, double> drift(double t, const double* y);
  // What the projection scheme compares with its threshold: per constraint
  // block (a body's own constraints, a joint's kept rows, a driver's row;
  // each row set aside as redundant on its own) the 2-norms |Phi| and |G v|
  // (|Phi_q N v| for a Kinematic block), the largest over blocks. For one
  // body it is the one-body model's rule (schemes::block_drift).
  std::pair<double, double> projection_drift(double t, const double* y);
  // Projects y onto Phi = 0 (Gauss-Newton, least change in the mass metric)
  // and v onto G v = 0, then makes (y, y') consistent.
  void project(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp);

  // --- The ODE form (multibody_ode.hpp; src/multibody/linear_part.cpp).
  // A scheme whose multiplier rows are acceleration-level (index1,
  // projection: no mu, no lambda') has a residual linear in (y', lambda):
  //   F(t, y, y') = A(t, q, v) [y'_state; lambda] + F(t, (q, v, 0), 0).
  // Writes A: on the state's columns dF/dy', on the multipliers' dF/dy; on
  // sparsity()'s pattern (values zeroed here). Allocates nothing.
  // `just_evaluated`: residual(t, y, .) was the last evaluation, at this same
  // (t, y), so the bodies' terms and the blocks' rows are reused, not
  // evaluated again (the ODE form's right-hand side: half its cost).
  void linear_part_sparse(double t, const double* y, double* values, bool just_evaluated = false);
  // The same through another sink (sparsity_sink().remapped(...): the ODE
  // form's KKT block written in place), into values the caller has zeroed.
  void linear_part_into(double t, const double* y, JacobianSink& sink, double* values, bool just_evaluated);
  const JacobianSink& sparsity_sink() const { return *sink_; }
  // After an accepted step of an ODE run: force elements with a state of
  // their own (a torsion angle's branch) follow the motion (after_step's part
  // that is not a restart).
  void follow_motion(double t, const double* y);

 private:
  struct BodyWork {
    BodyState st;
    StandardTerms terms;
    TermDerivatives derivs;
  };
  // |Phi| of the k-th row set aside, at the bodies' last evaluate().
  double dropped_row_miss(int k);
  // Dropped row k evaluated into *dropped_eval_ at the bodies' evaluated state.
  void evaluate_dropped_row(int k);
  // Start charts: each body with Euler angles in its most regular chart when
  // its own is within the switching margin at the start (multibody_problem.cpp).
  void choose_start_charts(double t0);
  void evaluate(double t, const double* y, int order, bool for_rows = false);
  void evaluate_block(int j, const double* y, const double* yp);
  // make_consistent for bodies not joined to one another (consistent_start.cpp):
  // each body by the one-body consistent start; F the residual at v' = 0 and
  // no multipliers.
  void make_consistent_by_body(Eigen::VectorXd& y, Eigen::VectorXd& yp, const Eigen::VectorXd& F);
  // A body's own block's rows into F and its multipliers' forces into the
  // body's rows, by the one-body model's expressions (schemes/body_rows.hpp).
  void internal_block_rows(const ConstraintBlock& blk, const Eigen::Map<const Eigen::VectorXd>& y,
                           const Eigen::Map<const Eigen::VectorXd>& yp, Eigen::Map<Eigen::VectorXd>& F) const;
  void differentiate_block(int j, const double* y, const double* yp);
  void assemble_jacobian(double t, double cj, const double* y, const double* yp, JacobianSink& sink);
  void assemble_linear_part(double t, const double* y, JacobianSink& sink, bool just_evaluated);
  void add_forces(const double* y, double* F);
  void add_force_jacobian(const double* y, JacobianSink& sink);
  // A joint's reaction from multipliers of the given rows (what RowReaction
  // says each is), bodies evaluated.
  JointReaction reaction_of_rows(int joint, const ConstraintRow* const* rows, const double* lambda, int count);
  // The minimum-norm reactions of the joints in a dependency
  // (minimum_norm_reactions.cpp): built after the layout, solved once per state.
  struct MinimumNormReactions {
    std::vector<int> joints, bodies;              // S and the bodies its joints hold
    std::vector<int> first_row;                   // per joint, into rows (-1: not in S)
    std::vector<const ConstraintRow*> rows;       // S's rows: each joint's kept, then set aside
    std::vector<int> kept_lambda_offset;          // in y, -1 for a row set aside
    Eigen::MatrixXd A;                            // G_S^T W^-1 over (x', omega) per body
    Eigen::VectorXd weight, lambda, f, memo_y;
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  };
  void prepare_minimum_norm_reactions();
  bool minimum_norm_applies(int joint) const;
  void solve_minimum_norm_reactions(const double* y);
  JointReaction minimum_norm_reaction(int joint, const double* y);
  // After an accepted step (bodies evaluated): the force elements and the
  // joint coordinates' branches follow the motion.
  void follow_force_elements();
  // A joint coordinate and its rows; `reference`: the angle at the last
  // accepted step (the branch an angle is unwrapped to).
  struct CoordinateTrack {
    int joint = -1;
    const JointCoordinate* def = nullptr;
    ConstraintRow rows[2];
    AngleBranch branch;  // an angle's: continued from the last accepted step
  };
  // Value and rate of one coordinate at the bodies' last evaluate().
  void coordinate_value(const CoordinateTrack& c, double& value, double& rate);
  // A joint's coordinate columns into out (value, rate per coordinate); returns their count.
  int write_coordinates(int joint, const double* y, double* out);
  // Force blocks' G (rows: their lambdas in order) over all velocities, and
  // stacked positions Phi, at the last evaluate().
  void constraint_matrices(Eigen::SparseMatrix<double>& G, Eigen::VectorXd& phi, std::vector<int>* row_block,
                           std::vector<int>* row_index) const;
  void start(const Scene& scene);
  void check_driver_start(int block, const std::string& where, double t0, double& worst, std::string& worst_row);
  // Before the layout: the rank of the Force rows at the given poses, the
  // rows set aside (removed from rows[joint]), mobility.
  void find_redundant_rows(const Scene& scene, std::vector<std::vector<ConstraintRow>>& rows);
  // Rank of the scaled Force rows (internal, kept and dropped) at y.
  int full_rank(double t, const double* y);
  // After the start's projection: dropped rows' misses, nearby poses.
  void check_redundant_rows(double t0);
  // The body states at the given poses (the bodies' q and v of y, size n_state_ at least).
  void physical_start(Eigen::VectorXd& y) const;
  bool change_charts(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp, bool force_check);
  std::string row_label(int block, int row) const;

  MultibodySpec spec_;
  bool lagrange_form_ = true;  // the scene's equations (a particle's BodyState is always on the Lagrange branch)
  AssemblyReport assembly_;
  BlockScheme scheme_;
  double switch_threshold_ = 0.1;
  bool switching_ = true;
  double projection_threshold_ = 0.0;
  bool project_every_step_ = false;
  std::vector<BodyModel> bodies_;
  std::vector<ConstraintBlock> blocks_;
  std::vector<UnknownGroup> groups_;
  std::vector<int> block_of_joint_;   // index in blocks_ of joint j (-1: no multipliers)
  std::vector<DriverRow> drivers_;    // spec_.drivers' rows
  std::vector<int> block_of_driver_;  // index in blocks_ of driver d
  std::vector<std::vector<int>> drivers_of_joint_;  // per joint, its drivers (spec order)
  BlockEval driver_scratch_;          // the coordinate rows of the driver being evaluated
  double evaluated_t_ = 0.0;          // the time of the last evaluate() (drivers' rows read it)
  std::vector<int> velocity_offset_;  // of body i's v in the stacked velocities
  int nv_total_ = 0;
  int n_ = 0;
  int n_state_ = 0;  // the bodies' q and v come first
  bool has_force_blocks_ = false;
  bool decoupled_ = false;  // bodies_decoupled(), fixed once the model is built
  bool placement_evaluated_ = false;  // the last evaluate() filled each body's R(q) (for_rows may skip it)
  SparsityPattern pattern_;
  std::unique_ptr<JacobianSink> sink_;
  std::vector<BodyWork> work_;
  std::vector<BlockEval> block_eval_;
  ForceElements forces_;      // registry order (src/multibody/force_elements/registry.cpp)
  ForceBodies force_bodies_;  // what they read of the bodies (states point into work_)
  bool forces_follow_motion_ = false;
  std::vector<CoordinateTrack> coordinates_;   // every joint's, joint by joint
  std::vector<int> first_coordinate_;          // per joint, into coordinates_ (size joints + 1)
  BlockEval coordinate_eval_;
  Eigen::VectorXd y0_, yp0_;
  Eigen::VectorXd marker_y_, marker_yp_;  // marker_kinematics' state and its solved y'
  std::vector<std::string> warnings_;
  RedundancyReport redundancy_;
  std::vector<std::vector<int>> dropped_of_joint_;  // indices into redundancy_.dropped
  std::vector<RedundantRow> set_aside_;             // the rows inactive now (index: in the joint's block)
  int subset_changes_ = 0;
  std::vector<SingularPose> singular_poses_;
  bool near_singular_ = false;     // inside a singular pose's neighbourhood (row_subset.cpp)
  double start_condition_ = -1.0;  // all the rows' R ratio at the start's rank, at the first check
  BranchWatch branch_;
  PoseBridge bridge_;
  double subset_baseline_ = 1.0;
  double start_baseline_ = 1.0;  // the start's  // max |alpha| right after the last choice of the subset
  double largest_dependency_ = 0.0;
  double largest_amplification_ = 0.0;
  std::unique_ptr<BlockEval> dropped_eval_;
  MinimumNormReactions minimum_norm_;
  // support_force's scratch: a residual row (plus one free body's), y' = 0,
  // the force elements' view with one body made free, a block's rows (on
  // the heap: a BlockEval is large, and problems live on callers' stacks).
  Eigen::VectorXd pivot_F_, pivot_yp_;
  ForceBodies pivot_bodies_;
  std::unique_ptr<BlockEval> pivot_eval_;
  std::vector<EventNote> events_;
  std::vector<EventNote> start_events_;  // chart switches at the start (choose_start_charts), per run
  const double* evaluated_y_ = nullptr;  // output_row: the bodies are evaluated at this y
  // drift()'s last answer and the (t, y) it was for (y copied: the driver
  // reuses its buffers).
  bool drift_memo_valid_ = false;
  double drift_memo_t_ = 0.0;
  Eigen::VectorXd drift_memo_y_;
  std::pair<double, double> drift_memo_{0.0, 0.0};
};

}  // namespace rigidae::multibody
