// A linear motor in a joint ([[joints]] keys motor_force, motor_profile of
// a type that carries them: prismatic): the force F s(t) on b along the
// joint's axis (and its opposite on a), F = motor_force, s the profile
// (unset: 1).
//
// Its coordinate is the type's displacement d (model/joint_type.hpp;
// prismatic: d = (p_b - p_a) . z_a, one row of dot products of body
// vectors), so the constraint-row machinery (constraint_rows.hpp) gives
// G_d (d' = G_d v) and d(G_d^T alpha)/dq. The force does the power
// F s(t) d', so its generalized force over both bodies' velocities is
//   Q = F s(t) G_d^T,
// and the dynamic rows (which hold -f) gain -F s(t) G_d^T. Exact iteration
// matrix (rows of body X's velocities, columns of body Y's coordinates):
//   -dQ/dq_Y = d(G_d[X]^T alpha)/dq_Y with alpha = -F s(t)  (HL of constraint_rows),
//   -dQ/dv = 0 (G_d depends on the poses only).
// No potential (s depends on t): the energy check integrates the power
// F s(t) d' (ForceElement::power).
#include <optional>

#include "joint_element.hpp"

namespace rigidae::multibody {

namespace {

class JointForce final : public ForceElement {
 public:
  explicit JointForce(const JointSpec& js) : force_(js.motor_force), profile_(js.motor_profile) {
    body_[0] = js.body_a;
    body_[1] = js.body_b;
    joint_coordinate_rows(js, CoordinateKind::Length, rows_, "a linear motor");
  }

  void add_force(const ForceBodies& b, double* F) override {
    const BlockSides sides = this->sides(b);
    evaluate_rows(rows_, 1, sides, eval_);
    const double f = value(b.t);
    for (int x = 0; x < 2; ++x) {
      if (!sides.state[x]) continue;
      const int vo = b.v_offset[body_[x]];
      for (int k = 0; k < sides.state[x]->nv(); ++k) F[vo + k] -= f * eval_.G[x](0, k);
    }
  }

  void add_jacobian(const ForceBodies& b, JacobianSink& sink) override {
    const BlockSides sides = this->sides(b);
    evaluate_rows(rows_, 1, sides, eval_);
    const double alpha[1] = {-value(b.t)};
    const double* acc[2] = {nullptr, nullptr};
    for (int x = 0; x < 2; ++x)
      if (sides.state[x]) acc[x] = sides.state[x]->v;  // any velocities: dGa_q is not used here
    differentiate_rows(rows_, 1, sides, acc, alpha, nullptr, eval_);
    for (int x = 0; x < 2; ++x) {
      if (!sides.state[x]) continue;
      for (int y = 0; y < 2; ++y)
        if (sides.state[y]) sink.add(b.v_group[body_[x]], b.q_group[body_[y]], 0, 0, eval_.HL[x][y]);
    }
  }

  double potential_energy(const ForceBodies&) override { return 0.0; }
  bool conservative() const override { return false; }
  bool has_power() const override { return true; }
  double power(const ForceBodies& b) override {
    evaluate_rows(rows_, 1, sides(b), eval_);
    return value(b.t) * eval_.Gv(0);
  }

 private:
  BlockSides sides(const ForceBodies& b) const { return joint_sides(body_, b); }
  double value(double t) const { return profile_ ? force_ * profile_->value(t) : force_; }

  int body_[2] = {kGround, kGround};
  double force_ = 0.0;                   // N
  std::optional<TimeFunction> profile_;  // unset: constant
  ConstraintRow rows_[1];
  BlockEval eval_;  // scratch, sized on the stack's bounds: no allocation
};

}  // namespace

// One element per joint with a linear motor (its type lists the keys:
// model/joint_type.hpp; the loader sets the values).
void add_joint_forces(const MultibodySpec& spec, ForceElements& out) {
  for (const JointSpec& js : spec.joints)
    if (js.motor_force != 0.0) out.push_back(std::make_unique<JointForce>(js));
}

}  // namespace rigidae::multibody
