// A linear spring-damper between two body points ([[springs]], SpringSpec).
//
// e = p_b - p_a, l = |e|, l' = e_hat . e', force on b
//   F = -(k (l - L0) + c l') e_hat   (and -F on a),
// generalized forces Wm_b^T F and -Wm_a^T F (Wm: the point's velocity map,
// body_vector.hpp), with
//   dF/de  = -(k e_hat e_hat^T + (k (l - L0) + c l') (I - e_hat e_hat^T) / l
//             + c e_hat ((I - e_hat e_hat^T) e' / l)^T),
//   dF/de' = -c e_hat e_hat^T,
// and d(Wm^T F)/dq = dWtm(F) + Wm^T dF/dq. Potential 1/2 k (l - L0)^2;
// conservative when c = 0. Coincident ends (l < 1e-12 m) exert no force.
#include "rigidae/multibody/force_element.hpp"

namespace rigidae::multibody {

namespace {

struct SpringEval {
  Vec3 F = Vec3::Zero();
  Mat3 dF_de = Mat3::Zero(), dF_dedot = Mat3::Zero();
};

class Spring final : public ForceElement {
 public:
  explicit Spring(const SpringSpec& s) : s_(s) {}

  void add_force(const ForceBodies& b, double* F) override {
    const BodyState* sa = b.of(s_.body_a);
    const BodyState* sb = b.of(s_.body_b);
    VectorEval ea, eb;
    Vec3 pa = s_.point_a, pb = s_.point_b, va = Vec3::Zero(), vb = Vec3::Zero();
    if (sa) {
      evaluate_vector(*sa, {s_.body_a, s_.point_a, true}, ea);
      pa = ea.value;
      va = ea.Wv;
    }
    if (sb) {
      evaluate_vector(*sb, {s_.body_b, s_.point_b, true}, eb);
      pb = eb.value;
      vb = eb.Wv;
    }
    const SpringEval se = force(pb - pa, vb - va);
    if (sb) {
      const int vo = b.v_offset[s_.body_b];
      for (int k = 0; k < sb->nv(); ++k) F[vo + k] -= eb.Wm.col(k).dot(se.F);
    }
    if (sa) {
      const int vo = b.v_offset[s_.body_a];
      for (int k = 0; k < sa->nv(); ++k) F[vo + k] += ea.Wm.col(k).dot(se.F);
    }
  }

  void add_jacobian(const ForceBodies& b, JacobianSink& sink) override {
    VectorEval e[2];
    Mat3BQ dWw;
    BoundedMat<3, kMaxBodyQ> dFdq;
    BoundedMat<3, kMaxBodyV> dFdv;
    MatBVQ Hq;
    BoundedMat<kMaxBodyV, kMaxBodyV> Hv;
    const int body[2] = {s_.body_a, s_.body_b};
    const Vec3 pt[2] = {s_.point_a, s_.point_b};
    const BodyState* st[2];
    Vec3 p[2], pv[2];
    for (int i = 0; i < 2; ++i) {
      st[i] = b.of(body[i]);
      p[i] = pt[i];
      pv[i].setZero();
      if (st[i]) {
        evaluate_vector(*st[i], {body[i], pt[i], true}, e[i]);
        p[i] = e[i].value;
        pv[i] = e[i].Wv;
      }
    }
    const SpringEval se = force(p[1] - p[0], pv[1] - pv[0]);
    // Generalized force on side i: sign_i Wm_i^T F, sign = -1 (a), +1 (b).
    for (int i = 0; i < 2; ++i) {
      if (!st[i]) continue;
      const double sign_i = i == 0 ? -1.0 : 1.0;
      const int Vi = b.v_group[body[i]];
      vector_dWtm_dq(*st[i], {body[i], pt[i], true}, se.F, Hq);
      sink.add(Vi, b.q_group[body[i]], 0, 0, -sign_i * Hq);
      for (int j = 0; j < 2; ++j) {
        if (!st[j]) continue;
        const double sign_j = j == 0 ? -1.0 : 1.0;  // e = p_b - p_a
        vector_dWw_dq(*st[j], {body[j], pt[j], true}, st[j]->v, dWw);
        dFdq.noalias() = sign_j * (se.dF_de * e[j].D);
        dFdq.noalias() += sign_j * (se.dF_dedot * dWw);
        dFdv.noalias() = sign_j * (se.dF_dedot * e[j].Wm);
        Hq.noalias() = e[i].Wm.transpose() * dFdq;
        Hv.noalias() = e[i].Wm.transpose() * dFdv;
        sink.add(Vi, b.q_group[body[j]], 0, 0, -sign_i * Hq);
        sink.add(Vi, b.v_group[body[j]], 0, 0, -sign_i * Hv);
      }
    }
  }

  double potential_energy(const ForceBodies& b) override {
    VectorEval e;
    Vec3 p[2] = {s_.point_a, s_.point_b};
    const int body[2] = {s_.body_a, s_.body_b};
    for (int k = 0; k < 2; ++k)
      if (const BodyState* st = b.of(body[k])) {
        evaluate_vector(*st, {body[k], p[k], true}, e);
        p[k] = e.value;
      }
    const double stretch = (p[1] - p[0]).norm() - s_.rest_length;
    return 0.5 * s_.stiffness * stretch * stretch;
  }
  bool elastic() const override { return true; }
  bool conservative() const override { return s_.damping == 0.0; }

 private:
  SpringEval force(const Vec3& e, const Vec3& edot) const {
    SpringEval out;
    const double l = e.norm();
    if (l < 1e-12) return out;  // no direction: no force (rest length 0 and coincident points)
    const Vec3 u = e / l;
    const double ldot = u.dot(edot);
    const double tension = s_.stiffness * (l - s_.rest_length) + s_.damping * ldot;
    out.F = -tension * u;
    const Mat3 P = Mat3::Identity() - u * u.transpose();
    out.dF_de = -(s_.stiffness * u * u.transpose() + (tension / l) * P + s_.damping * u * (P * edot / l).transpose());
    out.dF_dedot = -s_.damping * u * u.transpose();
    return out;
  }

  SpringSpec s_;
};

}  // namespace

void add_springs(const MultibodySpec& spec, ForceElements& out) {
  for (const SpringSpec& s : spec.springs) out.push_back(std::make_unique<Spring>(s));
}

}  // namespace rigidae::multibody
