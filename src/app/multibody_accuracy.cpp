// How far a multibody run is from its tight reference (see app/accuracy.hpp):
// per grid point the worst body, by group.
#include <algorithm>
#include <cmath>

#include "rigidae/app/accuracy.hpp"
#include "error_series.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

using Series = detail::ErrorSeries;

}  // namespace

RunAccuracy measure_multibody_accuracy(const Scene& scene, const BodyGrid& run, const ReferenceTrajectory& ref,
                                       bool reached_end) {
  RunAccuracy acc;
  if (!ref.ok || !ref.multibody) return acc;
  const BodyGrid& r = ref.bodies;
  const std::size_t n = std::min(run.t.size(), r.t.size());
  const std::size_t nb = std::min(run.bodies.size(), r.bodies.size());
  reached_end = reached_end && n == r.t.size() && n > 0 && nb == r.bodies.size();
  Series rot, omega, pos;
  for (std::size_t i = 0; i < n; ++i) {
    double a = 0.0, w = 0.0, x = 0.0;
    for (std::size_t b = 0; b < nb; ++b) {
      a = std::max(a, so3::quaternion_distance(run.q_WB[i][b], r.q_WB[i][b]));
      w = std::max(w, (run.omega_W[i][b] - r.omega_W[i][b]).norm());
      x = std::max(x, (run.x_W[i][b] - r.x_W[i][b]).norm());
    }
    rot.add(a);
    omega.add(w);
    pos.add(x);
  }
  acc.points_compared = static_cast<long>(n);
  acc.orientation_rad = rot.stats(reached_end);
  acc.angular_velocity = omega.stats(reached_end);
  acc.position_m = pos.stats(reached_end);
  if (reached_end) {
    Eigen::VectorXd y(10 * nb), y_ref(10 * nb);
    for (std::size_t b = 0; b < nb; ++b) {
      Vec4 q = run.q_WB[n - 1][b];
      const Vec4& q_ref = r.q_WB[n - 1][b];
      if (q.dot(q_ref) < 0.0) q = -q;  // q and -q are the same rotation
      y.segment<10>(10 * b) << q, run.x_W[n - 1][b], run.omega_W[n - 1][b];
      y_ref.segment<10>(10 * b) << q_ref, r.x_W[n - 1][b], r.omega_W[n - 1][b];
    }
    acc.scd = significant_correct_digits(y, y_ref);
    acc.mescd = mixed_significant_correct_digits(y, y_ref, scene.solver.atol / scene.solver.rtol);
  }
  return acc;
}

RunAccuracy measure_run_accuracy(const Scene& scene, const std::filesystem::path& run_dir,
                                 const ReferenceTrajectory& ref, bool reached_end) {
  if (scene.multibody)
    return measure_multibody_accuracy(scene, read_body_grid(run_dir / "trajectory.csv"), ref, reached_end);
  return measure_accuracy(scene, read_trajectory_csv(run_dir / "trajectory.csv"), ref, reached_end);
}

}  // namespace rigidae
