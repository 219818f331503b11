#include "rigidae/record/recorder.hpp"

#include <fmt/format.h>

#include <charconv>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "rigidae/core/error.hpp"

namespace rigidae {

namespace {

constexpr std::size_t kWriteBuffer = 1 << 20;

std::string observation_columns(const std::vector<std::string>& multipliers) {
  std::string s = "qw,qx,qy,qz,omega_x,omega_y,omega_z,drift_position,drift_velocity";
  for (const auto& m : multipliers) s += "," + m;
  s += ",energy,energy_rel_error,vertical_momentum,vertical_momentum_rel_error";
  return s;
}

const char* kUnits =
    "# units: t s; h s; qw..qz unit quaternion of R_WB (body to space, scalar first); omega_* rad/s body frame; "
    "drift_position |Phi(q)| 1; drift_velocity |dPhi/dt| 1/s; lambda_* J (generalized constraint force); "
    "mu_* 1/s (kinematic multiplier); energy J; energy_rel_error (H-H0)/|H0|; vertical_momentum kg m^2/s about "
    "the reference point; vertical_momentum_rel_error (Lz-Lz0)/|L0|";

}  // namespace

CsvStream::CsvStream(const std::filesystem::path& path, const std::string& units_comment, const std::string& header)
    : buffer_(kWriteBuffer) {
  f_ = std::fopen(path.c_str(), "w");
  if (!f_) throw InputError(fmt::format("{}: cannot open for writing: {}", path.string(), std::strerror(errno)));
  std::setvbuf(f_, buffer_.data(), _IOFBF, buffer_.size());
  fmt::print(f_, "{}\n{}\n", units_comment, header);
}

CsvStream::~CsvStream() {
  if (f_) std::fclose(f_);
}

void CsvStream::flush() { std::fflush(f_); }

RunRecorder::RunRecorder(const DaeSystem& dae, const Scene& scene, const std::filesystem::path& out_dir)
    : dae_(dae),
      multiplier_names_(dae.multiplier_names()),
      with_chart_(dae.representation().has_charts()),
      step_observer_(dae, scene),
      grid_observer_(dae, scene),
      steps_(out_dir / "steps.csv", kUnits,
             "t,h,order," + observation_columns(multiplier_names_) + (with_chart_ ? ",chart" : "")),
      trajectory_(out_dir / "trajectory.csv", kUnits,
                  "t," + observation_columns(multiplier_names_) + (with_chart_ ? ",chart" : "")),
      events_(out_dir / "events.csv",
              "# units: t s; margin |det B| of the chart left (chart_switch), 1; drift_position |Phi| 1 and "
              "drift_velocity |dPhi/dt| 1/s just before a projection",
              "t,event,from,to,margin,drift_position,drift_velocity") {
  const int nm = static_cast<int>(multiplier_names_.size());
  extremes_.multiplier_min = Eigen::VectorXd::Constant(nm, std::numeric_limits<double>::infinity());
  extremes_.multiplier_max = Eigen::VectorXd::Constant(nm, -std::numeric_limits<double>::infinity());
}

namespace {

// Shortest text that reads back to the same double (std::to_chars, Ryu in
// libstdc++): exact, and ~3x fewer instructions than fmt with a precision,
// which made formatting half the cost of a recorded step.
void put(fmt::memory_buffer& b, double x, char before = ',') {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  if (before) b.push_back(before);
  b.append(text, end);
}

}  // namespace

void RunRecorder::write_observation(std::FILE* f, const Observation& o, fmt::memory_buffer& b) {
  for (int i = 0; i < 4; ++i) put(b, o.q_WB(i));
  for (int i = 0; i < 3; ++i) put(b, o.omega_B(i));
  put(b, o.drift.position);
  put(b, o.drift.velocity);
  for (int i = 0; i < o.multipliers.size(); ++i) put(b, o.multipliers(i));
  put(b, o.energy);
  put(b, o.energy_error);
  put(b, o.vertical_momentum);
  put(b, o.vertical_momentum_error);
  if (with_chart_) {
    b.push_back(',');
    const std::string chart = dae_.representation().chart_name();
    b.append(chart.data(), chart.data() + chart.size());
  }
  b.push_back('\n');
  std::fwrite(b.data(), 1, b.size(), f);
}

void RunRecorder::on_step(double t, double h, int order, const Eigen::VectorXd& y) {
  const Observation o = step_observer_.observe(t, y);
  fmt::memory_buffer b;  // on the stack: recording a step allocates nothing
  put(b, t, 0);
  put(b, h);
  fmt::format_to(fmt::appender(b), ",{}", order);
  write_observation(steps_.file(), o, b);
  RunExtremes& e = extremes_;
  ++e.steps_recorded;
  e.max_drift_position = std::max(e.max_drift_position, o.drift.position);
  e.max_drift_velocity = std::max(e.max_drift_velocity, o.drift.velocity);
  e.max_abs_energy_error = std::max(e.max_abs_energy_error, std::abs(o.energy_error));
  e.max_abs_vertical_momentum_error = std::max(e.max_abs_vertical_momentum_error, std::abs(o.vertical_momentum_error));
  e.multiplier_min = e.multiplier_min.cwiseMin(o.multipliers);
  e.multiplier_max = e.multiplier_max.cwiseMax(o.multipliers);
  e.last = o;
}

void RunRecorder::on_output(double t, const Eigen::VectorXd& y) {
  const Observation o = grid_observer_.observe(t, y);
  fmt::memory_buffer b;
  put(b, t, 0);
  write_observation(trajectory_.file(), o, b);
  if (extremes_.steps_recorded == 0) extremes_.last = o;
}

void RunRecorder::on_event(const EventNote& e) {
  if (e.what == "chart_switch")
    fmt::print(events_.file(), "{},chart_switch,{},{},{},,\n", e.t, e.from, e.to, e.margin);
  else if (e.what == "projection")
    fmt::print(events_.file(), "{},projection,,,,{},{}\n", e.t, e.drift_position, e.drift_velocity);
}

void RunRecorder::flush() {
  steps_.flush();
  trajectory_.flush();
  events_.flush();
}

}  // namespace rigidae
