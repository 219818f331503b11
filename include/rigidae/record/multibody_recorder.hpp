#pragma once
// Streams a multibody run to disk: trajectory.csv on the output grid (one
// column per quantity, named BODY.qw, JOINT.force_x, ...; see
// MultibodyProblem::output_names), steps.csv per accepted step (step size,
// order, constraint drift, energy error) and events.csv (chart switches per
// body, projections).
#include <filesystem>
#include <vector>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

class MultibodyRecorder final : public StepSink {
 public:
  MultibodyRecorder(multibody::MultibodyProblem& problem, const std::filesystem::path& out_dir);
  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override;
  void on_event(const EventNote& note) override;
  void flush();

  long steps_recorded() const { return steps_recorded_; }
  double max_drift_position() const { return max_drift_position_; }
  double max_drift_velocity() const { return max_drift_velocity_; }
  double max_abs_energy_rel_error() const { return max_energy_error_; }
  double initial_energy() const { return H0_; }
  double last_energy() const { return last_energy_; }

 private:
  multibody::MultibodyProblem& problem_;
  CsvStream steps_, trajectory_, events_;
  std::vector<double> row_;
  int energy_column_ = 0;
  double H0_ = 0.0, last_energy_ = 0.0;
  bool have_H0_ = false;
  long steps_recorded_ = 0;
  double max_drift_position_ = 0.0, max_drift_velocity_ = 0.0, max_energy_error_ = 0.0;
};

}  // namespace rigidae
