#pragma once
// The column set of a mechanism's run (record/run_columns.hpp): steps.csv
// with the step size, order, largest drift and the energy balance, then per
// recorded part its multipliers, reactions, residuals, joint coordinates and
// markers (MultibodyProblem::step_part_names); trajectory.csv with every
// recorded body's pose and velocities, joint reactions and coordinates,
// markers and the momenta (MultibodyProblem::output_names); events.csv with
// chart switches per body, projections, row-subset changes and singular
// poses. The scene's [output] bodies / joints say which parts
// (model/recorded_parts.hpp).
#include "rigidae/model/recorded_parts.hpp"
#include "rigidae/multibody/work_integral.hpp"
#include "rigidae/record/run_columns.hpp"

namespace rigidae {

class MechanismColumns final : public RunColumns {
 public:
  MechanismColumns(multibody::MultibodyProblem& problem, const Scene& scene);

  const columns::Table& table() const override;
  const std::vector<std::string>& value_names(columns::File f) const override {
    return f == columns::kSteps ? step_names_ : grid_names_;
  }
  const std::string& units_line(columns::File f) const override {
    return f == columns::kSteps ? step_units_ : grid_units_;
  }
  bool with_chart() const override { return false; }
  std::string_view chart() const override { return {}; }
  void observe(columns::File f, double t, const Eigen::VectorXd& y, Observation& o,
               std::span<double> values) override;
  double initial_energy() const override { return H0_; }
  const std::string& events_units() const override { return events_units_; }
  const std::string& events_header() const override { return events_header_; }
  void append_event(fmt::memory_buffer& b, const EventNote& n) const override;
  void add_summary(nlohmann::json& summary, const RunExtremes& x) const override;
  std::string final_report(const RunExtremes& x, double t_reached) const override;
  std::string note(const std::string& scheme_note) const override;

 private:
  // Sets H0 at the first state seen (the start) and returns (H - H0 - W) / max(|H0|, 1 J).
  double energy_error(double t, const Eigen::VectorXd& y, double H);

  multibody::MultibodyProblem& problem_;
  RecordedParts step_parts_, grid_parts_;
  std::vector<std::string> step_names_, grid_names_;
  std::string step_units_, grid_units_, events_units_, events_header_;
  int energy_column_ = 0;
  double H0_ = 0.0;
  bool have_H0_ = false;
  // The work of drivers and loads without a potential (energy_rel_error is
  // (H - H0 - W) / max(|H0|, 1 J)); off for a scene without them.
  bool has_work_ = false;
  multibody::WorkIntegral work_;
};

}  // namespace rigidae
