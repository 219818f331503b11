// The accuracy check of a multibody run: see include/rigidae/app/multibody_accuracy_check.hpp.
#include "rigidae/app/multibody_accuracy_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigidae {

namespace {

constexpr double kSmallestSize = 1e-3;  // m

}  // namespace

// The largest distance between the centres of mass and the ground's joint points at the start.
double mechanism_size(const MultibodySpec& spec) {
  std::vector<Vec3> anchors;
  for (const BodySpec& b : spec.bodies) anchors.push_back(b.x0_W);
  for (const JointSpec& j : spec.joints) {
    if (j.body_a == kGround) anchors.push_back(j.point_a);
    if (j.body_b == kGround) anchors.push_back(j.point_b);
  }
  double size = 0.0;
  for (std::size_t i = 0; i < anchors.size(); ++i)
    for (std::size_t k = i + 1; k < anchors.size(); ++k) size = std::max(size, (anchors[i] - anchors[k]).norm());
  // One free body: its joints' reach from its centre of mass.
  for (const JointSpec& j : spec.joints) size = std::max(size, std::max(j.point_a.norm(), j.point_b.norm()));
  return std::max(size, kSmallestSize);
}

MultibodyInvariantMonitor::MultibodyInvariantMonitor(multibody::MultibodyProblem& problem, const Scene& scene,
                                                     StepSink* next)
    : problem_(problem), next_(next), scene_(scene) {
  d_ = {kNaN, kNaN, kNaN, 0.0, 0.0, kNaN};
  const MultibodySpec& spec = *scene.multibody;
  // Every force element says whether it is conservative (an undamped spring,
  // gravity and constant space forces are; dampers, follower loads and
  // torques are not) and whether it reports its power: multibody/force_element.hpp.
  conservative_ = problem_.energy_balance_known();
  has_work_ = problem_.has_work();
  if (conservative_) d_.energy = 0.0;
  size_ = mechanism_size(spec);
  for (const BodySpec& b : spec.bodies) mass_ += b.mass;
}

void MultibodyInvariantMonitor::on_output(double t, const Eigen::VectorXd& y) {
  if (!started_) {  // the driver's first output is the consistent start
    started_ = true;
    const double T0 = problem_.kinetic_energy(y.data());
    h0_ = T0 + problem_.potential_energy(y.data());
    if (has_work_)
      work_.follow(t, y.data(), y.size(), problem_.size(), [&] { return problem_.work_rate(t, y.data()); });
    // A DAE run's W is a quadrature of the drivers' efforts, its multipliers;
    // an ODE run integrates W with the state (and solves the multipliers from it).
    work_from_efforts_ = !scene_.multibody->drivers.empty() &&
                         !multibody::WorkIntegral::carries_work(y.size(), problem_.size());
    // The springs' energy at the start can turn into motion as well (a wound
    // torsion spring released from rest has T0 = 0).
    e_scale_ = T0 + problem_.elastic_energy(y.data()) + scene_.multibody->gravity_W.norm() * size_ * mass_;
    if (!(e_scale_ > 0.0)) e_scale_ = 1.0;  // at rest without gravity or springs' energy: nothing moves
    v_scale_ = std::sqrt(2.0 * e_scale_ / mass_);
    d_.tolerance = scene_.solver.rtol + scene_.solver.atol / std::min({1.0, size_, v_scale_});
  }
  if (next_) next_->on_output(t, y);
}

void MultibodyInvariantMonitor::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  if (next_) next_->on_step(t, h, order, y);
  ++steps_;
  const auto [position, velocity] = problem_.drift(t, y.data());
  d_.constraint_position = std::max(d_.constraint_position, position / size_);
  d_.constraint_velocity = std::max(d_.constraint_velocity, velocity / v_scale_);
  if (conservative_) {
    const double H = problem_.kinetic_energy(y.data()) + problem_.potential_energy(y.data());
    if (has_work_)
      work_.follow(t, y.data(), y.size(), problem_.size(), [&] { return problem_.work_rate(t, y.data()); });
    d_.energy = std::max(d_.energy, std::abs(H - h0_ - work_.value()) / e_scale_);
  }
}

std::vector<AccuracyWarning> MultibodyInvariantMonitor::warnings() const {
  // A driver's work is its effort (a multiplier) times its rate. On IDA the
  // multipliers are outside the error test, held only by the Newton
  // iteration (about rtol^0.75 of their scale): the balance can drift with
  // them while the motion is right (measured on crank_slider_driven, whose
  // driven crank leaves no freedom: 108 of 250 runs within 100 x rtol of the
  // truth warned, docs/accuracy_check.md).
  std::string energy =
      "|H - H0 - W| relative to the kinetic energy plus m |g| L over the mechanism's size L "
      "(W: the work of drivers and loads)";
  if (work_from_efforts_)
    energy += "; W is the drivers' efforts, multipliers that IDA's error test leaves out: the driving "
              "torques and forces may be off rather than the motion";
  return drift_warnings(d_, steps_,
                        {energy,
                         "", "",
                         "max |Phi| over the joints relative to the mechanism's size",
                         "max |G v| over the joints relative to the largest speed"});
}

}  // namespace rigidae

namespace rigidae {

std::unique_ptr<RunMonitor> make_run_monitor(multibody::MultibodyProblem& system, const Scene& scene,
                                             const RunRecorder& recorder, StepSink& next) {
  if (const OneBodyView* one = recorder.columns().one_body())
    return std::make_unique<InvariantMonitor>(*one, scene, recorder, next);
  return std::make_unique<MultibodyInvariantMonitor>(system, scene, &next);
}

}  // namespace rigidae
