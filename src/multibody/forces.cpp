// Applied forces and their exact derivatives.
//
// Gravity m g and constant space forces act on x only. A constant force in
// the body frame is the direction R F_B (a body vector). A torque tau is
// applied as three couples: forces f_e = 1/2 tau_W x u_e at the tips of the
// body axes u_e = R E_e (and -f_e at the centre of mass), whose moment is
// sum_e u_e x f_e = tau for orthonormal u_e; its generalized force is
// sum_e W(E_e)^T f_e in either form (Euler form: exactly R^T tau_W). A
// body-frame torque uses f_e = 1/2 R (tau_B x E_e).
// A spring-damper between p_a and p_b: e = p_b - p_a, l = |e|, l' = e_hat.e',
// force on b F = -(k (l - L0) + c l') e_hat (and -F on a), generalized forces
// Wm_b^T F and -Wm_a^T F, with
//   dF/de  = -(k e_hat e_hat^T + (k (l - L0) + c l') (I - e_hat e_hat^T) / l
//             + c e_hat ((I - e_hat e_hat^T) e' / l)^T),
//   dF/de' = -c e_hat e_hat^T.
// The dynamic rows hold -f, so every term enters with a minus sign.
// Torsional spring-dampers in revolute joints: torsion.cpp.
#include <cmath>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::multibody {

namespace {

struct SpringEval {
  Vec3 F = Vec3::Zero();
  Mat3 dF_de = Mat3::Zero(), dF_dedot = Mat3::Zero();
};

SpringEval spring_force(const SpringSpec& s, const Vec3& e, const Vec3& edot) {
  SpringEval out;
  const double l = e.norm();
  if (l < 1e-12) return out;  // no direction: no force (rest length 0 and coincident points)
  const Vec3 u = e / l;
  const double ldot = u.dot(edot);
  const double tension = s.stiffness * (l - s.rest_length) + s.damping * ldot;
  out.F = -tension * u;
  const Mat3 P = Mat3::Identity() - u * u.transpose();
  out.dF_de = -(s.stiffness * u * u.transpose() + (tension / l) * P + s.damping * u * (P * edot / l).transpose());
  out.dF_dedot = -s.damping * u * u.transpose();
  return out;
}

}  // namespace

void MultibodyProblem::add_forces(const double* /*y*/, double* F) {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const int vo = groups_[bodies_[i].v_group].offset;
    for (int k = 0; k < 3; ++k) F[vo + k] -= bodies_[i].mass * spec_.gravity_W(k);
  }
  VectorEval ev;
  for (const BodyLoadSpec& load : spec_.loads) {
    const BodyState& st = work_[load.body].st;
    const int vo = groups_[bodies_[load.body].v_group].offset;
    const Vec3 f = load.body_frame ? Vec3(st.P.R * load.force) : load.force;
    for (int k = 0; k < 3; ++k) F[vo + k] -= f(k);
    if (load.torque.isZero(0.0)) continue;
    for (int e = 0; e < 3; ++e) {
      evaluate_vector(st, {load.body, Vec3::Unit(e), false}, ev);
      const Vec3 fe = load.body_frame ? Vec3(0.5 * (st.P.R * load.torque.cross(Vec3::Unit(e))))
                                      : Vec3(0.5 * load.torque.cross(ev.value));
      for (int k = 0; k < st.nv(); ++k) F[vo + k] -= ev.Wm.col(k).dot(fe);
    }
  }
  VectorEval ea, eb;
  for (const SpringSpec& s : spec_.springs) {
    const BodyState* sa = s.body_a == kGround ? nullptr : &work_[s.body_a].st;
    const BodyState* sb = s.body_b == kGround ? nullptr : &work_[s.body_b].st;
    Vec3 pa = s.point_a, pb = s.point_b, va = Vec3::Zero(), vb = Vec3::Zero();
    if (sa) {
      evaluate_vector(*sa, {s.body_a, s.point_a, true}, ea);
      pa = ea.value;
      va = ea.Wv;
    }
    if (sb) {
      evaluate_vector(*sb, {s.body_b, s.point_b, true}, eb);
      pb = eb.value;
      vb = eb.Wv;
    }
    const SpringEval se = spring_force(s, pb - pa, vb - va);
    if (sb) {
      const int vo = groups_[bodies_[s.body_b].v_group].offset;
      for (int k = 0; k < sb->nv(); ++k) F[vo + k] -= eb.Wm.col(k).dot(se.F);
    }
    if (sa) {
      const int vo = groups_[bodies_[s.body_a].v_group].offset;
      for (int k = 0; k < sa->nv(); ++k) F[vo + k] += ea.Wm.col(k).dot(se.F);
    }
  }
  add_torsion_forces(F);
}

void MultibodyProblem::add_force_jacobian(const double* /*y*/, JacobianSink& sink) {
  VectorEval ev;
  MatBVQ H;
  Mat3BQ D;
  for (const BodyLoadSpec& load : spec_.loads) {
    const BodyState& st = work_[load.body].st;
    const int Q = bodies_[load.body].q_group, V = bodies_[load.body].v_group;
    if (load.body_frame) {
      evaluate_vector(st, {load.body, load.force, false}, ev);
      sink.add(V, Q, 0, 0, -ev.D);
    }
    if (load.torque.isZero(0.0)) continue;
    for (int e = 0; e < 3; ++e) {
      evaluate_vector(st, {load.body, Vec3::Unit(e), false}, ev);
      Vec3 fe;
      if (load.body_frame) {
        const Vec3 a = load.torque.cross(Vec3::Unit(e));
        VectorEval ea;
        evaluate_vector(st, {load.body, a, false}, ea);
        fe = 0.5 * ea.value;
        D = 0.5 * ea.D;
      } else {
        fe = 0.5 * load.torque.cross(ev.value);
        D = 0.5 * (so3::hat(load.torque) * ev.D);
      }
      vector_dWtm_dq(st, {load.body, Vec3::Unit(e), false}, fe, H);
      H.noalias() += ev.Wm.transpose() * D;
      sink.add(V, Q, 0, 0, -H);
    }
  }
  VectorEval e[2];
  Mat3BQ dWw;
  BoundedMat<3, kMaxBodyQ> dFdq;
  BoundedMat<3, kMaxBodyV> dFdv;
  MatBVQ Hq;
  BoundedMat<kMaxBodyV, kMaxBodyV> Hv;
  for (const SpringSpec& s : spec_.springs) {
    const int body[2] = {s.body_a, s.body_b};
    const Vec3 pt[2] = {s.point_a, s.point_b};
    const BodyState* st[2];
    Vec3 p[2], pv[2];
    for (int i = 0; i < 2; ++i) {
      st[i] = body[i] == kGround ? nullptr : &work_[body[i]].st;
      p[i] = pt[i];
      pv[i].setZero();
      if (st[i]) {
        evaluate_vector(*st[i], {body[i], pt[i], true}, e[i]);
        p[i] = e[i].value;
        pv[i] = e[i].Wv;
      }
    }
    const SpringEval se = spring_force(s, p[1] - p[0], pv[1] - pv[0]);
    // Generalized force on side i: sign_i Wm_i^T F, sign = -1 (a), +1 (b).
    for (int i = 0; i < 2; ++i) {
      if (!st[i]) continue;
      const double sign_i = i == 0 ? -1.0 : 1.0;
      const int Vi = bodies_[body[i]].v_group;
      vector_dWtm_dq(*st[i], {body[i], pt[i], true}, se.F, Hq);
      sink.add(Vi, bodies_[body[i]].q_group, 0, 0, -sign_i * Hq);
      for (int j = 0; j < 2; ++j) {
        if (!st[j]) continue;
        const double sign_j = j == 0 ? -1.0 : 1.0;  // e = p_b - p_a
        vector_dWw_dq(*st[j], {body[j], pt[j], true}, st[j]->v, dWw);
        dFdq.noalias() = sign_j * (se.dF_de * e[j].D);
        dFdq.noalias() += sign_j * (se.dF_dedot * dWw);
        dFdv.noalias() = sign_j * (se.dF_dedot * e[j].Wm);
        Hq.noalias() = e[i].Wm.transpose() * dFdq;
        Hv.noalias() = e[i].Wm.transpose() * dFdv;
        sink.add(Vi, bodies_[body[j]].q_group, 0, 0, -sign_i * Hq);
        sink.add(Vi, bodies_[body[j]].v_group, 0, 0, -sign_i * Hv);
      }
    }
  }
  add_torsion_jacobian(sink);
}

}  // namespace rigidae::multibody
