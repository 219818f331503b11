// Markers ([[markers]], MarkerSpec): named points fixed in bodies, their
// position, velocity and acceleration in space (issue 22 item 5).
//
// With the marker's point p = x + R s of its body (body_vector.hpp):
//   position      p
//   velocity      p' = Wm (x', v)
//   acceleration  p'' = Wm (x'', v') + bias   (Euler form: R (omega' x s) +
//                 R omega x (omega x s); Lagrange form from R's partials)
// The accelerations (x'', v') are not part of y: they are solved here from
// the state, as the consistent start does (consistent_start.cpp), from
//   [M G^T; G 0] (v', lambda) = (f, target)
// with the scheme's acceleration-level target (gamma for index3, index2 and
// ggl: the constrained accelerations; index1's and Baumgarte's rows
// otherwise, which is the v' those schemes integrate). So a recorded row's
// acceleration is the one the model has at that state, on the output grid
// as at the steps, whatever the integrator. Not the hot path: it factors a
// sparse system per recorded row (only when the scene has markers).
#include "rigidae/multibody/multibody_problem.hpp"

namespace rigidae::multibody {

void MultibodyProblem::marker_kinematics(double t, const double* y, double* out) {
  if (spec_.markers.empty()) return;
  marker_y_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
  make_consistent(t, marker_y_, marker_yp_);  // at the row's time: a driver's row depends on it
  evaluate(t, y, 2);
  VectorEval e;
  int k = 0;
  for (const MarkerSpec& m : spec_.markers) {
    const BodyState& st = work_[m.body].st;
    evaluate_vector(st, {m.body, m.point, true}, e);
    const double* a = marker_yp_.data() + groups_[bodies_[m.body].v_group].offset;
    Vec3 acc = e.bias;
    for (int c = 0; c < st.nv(); ++c) acc += e.Wm.col(c) * a[c];
    for (const Vec3* v : {&e.value, &e.Wv, &acc})
      for (int c = 0; c < 3; ++c) out[k++] = (*v)(c);
  }
}

}  // namespace rigidae::multibody
