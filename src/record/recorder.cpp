#include "rigidae/record/recorder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "rigidae/core/error.hpp"
#include "rigidae/record/columns.hpp"

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
                   const OutputSettings& output, const std::filesystem::path& out_dir, const std::string& units)
    : table_(table), with_chart_(with_chart) {
  if (out_dir.empty()) return;  // a run kept in memory only
  const bool steps = output.record == RecordMode::Steps;
  csv_ = open_csv_if(steps && output.step_format == StepFormat::Csv, out_dir / "steps.csv", units,
                     columns::header(table, columns::kSteps, multiplier_names, with_chart));
  const std::filesystem::path npy = out_dir / "steps.npy";
  if (steps && output.step_format == StepFormat::Npy)
    npy_ = std::make_unique<NpyFile>(npy, columns::npy_fields(table, columns::kSteps, multiplier_names, with_chart));
  else
    remove_stale(npy);
}

namespace {

std::vector<std::string> split_header(const std::string& header) {
  std::vector<std::string> names;
  std::size_t at = 0;
  while (at <= header.size()) {
    const std::size_t comma = std::min(header.find(',', at), header.size());
    names.push_back(header.substr(at, comma - at));
    at = comma + 1;
  }
  return names;
}

}  // namespace

RunRecorder::RunRecorder(RunColumns& columns, const OutputSettings& output, const TimeGrid& time,
                         const std::filesystem::path& out_dir, MemoryRows* memory)
    : columns_(columns),
      memory_(memory),
      with_chart_(columns.with_chart()),
      events_(out_dir.empty() ? nullptr
                              : std::make_unique<CsvStream>(out_dir / "events.csv", columns.events_units(),
                                                            columns.events_header())),
      steps_(columns.table(), columns.value_names(columns::kSteps), with_chart_, output, out_dir,
             columns.units_line(columns::kSteps)),
      trajectory_(out_dir.empty() ? nullptr
                                  : open_csv_if(output.record != RecordMode::None, out_dir / "trajectory.csv",
                                                columns.units_line(columns::kTrajectory),
                                                columns::header(columns.table(), columns::kTrajectory,
                                                                columns.value_names(columns::kTrajectory),
                                                                with_chart_))) {
  start_is_output_ = time.output_times.empty() || time.output_times.front() == time.start;
  step_values_wanted_ = static_cast<bool>(steps_) || (memory_ && memory_->keep_steps);
  step_values_.resize(columns.value_names(columns::kSteps).size());
  grid_values_.resize(columns.value_names(columns::kTrajectory).size());
  if (memory_) {
    const columns::Table& table = columns.table();
    memory_->step_columns =
        split_header(columns::header(table, columns::kSteps, columns.value_names(columns::kSteps), with_chart_));
    memory_->grid_columns = split_header(
        columns::header(table, columns::kTrajectory, columns.value_names(columns::kTrajectory), with_chart_));
    for (const columns::Column& c : table.columns)
      if (c.kind == columns::Kind::Integer) memory_->integer_columns.emplace_back(c.name);
  }
}

void RunRecorder::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  Observation& o = step_observation_;
  columns_.observe(columns::kSteps, t, y, o,
                   step_values_wanted_ ? std::span<double>(step_values_) : std::span<double>());
  if (step_values_wanted_) {
    const columns::Sample s{t, h, order, &o, columns_.chart(), step_values_};
    if (steps_) steps_.write(s);
    if (memory_ && memory_->keep_steps)
      columns::append_numbers(memory_->steps, columns_.table(), columns::kSteps, s, with_chart_, memory_->charts);
  }
  extremes_.add_step(o);
}

void RunRecorder::on_output(double t, const Eigen::VectorXd& y) {
  const bool wanted = trajectory_ || (memory_ && memory_->keep_grid);
  const bool row = wanted && (seen_start_ || start_is_output_);
  seen_start_ = true;
  if (!row && extremes_.steps_recorded > 0) return;
  Observation o;
  columns_.observe(columns::kTrajectory, t, y, o, row ? std::span<double>(grid_values_) : std::span<double>());
  if (row) {
    const columns::Sample s{t, 0.0, 0, &o, columns_.chart(), grid_values_};
    if (trajectory_) {
      row_.clear();
      columns::append_row(row_, columns_.table(), columns::kTrajectory, s, with_chart_);
      trajectory_->file().write(row_.data(), row_.size());
    }
    if (memory_ && memory_->keep_grid)
      columns::append_numbers(memory_->grid, columns_.table(), columns::kTrajectory, s, with_chart_, memory_->charts);
  }
  if (extremes_.steps_recorded == 0) extremes_.last = o;
}

void RunRecorder::on_event(const EventNote& e) {
  if (memory_) memory_->events.push_back(e);
  if (!events_) return;
  row_.clear();
  columns_.append_event(row_, e);
  if (row_.size()) events_->file().write(row_.data(), row_.size());
}

void RunRecorder::close() {
  CloseEach each;
  each([&] { steps_.close(); });
  if (trajectory_) each([&] { trajectory_->close(); });
  if (events_) each([&] { events_->close(); });
  each.rethrow_first();
}

}  // namespace rigidae
