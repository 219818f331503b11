#include "rigidae/app/accuracy.hpp"
#include "error_series.hpp"

#include <algorithm>
#include <cmath>

#include <limits>
#include <optional>
#include <utility>

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

namespace {

// The multipliers' reference values: the run's own system at the reference
// state (its consistent start there, in the start chart: only Euler angles
// have charts, and they have no multipliers). Only a one-body file names
// its multipliers (lambda_*, mu_* by row), so the system is that body's.
class ReferenceMultipliers {
 public:
  ReferenceMultipliers(const Scene& scene, const std::vector<std::string>& run_names)
      : system_scene_(one_body_system(scene)), system_(system_scene_), view_(system_, scene), names_(run_names) {
    const std::vector<std::string> own = view_.multiplier_names();
    for (const std::string& name : names_) {
      const auto it = std::find(own.begin(), own.end(), name);
      position_.push_back(it == own.end() ? -1 : static_cast<int>(it - own.begin()));
    }
  }
  // The largest force (lambda) and kinematic (mu) multiplier errors of one grid point; NaN where there are none.
  std::pair<double, double> errors(double t, const Vec4& q_ref, const Vec3& omega_ref, const std::vector<double>& run) {
    view_.consistent_state(t, so3::quaternion_to_matrix(q_ref), omega_ref, y_, yp_);
    double e_lambda = kNaN, e_mu = kNaN;
    for (std::size_t k = 0; k < names_.size(); ++k) {
      const double exact = position_[k] >= 0 ? y_[view_.multiplier_offset() + position_[k]] : 0.0;
      double& worst = names_[k].rfind("lambda_", 0) == 0 ? e_lambda : e_mu;
      worst = std::max(std::isnan(worst) ? 0.0 : worst, std::abs(run[k] - exact));
    }
    return {e_lambda, e_mu};
  }

 private:
  Scene system_scene_;
  multibody::MultibodyProblem system_;
  OneBodyView view_;
  std::vector<std::string> names_;
  std::vector<int> position_;  // in the system's multiplier order; -1: not one of its rows (exact value 0)
  Eigen::VectorXd y_, yp_;
};

}  // namespace

RunAccuracy measure_accuracy(const Scene& scene, const BodyGrid& run, const ReferenceTrajectory& ref,
                             bool reached_end) {
  RunAccuracy acc;
  if (!ref.ok) return acc;
  const BodyGrid& r = ref.grid;
  const std::size_t n = std::min(run.t.size(), r.t.size());
  const std::size_t nb = std::min(run.bodies.size(), r.bodies.size());
  reached_end = reached_end && n == r.t.size() && n > 0 && nb == r.bodies.size();
  const bool positions = run.has_positions() && r.has_positions();
  std::optional<ReferenceMultipliers> multipliers;
  if (!run.multiplier_names.empty()) multipliers.emplace(scene, run.multiplier_names);

  ErrorSeries orientation, omega, position, lambda, mu;
  for (std::size_t i = 0; i < n; ++i) {
    double a = 0.0, w = 0.0, x = 0.0;
    for (std::size_t b = 0; b < nb; ++b) {
      a = std::max(a, so3::quaternion_distance(run.q_WB[i][b], r.q_WB[i][b]));
      w = std::max(w, (run.omega_B[i][b] - r.omega_B[i][b]).norm());
      if (positions) x = std::max(x, (run.x_W[i][b] - r.x_W[i][b]).norm());
    }
    orientation.add(a);
    omega.add(w);
    if (positions) position.add(x);
    if (!multipliers) continue;
    const auto [e_lambda, e_mu] = multipliers->errors(r.t[i], r.q_WB[i][0], r.omega_B[i][0], run.multipliers[i]);
    if (!std::isnan(e_lambda)) lambda.add(e_lambda);
    if (!std::isnan(e_mu)) mu.add(e_mu);
  }
  acc.points_compared = static_cast<long>(n);
  acc.orientation_rad = orientation.stats(reached_end);
  acc.angular_velocity = omega.stats(reached_end);
  acc.position_m = position.stats(reached_end);
  acc.lambda = lambda.stats(reached_end);
  acc.mu = mu.stats(reached_end);
  if (reached_end) {
    // Each body's final physical state: q (aligned in sign: q and -q are the
    // same rotation), x where recorded, omega_B.
    const int per_body = positions ? 10 : 7;
    Eigen::VectorXd y(per_body * nb), y_ref(per_body * nb);
    for (std::size_t b = 0; b < nb; ++b) {
      Vec4 q = run.q_WB[n - 1][b];
      const Vec4& q_ref = r.q_WB[n - 1][b];
      if (q.dot(q_ref) < 0.0) q = -q;
      const Eigen::Index o = static_cast<Eigen::Index>(per_body * b);
      y.segment<4>(o) = q;
      y_ref.segment<4>(o) = q_ref;
      if (positions) {
        y.segment<3>(o + 4) = run.x_W[n - 1][b];
        y_ref.segment<3>(o + 4) = r.x_W[n - 1][b];
      }
      y.segment<3>(o + per_body - 3) = run.omega_B[n - 1][b];
      y_ref.segment<3>(o + per_body - 3) = r.omega_B[n - 1][b];
    }
    acc.scd = significant_correct_digits(y, y_ref);
    acc.mescd = mixed_significant_correct_digits(y, y_ref, scene.solver.atol / scene.solver.rtol);
  }
  return acc;
}

RunAccuracy measure_run_accuracy(const Scene& scene, const std::filesystem::path& run_dir,
                                 const ReferenceTrajectory& ref, bool reached_end) {
  return measure_accuracy(scene, read_trajectory_csv(run_dir / "trajectory.csv"), ref, reached_end);
}

}  // namespace rigidae
