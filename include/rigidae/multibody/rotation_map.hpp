#pragma once
// The placement R(q) of a body's rotation coordinates and its partial
// derivatives, which is all a joint needs to know about a representation.
//
//   quaternion (scalar first): R(q) = (w^2 - v.v) I + 2 v v^T + 2 w hat(v), the
//     homogeneous quadratic placement of the Lagrange form (|q|^2 times a
//     rotation): R_k linear in q, R_km constant, third partials zero;
//   linear (the 9 entries of R row by row): R_k = e_i e_j^T for k = 3i + j,
//     higher partials zero;
//   Euler angles (a, b, c) about body axes (i, j, k): R = A(a) B(b) C(c) with
//     elementary rotations, and since d/da A = A hat(e_i), every mixed partial
//     is A hat(e_i)^n0 B hat(e_j)^n1 C hat(e_k)^n2 (orders n0, n1, n2).
// The Euler-form kinematics keep R' = R hat(Omega) exactly in all three (the
// quadratic quaternion placement too: |q| is constant along q' = 1/2 L Omega).
#include <array>
#include <memory>

#include "rigidae/core/types.hpp"
#include "rigidae/model/coordinates.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae {

namespace multibody {

// R and its partials at one q; d2 and d3 only up to the order asked for.
struct RotationPartials {
  int nq = 0;
  Mat3 R;
  std::array<Mat3, 9> d1;                                  // dR/dq_k
  std::array<std::array<Mat3, 9>, 9> d2;                   // d2R/dq_k dq_m (order >= 2)
  std::array<std::array<std::array<Mat3, 3>, 3>, 3> d3;    // Euler angles only (order 3)
  bool d2_zero = false;  // linear coordinates
  bool d3_zero = true;   // quaternion, linear
};

class RotationMap {
 public:
  virtual ~RotationMap() = default;
  virtual int nq() const = 0;
  // Fills out with R and its partials up to `order` (1, 2 or 3) at q. No allocation.
  virtual void evaluate(const double* q, int order, RotationPartials& out) const = 0;
  // Euler angles: the chart the coordinates are in now.
  virtual void set_sequence(const so3::EulerSequence& /*seq*/) {}
};

std::unique_ptr<RotationMap> make_rotation_map(const Coordinates& c, const so3::EulerSequence& seq);

}  // namespace multibody
}  // namespace rigidae
