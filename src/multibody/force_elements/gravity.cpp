// Gravity: the force m g on every body's centre of mass.
//   Q_x = m g (on x only: the frame's origin is the centre of mass, so no torque)
//   dQ/dq = dQ/dv = 0
//   V = -m g . x
// A pivoted body (no x) is left out of Q: its rotation block carries the
// gravity torque about the pivot (src/multibody/pivot.cpp); its potential
// counts, x being its centre of mass.
#include "rigidae/multibody/force_element.hpp"

namespace rigidae::multibody {

namespace {

class Gravity final : public ForceElement {
 public:
  void add_force(const ForceBodies& b, double* F) override {
    for (std::size_t i = 0; i < b.state.size(); ++i)
      for (int k = 0; k < b.state[i]->nx; ++k) F[b.v_offset[i] + k] -= b.mass[i] * b.gravity_W(k);
  }
  void add_jacobian(const ForceBodies&, JacobianSink&) override {}
  double potential_energy(const ForceBodies& b) override {
    double V = 0.0;
    for (std::size_t i = 0; i < b.state.size(); ++i) V -= b.mass[i] * b.gravity_W.dot(b.state[i]->x());
    return V;
  }
  bool conservative() const override { return true; }
  bool acts_on_pivoted_bodies() const override { return false; }  // x rows only
};

}  // namespace

void add_gravity(const MultibodySpec&, ForceElements& out) { out.push_back(std::make_unique<Gravity>()); }

}  // namespace rigidae::multibody
