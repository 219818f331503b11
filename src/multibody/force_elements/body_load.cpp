// A force (at the centre of mass) and torque on one body ([[loads]],
// BodyLoadSpec), in space or in the body frame: constant, or both scaled by
// s(t), the load's profile (model/time_function.hpp); every formula below
// holds with F, tau replaced by s(t) F, s(t) tau (t is not an unknown, so
// the iteration matrix only scales). A profiled load has a time-dependent
// potential and is not conservative: the energy check counts its work.
//
// A space force F acts on x only: Q_x = F, V = -F . x. A body-frame force
// acts on x too, Q_x = R F_B: the direction F_B fixed in the body, so
// dQ_x/dq is that body vector's D (a follower load: no potential). A torque tau is applied as three
// couples: forces f_e = 1/2 tau_W x u_e at the tips of the body axes
// u_e = R E_e (and -f_e at the centre of mass), whose moment is
// sum_e u_e x f_e = tau for orthonormal u_e; its generalized force is
// sum_e W(E_e)^T f_e in either form (Euler form: exactly R^T tau_W). A
// body-frame torque uses f_e = 1/2 R (tau_B x E_e). A torque has no
// potential that rigidae tracks, so a load with one is not conservative.
// On a pivoted body (no x) the force acts at the centre of mass through the
// lever R c: Q = W_c^T F, dQ/dq = dWtm_c(F) + W_c^T dF/dq (dF/dq: the
// body-frame direction's D, else 0), W_c the centre of mass's velocity map.
#include "rigidae/multibody/force_element.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::multibody {

namespace {

class BodyLoad final : public ForceElement {
 public:
  explicit BodyLoad(const BodyLoadSpec& load) : spec_(load), load_(load) {}

  void add_force(const ForceBodies& b, double* F) override {
    scale(b.t);
    const BodyState& st = *b.of(load_.body);
    const int vo = b.v_offset[load_.body];
    const Vec3 f = load_.body_frame ? Vec3(st.P.R * load_.force) : load_.force;
    VectorEval ev;
    if (st.nx == 3) {
      for (int k = 0; k < 3; ++k) F[vo + k] -= f(k);
    } else {
      evaluate_vector(st, {load_.body, Vec3::Zero(), true}, ev);
      for (int k = 0; k < st.nv(); ++k) F[vo + k] -= ev.Wm.col(k).dot(f);
    }
    if (load_.torque.isZero(0.0)) return;
    for (int e = 0; e < 3; ++e) {
      evaluate_vector(st, {load_.body, Vec3::Unit(e), false}, ev);
      const Vec3 fe = load_.body_frame ? Vec3(0.5 * (st.P.R * load_.torque.cross(Vec3::Unit(e))))
                                       : Vec3(0.5 * load_.torque.cross(ev.value));
      for (int k = 0; k < st.nv(); ++k) F[vo + k] -= ev.Wm.col(k).dot(fe);
    }
  }

  void add_jacobian(const ForceBodies& b, JacobianSink& sink) override {
    scale(b.t);
    const BodyState& st = *b.of(load_.body);
    const int Q = b.q_group[load_.body], V = b.v_group[load_.body];
    VectorEval ev;
    MatBVQ H;
    Mat3BQ D;
    if (st.nx == 0) {
      VectorEval com;
      evaluate_vector(st, {load_.body, Vec3::Zero(), true}, com);
      Vec3 f = load_.force;
      if (load_.body_frame) {
        evaluate_vector(st, {load_.body, load_.force, false}, ev);
        f = ev.value;
      }
      vector_dWtm_dq(st, {load_.body, Vec3::Zero(), true}, f, H);
      if (load_.body_frame) H.noalias() += com.Wm.transpose() * ev.D;
      sink.add(V, Q, 0, 0, -H);
    } else if (load_.body_frame) {
      evaluate_vector(st, {load_.body, load_.force, false}, ev);
      sink.add(V, Q, 0, 0, -ev.D);
    }
    if (load_.torque.isZero(0.0)) return;
    for (int e = 0; e < 3; ++e) {
      evaluate_vector(st, {load_.body, Vec3::Unit(e), false}, ev);
      Vec3 fe;
      if (load_.body_frame) {
        const Vec3 a = load_.torque.cross(Vec3::Unit(e));
        VectorEval ea;
        evaluate_vector(st, {load_.body, a, false}, ea);
        fe = 0.5 * ea.value;
        D = 0.5 * ea.D;
      } else {
        fe = 0.5 * load_.torque.cross(ev.value);
        D = 0.5 * (so3::hat(load_.torque) * ev.D);
      }
      vector_dWtm_dq(st, {load_.body, Vec3::Unit(e), false}, fe, H);
      H.noalias() += ev.Wm.transpose() * D;
      sink.add(V, Q, 0, 0, -H);
    }
  }

  // A space force's potential -F . x; a follower force or a torque: none tracked.
  double potential_energy(const ForceBodies& b) override {
    return force_potential_tracked() ? -load_.force.dot(b.of(load_.body)->x()) : 0.0;
  }
  bool conservative() const override {
    return !spec_.profile && !load_.body_frame && load_.torque.norm() == 0.0;
  }

  // The power Q . v at the bodies' evaluation of what potential_energy does
  // not track (the work the energy check counts): a constant space force's
  // work is already its potential's change, so a load that is not
  // conservative only because of its torque counts the torque's power alone.
  bool has_power() const override { return true; }
  double power(const ForceBodies& b) override {
    scale(b.t);
    const BodyState& st = *b.of(load_.body);
    double p = 0.0;
    VectorEval ev;
    if (!force_potential_tracked()) {
      // The centre of mass's velocity (x' for a free body; W_c v for a pivoted one).
      const Vec3 f = load_.body_frame ? Vec3(st.P.R * load_.force) : load_.force;
      evaluate_vector(st, {load_.body, Vec3::Zero(), true}, ev);
      p += f.dot(ev.Wv);
    }
    if (load_.torque.isZero(0.0)) return p;
    for (int e = 0; e < 3; ++e) {
      evaluate_vector(st, {load_.body, Vec3::Unit(e), false}, ev);
      const Vec3 fe = load_.body_frame ? Vec3(0.5 * (st.P.R * load_.torque.cross(Vec3::Unit(e))))
                                       : Vec3(0.5 * load_.torque.cross(ev.value));
      p += ev.Wv.dot(fe);
    }
    return p;
  }

 private:
  bool force_potential_tracked() const { return !spec_.profile && !load_.body_frame; }
  // load_ = spec_ scaled by the profile at t (no allocation).
  void scale(double t) {
    if (!spec_.profile) return;
    const double s = spec_.profile->value(t);
    load_.force = s * spec_.force;
    load_.torque = s * spec_.torque;
  }
  BodyLoadSpec spec_;
  BodyLoadSpec load_;
};

}  // namespace

void add_body_loads(const MultibodySpec& spec, ForceElements& out) {
  for (const BodyLoadSpec& l : spec.loads) out.push_back(std::make_unique<BodyLoad>(l));
}

}  // namespace rigidae::multibody
