#pragma once
// What a run's records hold, column by column: the system's side of the one
// recorder (record/recorder.hpp). The recorder streams rows and keeps the
// run's extremes; a column set says what a row is:
//   table()          the columns of steps.csv / steps.npy and trajectory.csv
//                    (record/columns.hpp), their order, units and number layout
//   value_names(f)   the names of the table's one Multipliers or Values column
//                    in file f (a body's multipliers; a mechanism's per-part
//                    multipliers, reactions, joint coordinates and markers)
//   observe(f, ...)  one row's numbers at (t, y)
//   events.csv       its header and one row per event
//   add_summary      the summary.json keys that are the column set's own
//                    (a single body's final quaternion and multipliers; a
//                    mechanism's recorded parts, mobility, set-aside rows)
// Two column sets exist, both chosen by the model (make_run_columns): a
// system loaded from a one-body scene keeps the single-body files (qw..qz,
// omega_x..z in the body frame, lambda_*/mu_* by constraint, vertical
// momentum, the Euler chart), every other system the mechanism files
// (BODY.qw.., JOINT.force_x.., the global drift and energy).
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rigidae/model/scene.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/record/observation.hpp"
#include "rigidae/solver/ida_driver.hpp"

namespace rigidae {

class OneBodyView;
struct RunExtremes;

class RunColumns {
 public:
  virtual ~RunColumns() = default;
  virtual const columns::Table& table() const = 0;
  virtual const std::vector<std::string>& value_names(columns::File f) const = 0;
  // The first line of file f ("# units: t s; ..."), with the note that the
  // multipliers are not error-controlled where they are not.
  virtual const std::string& units_line(columns::File f) const = 0;
  virtual bool with_chart() const = 0;
  // The Euler-angle chart the run is in now ("" without charts).
  virtual std::string_view chart() const = 0;
  // The numbers of one row of file f at (t, y): `o` for the table's Real
  // columns, `values` (value_names(f).size() of them) for its Values column.
  // Called in time order; a step's energy error counts the work done so far.
  virtual void observe(columns::File f, double t, const Eigen::VectorXd& y, Observation& o,
                       std::span<double> values) = 0;
  // The energy H0 the errors are measured against, J.
  virtual double initial_energy() const = 0;
  virtual const std::string& events_units() const = 0;
  virtual const std::string& events_header() const = 0;
  virtual void append_event(fmt::memory_buffer& b, const EventNote& n) const = 0;
  virtual void add_summary(nlohmann::json& summary, const RunExtremes& x) const = 0;
  // The run's one-line description, given the scheme's note on the first body.
  virtual std::string note(const std::string& scheme_note) const = 0;
  // The lines of `rigidae solve`'s report on the final state, the drift and
  // the invariants (each line "  label  text\n").
  virtual std::string final_report(const RunExtremes& x, double t_reached) const = 0;
  // The one-body reading of the system when that is what the records are
  // (the accuracy check of a single body reads it), else null.
  virtual const OneBodyView* one_body() const { return nullptr; }
};

// Whether the runs of a system record the single-body column set: a system
// loaded from a one-body scene (MultibodySpec::one_body_scene) does, any
// other the mechanism columns. make_run_columns and body_column_prefix read
// this one function, so that what is recorded and what reads it back agree.
bool records_one_body_columns(const MultibodySpec& spec);

// The prefix of body `body`'s columns in the run's files (trajectory.csv):
// "" for the single-body columns (qw..qz, no position), "NAME." for a
// mechanism's (NAME.qw.., NAME.x.., NAME.pivot_force_x..).
std::string body_column_prefix(const MultibodySpec& spec, std::size_t body);

// The column set of a run of `system` (built from as_system(scene)); `scene`
// is the scene as loaded (its integrator says whether the multipliers are
// error-controlled).
std::unique_ptr<RunColumns> make_run_columns(multibody::MultibodyProblem& system, const Scene& scene);

}  // namespace rigidae
