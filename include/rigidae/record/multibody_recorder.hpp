#pragma once
// Streams a multibody run to disk: trajectory.csv on the output grid (one
// column per quantity, named BODY.qw, JOINT.force_x, ...; see
// MultibodyProblem::output_names), steps.csv per accepted step (step size,
// order, constraint drift, energy error, then per recorded part its
// multipliers, reactions and drift: MultibodyProblem::step_part_names; or
// steps.npy, the same rows in NumPy's format) and events.csv (chart switches
// per body, projections); the output settings say which
// (record/recorder.hpp), the scene's [output] bodies / joints which parts
// (model/recorded_parts.hpp).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/multibody/work_integral.hpp"
#include "rigidae/record/npy_file.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

class MultibodyRecorder final : public StepSink {
 public:
  // `time`: the run's grid (the start is reported first, always, and is a row
  // of trajectory.csv only when it is an output time).
  MultibodyRecorder(multibody::MultibodyProblem& problem, const std::filesystem::path& out_dir,
                    const OutputSettings& output = {}, const TimeGrid& time = {},
                    const std::string& integrator = "ida");
  void on_step(double t, double h, int order, const Eigen::VectorXd& y) override;
  void on_output(double t, const Eigen::VectorXd& y) override;
  void on_event(const EventNote& note) override;
  void flush();
  // Flushes, syncs and closes every file (the .npy header gets its row count);
  // throws OutputError naming the first that fails.
  void close();

  long steps_recorded() const { return steps_recorded_; }
  double max_drift_position() const { return max_drift_position_; }
  double max_drift_velocity() const { return max_drift_velocity_; }
  double max_abs_energy_rel_error() const { return max_energy_error_; }
  double initial_energy() const { return H0_; }
  double last_energy() const { return last_energy_; }
  // The parts with columns in the step file and in trajectory.csv.
  const RecordedParts& step_parts() const { return step_parts_; }
  const RecordedParts& grid_parts() const { return grid_parts_; }
  // The step file's columns and its units line (without "# ").
  std::vector<std::string> step_columns() const;
  std::string step_units() const;

 private:
  multibody::MultibodyProblem& problem_;
  RecordedParts step_parts_, grid_parts_;
  std::vector<std::string> step_part_names_;
  std::string step_units_more_;  // the units of the per-part columns, the error-control note
  std::vector<double> step_values_;  // the per-part columns of one step row, reused
  CsvStream events_;  // created first, then the step file and trajectory.csv
  StepFile steps_;
  std::unique_ptr<CsvStream> trajectory_;
  std::vector<double> row_;
  int energy_column_ = 0;
  double H0_ = 0.0, last_energy_ = 0.0;
  bool have_H0_ = false;
  bool start_is_output_ = true, seen_start_ = false;
  long steps_recorded_ = 0;
  double max_drift_position_ = 0.0, max_drift_velocity_ = 0.0, max_energy_error_ = 0.0;
  // The work of drivers and loads without a potential (energy_rel_error is
  // (H - H0 - W) / max(|H0|, 1 J)); off for a scene without them.
  bool has_work_ = false;
  multibody::WorkIntegral work_;
};

}  // namespace rigidae
