// GGL: the stabilized index-2 form of Gear, Gupta and Leimkuhler (1985).
//
// Force kind (Lagrange form):          Kinematic kind (Euler form):
//   q' = v - Phi_q^T mu                  q' = N v - Phi_q^T mu
//   M v' = f - G^T lambda                M v' = f
//   G v = 0                              Phi(q) = 0
//   Phi(q) = 0
// Both constraint levels hold to the Newton tolerance at every step; mu = 0
// on the exact solution. lambda and mu are index 2: they leave IDA's error
// test (IDASetSuppressAlg), as index-2 BDF theory requires.
#include "factories.hpp"

namespace rigidae::schemes {

namespace {

class GglScheme final : public ConstraintScheme {
 public:
  std::string name() const override { return "ggl"; }
  // Force: lambda rows G v, mu rows Phi. Kinematic: mu rows Phi.
  SchemeRows rows() const override {
    return {{true, true, {0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}}, {false, true, {}, {1.0, 0.0, 0.0}}};
  }
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_ggl(const SchemeSettings& /*settings*/) { return std::make_unique<GglScheme>(); }

}  // namespace rigidae::schemes
