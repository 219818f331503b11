#include "rigidae/app/accuracy.hpp"
#include "error_series.hpp"

#include <algorithm>
#include <cmath>

#include <optional>

#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/multibody/one_body_view.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

namespace {

using ErrorSeries = detail::ErrorSeries;

// As the IVP Test Set's report code: an error below the unit round-off
// counts as the round-off, so an exact match gives ~15.95 digits, not +inf.
double digits(double worst) { return -std::log10(std::max(worst, std::numeric_limits<double>::epsilon() / 2)); }

// Reference components this small carry no relative accuracy; the Test Set skips them.
constexpr double kNegligible = 1e-200;

Eigen::VectorXd physical_state(const Vec4& q, const Vec3& omega) {
  Eigen::VectorXd y(7);
  y << q, omega;
  return y;
}

}  // namespace

double significant_correct_digits(const Eigen::VectorXd& y, const Eigen::VectorXd& y_ref) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (std::abs(y_ref[i]) >= kNegligible) worst = std::max(worst, std::abs(y[i] - y_ref[i]) / std::abs(y_ref[i]));
  return digits(worst);
}

double mixed_significant_correct_digits(const Eigen::VectorXd& y, const Eigen::VectorXd& y_ref,
                                        double atol_over_rtol) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    worst = std::max(worst, std::abs(y[i] - y_ref[i]) / (atol_over_rtol + std::abs(y_ref[i])));
  return digits(worst);
}

RunAccuracy measure_accuracy(const Scene& scene, const GridTrajectory& run, const ReferenceTrajectory& ref,
                             bool reached_end) {
  RunAccuracy acc;
  if (!ref.ok) return acc;
  const std::size_t n = std::min(run.t.size(), ref.t.size());
  reached_end = reached_end && n == ref.t.size() && n > 0;

  // The exact multipliers: the system's consistent state at the reference's
  // physical state (the start chart: only Euler angles have charts, and
  // they have no multipliers).
  std::optional<Scene> system_scene;
  std::optional<multibody::MultibodyProblem> system;
  std::optional<OneBodyView> dae;
  if (!run.multiplier_names.empty()) {
    system_scene.emplace(one_body_system(scene));
    system.emplace(*system_scene);
    dae.emplace(*system, scene);
  }
  std::vector<int> lambda_cols, mu_cols;  // positions in the DAE's multiplier order
  Eigen::VectorXd y, yp;
  int first_multiplier = 0;
  if (dae) {
    const std::vector<std::string> names = dae->multiplier_names();
    for (std::size_t k = 0; k < run.multiplier_names.size(); ++k) {
      const auto it = std::find(names.begin(), names.end(), run.multiplier_names[k]);
      const int pos = it == names.end() ? -1 : static_cast<int>(it - names.begin());
      (run.multiplier_names[k].rfind("lambda_", 0) == 0 ? lambda_cols : mu_cols).push_back(pos);
    }
    first_multiplier = dae->multiplier_offset();
  }

  ErrorSeries orientation, omega, lambda, mu;
  for (std::size_t i = 0; i < n; ++i) {
    orientation.add(so3::quaternion_distance(run.q_WB[i], ref.q_WB[i]));
    omega.add((run.omega_B[i] - ref.omega_B[i]).norm());
    if (!dae) continue;
    dae->consistent_state(ref.t[i], so3::quaternion_to_matrix(ref.q_WB[i]), ref.omega_B[i], y, yp);
    double e_lambda = 0.0, e_mu = 0.0;
    std::size_t li = 0, mi = 0;
    for (std::size_t k = 0; k < run.multiplier_names.size(); ++k) {
      const bool force = run.multiplier_names[k].rfind("lambda_", 0) == 0;
      const int pos = force ? lambda_cols[li++] : mu_cols[mi++];
      const double exact = pos >= 0 ? y[first_multiplier + pos] : 0.0;
      const double e = std::abs(run.multipliers[i][k] - exact);
      (force ? e_lambda : e_mu) = std::max(force ? e_lambda : e_mu, e);
    }
    if (!lambda_cols.empty()) lambda.add(e_lambda);
    if (!mu_cols.empty()) mu.add(e_mu);
  }
  acc.points_compared = static_cast<long>(n);
  acc.orientation_rad = orientation.stats(reached_end);
  acc.angular_velocity = omega.stats(reached_end);
  acc.lambda = lambda.stats(reached_end);
  acc.mu = mu.stats(reached_end);
  if (reached_end) {
    Vec4 q = run.q_WB[n - 1];
    const Vec4& q_ref = ref.q_WB[n - 1];
    if (q.dot(q_ref) < 0.0) q = -q;  // q and -q are the same rotation
    const Eigen::VectorXd y_run = physical_state(q, run.omega_B[n - 1]);
    const Eigen::VectorXd y_ref = physical_state(q_ref, ref.omega_B[n - 1]);
    acc.scd = significant_correct_digits(y_run, y_ref);
    acc.mescd = mixed_significant_correct_digits(y_run, y_ref, scene.solver.atol / scene.solver.rtol);
  }
  return acc;
}

}  // namespace rigidae
