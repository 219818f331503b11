#include "rigidae/record/recorder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "rigidae/core/error.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/record/error_control.hpp"

namespace rigidae {

namespace {

constexpr std::size_t kWriteBuffer = 1 << 20;

}  // namespace

CsvStream::CsvStream(const std::filesystem::path& path, const std::string& units_comment, const std::string& header)
    : stream_(path, kWriteBuffer) {
  stream_.write(fmt::format("{}\n{}\n", units_comment, header));
}

namespace {

// Removes a previous run's file that this run does not write (a stale file
// would pass for this run's).
void remove_stale(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
}

}  // namespace

std::unique_ptr<CsvStream> open_csv_if(bool wanted, const std::filesystem::path& path,
                                       const std::string& units_comment, const std::string& header) {
  if (wanted) return std::make_unique<CsvStream>(path, units_comment, header);
  remove_stale(path);
  return nullptr;
}

StepFile::StepFile(const columns::Table& table, const std::vector<std::string>& multiplier_names, bool with_chart,
                   const OutputSettings& output, const std::filesystem::path& out_dir, const std::string& units_more)
    : table_(table), with_chart_(with_chart) {
  const bool steps = output.record == RecordMode::Steps;
  csv_ = open_csv_if(steps && output.step_format == StepFormat::Csv, out_dir / "steps.csv",
                     columns::units_line(table) + units_more, columns::header(table, columns::kSteps, multiplier_names, with_chart));
  const std::filesystem::path npy = out_dir / "steps.npy";
  if (steps && output.step_format == StepFormat::Npy)
    npy_ = std::make_unique<NpyFile>(npy, columns::npy_fields(table, columns::kSteps, multiplier_names, with_chart));
  else
    remove_stale(npy);
}

namespace {

// The units line's addition when the run has multipliers and they are not
// error-controlled (record/error_control.hpp).
std::string multipliers_note(const OneBodyView& problem, const Scene& scene) {
  if (problem.multiplier_names().empty()) return "";
  const MultiplierErrorControl c = multiplier_error_control(
      scene.solver.integrator, problem.system().suppress_algebraic_error_test(), problem.system().scheme().name);
  return c.controlled ? std::string() : "; multipliers NOT error-controlled: " + c.note;
}

}  // namespace

RunRecorder::RunRecorder(const OneBodyView& problem, const Scene& scene, const std::filesystem::path& out_dir)
    : problem_(problem),
      multiplier_names_(problem.multiplier_names()),
      with_chart_(problem.representation().has_charts()),
      step_observer_(problem, scene),
      grid_observer_(problem, scene),
      steps_(columns::single_body(), multiplier_names_, with_chart_, scene.output, out_dir,
             multipliers_note(problem, scene)),
      trajectory_(open_csv_if(scene.output.record != RecordMode::None, out_dir / "trajectory.csv",
                              columns::units_line() + multipliers_note(problem, scene),
                              columns::header(columns::kTrajectory, multiplier_names_, with_chart_))),
      events_(out_dir / "events.csv",
              "# units: t s; margin |det B| of the chart left (chart_switch), 1; drift_position |Phi| 1 and "
              "drift_velocity |dPhi/dt| 1/s just before a projection",
              "t,event,from,to,margin,drift_position,drift_velocity") {
  const TimeGrid& g = scene.time;
  start_is_output_ = g.output_times.empty() || g.output_times.front() == g.start;
  const int nm = static_cast<int>(multiplier_names_.size());
  extremes_.multiplier_min = Eigen::VectorXd::Constant(nm, std::numeric_limits<double>::infinity());
  extremes_.multiplier_max = Eigen::VectorXd::Constant(nm, -std::numeric_limits<double>::infinity());
}

void RunRecorder::write_row(CheckedStream& f, columns::File file, const columns::Sample& sample) {
  fmt::memory_buffer b;  // on the stack: recording a step allocates nothing
  columns::append_row(b, file, sample, with_chart_);
  f.write(b.data(), b.size());
}

void RunRecorder::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  const Observation o = step_observer_.observe(t, y);
  if (steps_) {
    const std::string chart = with_chart_ ? problem_.representation().chart_name() : std::string();
    steps_.write({t, h, order, &o, chart, {}});
  }
  extremes_.add_step(o);
}

void RunRecorder::on_output(double t, const Eigen::VectorXd& y) {
  const bool row = trajectory_ && (seen_start_ || start_is_output_);
  seen_start_ = true;
  if (!row && extremes_.steps_recorded > 0) return;
  const Observation o = grid_observer_.observe(t, y);
  if (row) {
    const std::string chart = with_chart_ ? problem_.representation().chart_name() : std::string();
    write_row(trajectory_->file(), columns::kTrajectory, {t, 0.0, 0, &o, chart, {}});
  }
  if (extremes_.steps_recorded == 0) extremes_.last = o;
}

void RunRecorder::on_event(const EventNote& e) {
  if (e.what == "chart_switch")
    events_.file().write(fmt::format("{},chart_switch,{},{},{},,\n", e.t, e.from, e.to, e.margin));
  else if (e.what == "projection")
    events_.file().write(fmt::format("{},projection,,,,{},{}\n", e.t, e.drift_position, e.drift_velocity));
}

void RunRecorder::flush() {
  steps_.flush();
  if (trajectory_) trajectory_->flush();
  events_.flush();
}

void RunRecorder::close() {
  CloseEach each;
  each([&] { steps_.close(); });
  if (trajectory_) each([&] { trajectory_->close(); });
  each([&] { events_.close(); }).rethrow_first();
}

}  // namespace rigidae
