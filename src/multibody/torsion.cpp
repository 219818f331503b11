// A torsional spring-damper in a revolute joint: its angle, generalized
// forces, exact derivatives and potential energy.
//
// The angle of b relative to a about the joint axis, from the two bodies'
// orientations: with n_a, z_a the normal and axis fixed in a, n_b the normal
// fixed in b (all carried to space by their bodies),
//   C = n_a . n_b,   S = (z_a x n_a) . n_b,   theta = atan2(S, C)
// (on the branch continuous with the last accepted step: a spring wound
// past half a turn keeps its sign). C and S are dot products of body
// vectors, so the constraint-row machinery (constraint_rows.hpp) gives
// their partials: Phi_q (dC/dq), G (C' = G_C v) and d(G^T l)/dq. With
// r2 = C^2 + S^2 (= 1 while the axes stay parallel):
//   dtheta/dq = (C S_q - S C_q) / r2,    theta' = G_theta v,
//   G_theta   = (C G_S - S G_C) / r2.
// The torque on b about the axis is -T, T = k (theta - theta0) + c theta',
// and +T on a; its generalized force (power T theta') is Q = -T G_theta^T
// over both bodies' velocities, so the dynamic rows (which hold -f) gain
//   + T G_theta^T = G_C^T alpha_C + G_S^T alpha_S,  alpha = T (-S, C) / r2.
// Exact iteration matrix (rows of body X's velocities, columns of body Y):
//   d/dq_Y = d(G^T alpha)/dq_Y |alpha fixed  (HL of constraint_rows)
//          + G_C[X]^T dalpha_C/dq_Y + G_S[X]^T dalpha_S/dq_Y
//   dalpha_C/dq = -T d(S/r2)/dq - (S/r2) dT/dq,  dalpha_S/dq = T d(C/r2)/dq + (C/r2) dT/dq
//   dT/dq = k dtheta/dq + c dtheta'/dq,
//   dtheta'/dq = (C_q S' + C S'_q - S_q C' - S C'_q)/r2 - 2 theta' (C C_q + S S_q)/r2
//   d/dv_Y = c G_theta[X]^T G_theta[Y]
// (C'_q = d(G_C v)/dq, dGv_q of constraint_rows). Potential 1/2 k (theta - theta0)^2.
#include <cmath>
#include <numbers>

#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::multibody {

namespace {

BodyVector direction(int body, const Vec3& s) { return {body, s, false}; }

// Rows over one body's coordinates or velocities (row vectors must be row-major in Eigen).
using RowQ = Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxBodyQ>;
using RowV = Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxBodyV>;

}  // namespace

std::vector<TorsionSpring> torsion_springs(const MultibodySpec& spec) {
  std::vector<TorsionSpring> out;
  for (int j = 0; j < static_cast<int>(spec.joints.size()); ++j) {
    const JointSpec& js = spec.joints[j];
    if (js.type != JointType::Revolute || (js.torsion_stiffness == 0.0 && js.torsion_damping == 0.0)) continue;
    TorsionSpring t;
    t.joint = j;
    t.body[0] = js.body_a;
    t.body[1] = js.body_b;
    t.stiffness = js.torsion_stiffness;
    t.damping = js.torsion_damping;
    t.rest_angle = js.torsion_rest_angle;
    t.rows[0].name = "cos";
    t.rows[0].terms[0] = {1.0, direction(js.body_a, js.normal_a), direction(js.body_b, js.normal_b)};
    t.rows[1].name = "sin";
    t.rows[1].terms[0] = {1.0, direction(js.body_a, js.axis_a.cross(js.normal_a)), direction(js.body_b, js.normal_b)};
    out.push_back(t);
  }
  return out;
}

BlockSides MultibodyProblem::torsion_sides(const TorsionSpring& ts) const {
  BlockSides sides;
  for (int x = 0; x < 2; ++x) {
    sides.body[x] = ts.body[x];
    sides.state[x] = ts.body[x] == kGround ? nullptr : &work_[ts.body[x]].st;
  }
  return sides;
}

double MultibodyProblem::torsion_angle(const TorsionSpring& ts, const BlockEval& e) const {
  const double raw = std::atan2(e.phi(1), e.phi(0));
  return ts.reference + std::remainder(raw - ts.reference, 2.0 * std::numbers::pi);
}

void MultibodyProblem::add_torsion_forces(double* F) {
  BlockEval& e = torsion_eval_;
  for (const TorsionSpring& ts : torsions_) {
    const BlockSides sides = torsion_sides(ts);
    evaluate_rows(ts.rows, 2, sides, e);
    const double C = e.phi(0), S = e.phi(1), r2 = C * C + S * S;
    const double rate = (C * e.Gv(1) - S * e.Gv(0)) / r2;
    const double T = ts.stiffness * (torsion_angle(ts, e) - ts.rest_angle) + ts.damping * rate;
    for (int x = 0; x < 2; ++x) {
      if (!sides.state[x]) continue;
      const int vo = groups_[bodies_[ts.body[x]].v_group].offset;
      for (int k = 0; k < sides.state[x]->nv(); ++k) F[vo + k] += T * (C * e.G[x](1, k) - S * e.G[x](0, k)) / r2;
    }
  }
}

void MultibodyProblem::add_torsion_jacobian(JacobianSink& sink) {
  BlockEval& e = torsion_eval_;
  RowQ theta_q[2], rate_q[2], dT_q[2], dalpha_c[2], dalpha_s[2];
  RowV g_theta[2];
  MatBVQ Hq;
  BoundedMat<kMaxBodyV, kMaxBodyV> Hv;
  for (const TorsionSpring& ts : torsions_) {
    const BlockSides sides = torsion_sides(ts);
    evaluate_rows(ts.rows, 2, sides, e);
    const double C = e.phi(0), S = e.phi(1), r2 = C * C + S * S;
    const double Cd = e.Gv(0), Sd = e.Gv(1);
    const double rate = (C * Sd - S * Cd) / r2;
    const double T = ts.stiffness * (torsion_angle(ts, e) - ts.rest_angle) + ts.damping * rate;
    const double alpha[2] = {-T * S / r2, T * C / r2};
    const double* acc[2] = {nullptr, nullptr};
    for (int x = 0; x < 2; ++x)
      if (sides.state[x]) acc[x] = sides.state[x]->v;  // any velocities: dGa_q is not used here
    // Keep the first pass's values: differentiate_rows fills only the derivative fields.
    differentiate_rows(ts.rows, 2, sides, acc, alpha, nullptr, e);
    for (int y = 0; y < 2; ++y) {
      if (!sides.state[y]) continue;
      const auto Cq = e.phi_q[y].row(0), Sq = e.phi_q[y].row(1);
      const RowQ r2_q = 2.0 * (C * Cq + S * Sq);
      theta_q[y] = (C * Sq - S * Cq) / r2;
      g_theta[y] = (C * e.G[y].row(1) - S * e.G[y].row(0)) / r2;
      rate_q[y] = (Cq * Sd + C * e.dGv_q[y].row(1) - Sq * Cd - S * e.dGv_q[y].row(0)) / r2 - rate * r2_q / r2;
      dT_q[y] = ts.stiffness * theta_q[y] + ts.damping * rate_q[y];
      // d(S/r2) = (S_q - S r2_q / r2) / r2, and the same for C.
      dalpha_c[y] = -T * (Sq - S * r2_q / r2) / r2 - (S / r2) * dT_q[y];
      dalpha_s[y] = T * (Cq - C * r2_q / r2) / r2 + (C / r2) * dT_q[y];
    }
    for (int x = 0; x < 2; ++x) {
      if (!sides.state[x]) continue;
      const int Vx = bodies_[ts.body[x]].v_group;
      for (int y = 0; y < 2; ++y) {
        if (!sides.state[y]) continue;
        Hq = e.HL[x][y];
        Hq.noalias() += e.G[x].row(0).transpose() * dalpha_c[y];
        Hq.noalias() += e.G[x].row(1).transpose() * dalpha_s[y];
        sink.add(Vx, bodies_[ts.body[y]].q_group, 0, 0, Hq);
        Hv.noalias() = ts.damping * (g_theta[x].transpose() * g_theta[y]);
        sink.add(Vx, bodies_[ts.body[y]].v_group, 0, 0, Hv);
      }
    }
  }
}

void MultibodyProblem::follow_torsion_angles() {
  for (TorsionSpring& ts : torsions_) {
    evaluate_rows(ts.rows, 2, torsion_sides(ts), torsion_eval_);
    ts.reference = torsion_angle(ts, torsion_eval_);
  }
}

double MultibodyProblem::torsion_potential_energy() {
  double V = 0.0;
  for (const TorsionSpring& ts : torsions_) {
    evaluate_rows(ts.rows, 2, torsion_sides(ts), torsion_eval_);
    const double d = torsion_angle(ts, torsion_eval_) - ts.rest_angle;
    V += 0.5 * ts.stiffness * d * d;
  }
  return V;
}

}  // namespace rigidae::multibody
