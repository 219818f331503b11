// A run that records nothing (see include/rigidae/app/unrecorded_run.hpp).
#include "rigidae/app/unrecorded_run.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/so3/rotation.hpp"
#include "run_system.hpp"

namespace rigidae {

namespace {

// Keeps the last output state (a copy into storage sized once) and nothing else.
class LastOutput final : public StepSink {
 public:
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double t, const Eigen::VectorXd& y) override {
    t_ = t;
    y_ = y;
  }
  void on_event(const EventNote&) override {}
  bool needs_every_output() const override { return false; }  // the drivers skip the other grid points

  double t_ = 0.0;
  Eigen::VectorXd y_;
};

// Every scene runs as a system of bodies (a one-body scene as one pivoted
// body): its bodies' final orientations, positions and space angular velocities.
UnrecordedRun system_run(const Scene& scene) {
  check_multibody_integrator(scene);
  multibody::MultibodyProblem problem(scene);
  LastOutput sink;
  UnrecordedRun r;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    r.run = run_multibody(problem, scene, sink);
  } catch (const SolverError& e) {
    r.run.status = RunStatus::Failed;
    r.run.message = e.what();
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<Vec4> q;
  std::vector<Vec3> x, w;
  for (int i = 0; i < static_cast<int>(problem.bodies().size()); ++i) {
    r.last.bodies.push_back(problem.bodies()[i].name);
    q.push_back(problem.body_orientation(i, sink.y_.data()));
    x.push_back(problem.body_position(i, sink.y_.data()));
    w.push_back(so3::quaternion_to_matrix(q.back()).transpose() * problem.body_omega_space(i, sink.y_.data()));
  }
  r.last.add_point(sink.t_, std::move(q), std::move(x), std::move(w));
  return r;
}

}  // namespace

UnrecordedRun run_unrecorded(const Scene& scene) { return system_run(as_system(scene)); }

double final_orientation_error(const UnrecordedRun& r, const ReferenceTrajectory& ref) {
  const BodyGrid& g = ref.grid;
  if (!ref.ok || r.run.status != RunStatus::Success || r.last.t.empty() || g.t.empty()) return kNaN;
  if (std::abs(r.last.t[0] - g.t.back()) > 1e-9 * std::max(1.0, std::abs(g.t.back()))) return kNaN;
  const std::vector<Vec4>& q_ref = g.q_WB.back();
  if (q_ref.size() != r.last.q_WB[0].size()) return kNaN;
  double worst = 0.0;
  for (std::size_t b = 0; b < q_ref.size(); ++b)
    worst = std::max(worst, so3::quaternion_distance(r.last.q_WB[0][b], q_ref[b]));
  return worst;
}

}  // namespace rigidae
