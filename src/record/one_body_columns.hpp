#pragma once
// The column set of a one-body scene's run (record/run_columns.hpp):
// steps.csv and trajectory.csv as single bodies have always written them
// (record/columns.hpp's table), read through OneBodyView; events.csv with
// chart switches and projections.
#include "rigidae/multibody/one_body_view.hpp"
#include "rigidae/record/observation.hpp"
#include "rigidae/record/run_columns.hpp"

namespace rigidae {

class OneBodyColumns final : public RunColumns {
 public:
  // `scene`: the one-body scene (outlives this); `system`: one_body_system(scene)'s problem.
  OneBodyColumns(multibody::MultibodyProblem& system, const Scene& scene);

  const columns::Table& table() const override;
  const std::vector<std::string>& value_names(columns::File) const override { return names_; }
  const std::string& units_line(columns::File) const override { return units_; }
  bool with_chart() const override;
  std::string_view chart() const override;
  void observe(columns::File f, double t, const Eigen::VectorXd& y, Observation& o,
               std::span<double> values) override;
  double initial_energy() const override;
  const std::string& events_units() const override { return events_units_; }
  const std::string& events_header() const override { return events_header_; }
  void append_event(fmt::memory_buffer& b, const EventNote& n) const override;
  void add_summary(nlohmann::json& summary, const RunExtremes& x) const override;
  std::string final_report(const RunExtremes& x, double t_reached) const override;
  std::string note(const std::string& scheme_note) const override { return scheme_note; }
  const OneBodyView* one_body() const override { return &view_; }

 private:
  const Scene& scene_;
  OneBodyView view_;
  Observer step_observer_, grid_observer_;
  std::vector<std::string> names_;
  std::string units_, events_units_, events_header_;
  std::string chart_;  // the chart of the last row observed
};

}  // namespace rigidae
