// A torque about a joint's axis ([[joints]] keys of a type that carries
// them: revolute): a torsional spring-damper (stiffness, damping,
// rest_angle) and a motor (motor_torque tau_m, motor_profile s(t)); its
// angle, generalized forces, exact derivatives, potential energy and the
// motor's power.
//
// The angle of b relative to a about the joint axis: the joint type's angle
// coordinate (model/joint_type.hpp; revolute: with n_a, z_a the normal and
// axis fixed in a, n_b the normal fixed in b, all carried to space,
//   C = n_a . n_b,   S = (z_a x n_a) . n_b,   theta = atan2(S, C))
// (on the branch that continues the motion from the last accepted step,
// multibody/angle_branch.hpp: a spring wound
// past half a turn keeps its sign). C and S are dot products of body
// vectors, so the constraint-row machinery (constraint_rows.hpp) gives
// their partials: Phi_q (dC/dq), G (C' = G_C v) and d(G^T l)/dq. With
// r2 = C^2 + S^2 (= 1 while the axes stay parallel):
//   dtheta/dq = (C S_q - S C_q) / r2,    theta' = G_theta v,
//   G_theta   = (C G_S - S G_C) / r2.
// The torque on b about the axis is -T, T = k (theta - theta0) + c theta'
// - tau_m s(t), and +T on a; its generalized force (power T theta') is Q = -T G_theta^T
// over both bodies' velocities, so the dynamic rows (which hold -f) gain
//   + T G_theta^T = G_C^T alpha_C + G_S^T alpha_S,  alpha = T (-S, C) / r2.
// Exact iteration matrix (rows of body X's velocities, columns of body Y):
//   d/dq_Y = d(G^T alpha)/dq_Y |alpha fixed  (HL of constraint_rows)
//          + G_C[X]^T dalpha_C/dq_Y + G_S[X]^T dalpha_S/dq_Y
//   dalpha_C/dq = -T d(S/r2)/dq - (S/r2) dT/dq,  dalpha_S/dq = T d(C/r2)/dq + (C/r2) dT/dq
//   dT/dq = k dtheta/dq + c dtheta'/dq,
//   dtheta'/dq = (C_q S' + C S'_q - S_q C' - S C'_q)/r2 - 2 theta' (C C_q + S S_q)/r2
//   d/dv_Y = c G_theta[X]^T G_theta[Y]
// (C'_q = d(G_C v)/dq, dGv_q of constraint_rows); the motor's term depends
// on t alone, so it enters the matrix only through alpha. Potential
// 1/2 k (theta - theta0)^2; the motor has none: its power tau_m s(t) theta'
// is what the energy check integrates (when there is no damper, whose
// dissipation is not tracked).
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "rigidae/multibody/angle_branch.hpp"
#include "joint_element.hpp"

namespace rigidae::multibody {

namespace {

// Rows over one body's coordinates or velocities (row vectors must be row-major in Eigen).
using RowQ = Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxBodyQ>;
using RowV = Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxBodyV>;

class TorsionSpring final : public ForceElement {
 public:
  explicit TorsionSpring(const JointSpec& js) {
    body_[0] = js.body_a;
    body_[1] = js.body_b;
    stiffness_ = js.torsion_stiffness;
    damping_ = js.torsion_damping;
    rest_angle_ = js.torsion_rest_angle;
    motor_torque_ = js.motor_torque;
    motor_profile_ = js.motor_profile;
    // The joint type's first angle (revolute: C = n_a . n_b, S = (z_a x n_a) . n_b).
    joint_coordinate_rows(js, CoordinateKind::Angle, rows_, "a torsional spring or motor");
  }

  void add_force(const ForceBodies& b, double* F) override {
    BlockEval& e = eval_;
    const BlockSides sides = this->sides(b);
    evaluate_rows(rows_, 2, sides, e);
    const double C = e.phi(0), S = e.phi(1), r2 = C * C + S * S;
    const double rate = (C * e.Gv(1) - S * e.Gv(0)) / r2;
    const double T = stiffness_ * (angle(e, rate, b.t) - rest_angle_) + damping_ * rate - motor(b.t);
    for (int x = 0; x < 2; ++x) {
      if (!sides.state[x]) continue;
      const int vo = b.v_offset[body_[x]];
      for (int k = 0; k < sides.state[x]->nv(); ++k) F[vo + k] += T * (C * e.G[x](1, k) - S * e.G[x](0, k)) / r2;
    }
  }

  void add_jacobian(const ForceBodies& b, JacobianSink& sink) override {
    BlockEval& e = eval_;
    RowQ theta_q[2], rate_q[2], dT_q[2], dalpha_c[2], dalpha_s[2];
    RowV g_theta[2];
    MatBVQ Hq;
    BoundedMat<kMaxBodyV, kMaxBodyV> Hv;
    const BlockSides sides = this->sides(b);
    evaluate_rows(rows_, 2, sides, e);
    const double C = e.phi(0), S = e.phi(1), r2 = C * C + S * S;
    const double Cd = e.Gv(0), Sd = e.Gv(1);
    const double rate = (C * Sd - S * Cd) / r2;
    const double T = stiffness_ * (angle(e, rate, b.t) - rest_angle_) + damping_ * rate - motor(b.t);
    const double alpha[2] = {-T * S / r2, T * C / r2};
    const double* acc[2] = {nullptr, nullptr};
    for (int x = 0; x < 2; ++x)
      if (sides.state[x]) acc[x] = sides.state[x]->v;  // any velocities: dGa_q is not used here
    // Keep the first pass's values: differentiate_rows fills only the derivative fields.
    differentiate_rows(rows_, 2, sides, acc, alpha, nullptr, e);
    for (int y = 0; y < 2; ++y) {
      if (!sides.state[y]) continue;
      const auto Cq = e.phi_q[y].row(0), Sq = e.phi_q[y].row(1);
      const RowQ r2_q = 2.0 * (C * Cq + S * Sq);
      theta_q[y] = (C * Sq - S * Cq) / r2;
      g_theta[y] = (C * e.G[y].row(1) - S * e.G[y].row(0)) / r2;
      rate_q[y] = (Cq * Sd + C * e.dGv_q[y].row(1) - Sq * Cd - S * e.dGv_q[y].row(0)) / r2 - rate * r2_q / r2;
      dT_q[y] = stiffness_ * theta_q[y] + damping_ * rate_q[y];
      // d(S/r2) = (S_q - S r2_q / r2) / r2, and the same for C.
      dalpha_c[y] = -T * (Sq - S * r2_q / r2) / r2 - (S / r2) * dT_q[y];
      dalpha_s[y] = T * (Cq - C * r2_q / r2) / r2 + (C / r2) * dT_q[y];
    }
    for (int x = 0; x < 2; ++x) {
      if (!sides.state[x]) continue;
      const int Vx = b.v_group[body_[x]];
      for (int y = 0; y < 2; ++y) {
        if (!sides.state[y]) continue;
        Hq = e.HL[x][y];
        Hq.noalias() += e.G[x].row(0).transpose() * dalpha_c[y];
        Hq.noalias() += e.G[x].row(1).transpose() * dalpha_s[y];
        sink.add(Vx, b.q_group[body_[y]], 0, 0, Hq);
        Hv.noalias() = damping_ * (g_theta[x].transpose() * g_theta[y]);
        sink.add(Vx, b.v_group[body_[y]], 0, 0, Hv);
      }
    }
  }

  double potential_energy(const ForceBodies& b) override {
    evaluate_rows(rows_, 2, sides(b), eval_);
    const double d = angle(eval_, rate(eval_), b.t) - rest_angle_;
    return 0.5 * stiffness_ * d * d;
  }
  bool elastic() const override { return true; }
  bool conservative() const override { return damping_ == 0.0 && motor_torque_ == 0.0; }
  // The motor's power tau_m s(t) theta' (the spring's work is its potential's change).
  bool has_power() const override { return motor_torque_ != 0.0 && damping_ == 0.0; }
  double power(const ForceBodies& b) override {
    const BlockSides sides = this->sides(b);
    evaluate_rows(rows_, 2, sides, eval_);
    const double C = eval_.phi(0), S = eval_.phi(1);
    return motor(b.t) * (C * eval_.Gv(1) - S * eval_.Gv(0)) / (C * C + S * S);
  }

  // The angle starts on its principal branch (-pi, pi] and follows the motion.
  bool follows_motion() const override { return true; }
  void reset() override { branch_.reset(); }
  void follow(const ForceBodies& b) override {
    evaluate_rows(rows_, 2, sides(b), eval_);
    const double r = rate(eval_);
    branch_.accept(std::atan2(eval_.phi(1), eval_.phi(0)), r, b.t);
  }

 private:
  BlockSides sides(const ForceBodies& b) const { return joint_sides(body_, b); }
  double motor(double t) const {
    if (motor_torque_ == 0.0) return 0.0;
    return motor_profile_ ? motor_torque_ * motor_profile_->value(t) : motor_torque_;
  }
  static double rate(const BlockEval& e) {
    const double C = e.phi(0), S = e.phi(1);
    return (C * e.Gv(1) - S * e.Gv(0)) / (C * C + S * S);
  }
  // On the branch that continues the motion from the last accepted step.
  double angle(const BlockEval& e, double rate_now, double t) const {
    return branch_.continued(std::atan2(e.phi(1), e.phi(0)), rate_now, t);
  }

  int body_[2] = {kGround, kGround};
  double stiffness_ = 0.0, damping_ = 0.0, rest_angle_ = 0.0;  // N m/rad, N m s/rad, rad
  double motor_torque_ = 0.0;                                  // N m
  std::optional<TimeFunction> motor_profile_;                  // unset: constant
  ConstraintRow rows_[2];
  AngleBranch branch_;      // the angle at the last accepted step
  BlockEval eval_;          // scratch, sized on the stack's bounds: no allocation
};

}  // namespace

// One element per joint that carries a spring, a damper or a motor (its
// type lists the keys: model/joint_type.hpp; the loader sets the values).
void add_torsion_springs(const MultibodySpec& spec, ForceElements& out) {
  for (const JointSpec& js : spec.joints)
    if (js.torsion_stiffness != 0.0 || js.torsion_damping != 0.0 || js.motor_torque != 0.0)
      out.push_back(std::make_unique<TorsionSpring>(js));
}

}  // namespace rigidae::multibody
