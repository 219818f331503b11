// A mechanism's per-step records (steps.csv / steps.npy): every joint's
// multipliers, reaction and drift at every accepted step, checked against
// physics that does not go through the recorder: static equilibrium of a
// hanging chain (each joint carries the weight below it, Newton's third law
// at the elbow), a near-point-mass pendulum's rod tension from energy
// conservation, the output grid's reactions at the same instants, and the
// .npy file's columns against the .csv's.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "alloc_counter.hpp"
#include "cli_runner.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/record/run_columns.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

struct Table {
  std::string units;
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  int col(const std::string& name) const {
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return static_cast<int>(k);
    FAIL("no column " << name);
    return -1;
  }
  bool has(const std::string& name) const {
    for (const std::string& n : names)
      if (n == name) return true;
    return false;
  }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  return out;
}

Table read_table(const fs::path& csv) {
  std::ifstream in(csv);
  REQUIRE(in);
  Table t;
  std::getline(in, t.units);
  std::string line;
  std::getline(in, line);
  t.names = split(line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (const std::string& c : split(line)) row.push_back(std::stod(c));
    REQUIRE(row.size() == t.names.size());
    t.rows.push_back(row);
  }
  return t;
}

// A body hanging at rest: centre of mass `below` the point P (space), no spin.
BodySpec hanging(const std::string& name, double mass, const Vec3& x) {
  BodySpec b;
  b.name = name;
  b.mass = mass;
  b.inertia_com = Vec3(0.02 * mass, 0.03 * mass, 0.01 * mass).asDiagonal();
  b.x0_W = x;
  b.R0_WB = Mat3::Identity();
  b.where = {"built_in.toml", 2, 1};
  return b;
}

// Two bodies hanging at rest below the origin on spherical joints.
Scene hanging_chain(Coordinates c, Equations e, const std::string& scheme) {
  Scene s = test::multibody_base(c, e, scheme);
  s.name = "hanging_chain";
  MultibodySpec& m = *s.multibody;
  m.bodies = {hanging("upper", 2.0, Vec3(0, 0, -0.5)), hanging("lower", 3.0, Vec3(0, 0, -1.5))};
  m.joints.push_back(test::joint_at(m, &joint_type("spherical"), kGround, 0, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX(),
                                    "shoulder"));
  m.joints.push_back(test::joint_at(m, &joint_type("spherical"), 0, 1, Vec3(0, 0, -1), Vec3::UnitZ(), Vec3::UnitX(),
                                    "elbow"));
  m.gravity_W = Vec3(0, 0, -9.81);
  s.solver.rtol = s.solver.atol = 1e-9;
  s.time = {0.0, 1.0, 0.1};
  return s;
}

}  // namespace

TEST_CASE("mechanism steps: a chain hanging at rest carries the weight below each joint at every step") {
  // Independent truth: static equilibrium. The shoulder holds both bodies
  // ((2 + 3) kg g up on the upper one), the elbow the lower one (3 kg g up
  // on it; by Newton's third law 3 kg g down on the upper one, which is what
  // makes the shoulder's 5 kg g balance the upper body's 2 kg g).
  for (const auto& [coords, eqs, scheme] :
       {std::tuple{Coordinates::Quaternion, Equations::Lagrange, "ggl"},
        std::tuple{Coordinates::Quaternion, Equations::Euler, "index3"},
        std::tuple{Coordinates::Linear, Equations::Euler, "baumgarte"}}) {
    CAPTURE(scheme);
    Scene s = hanging_chain(coords, eqs, scheme);
    const fs::path dir = test::fresh_temp_dir(std::string("mb_hanging_") + scheme);
    const SolveOutcome o = solve_scene(s, dir);
    REQUIRE(o.run.status == RunStatus::Success);
    const Table t = read_table(dir / "steps.csv");
    REQUIRE(static_cast<long>(t.rows.size()) == o.run.counters.steps);
    REQUIRE(t.rows.size() > 3);
    // Every joint's multipliers by row name, its reaction and its drift.
    for (const char* joint : {"shoulder", "elbow"})
      for (const char* c : {".lambda_x", ".lambda_y", ".lambda_z", ".force_x", ".force_y", ".force_z", ".torque_x",
                            ".torque_y", ".torque_z", ".residual_position", ".residual_velocity"})
        CHECK_MESSAGE(t.has(std::string(joint) + c), joint << c);
    // A body's own constraints: the Lagrange form's quaternion norm is held by
    // a force (lambda), the Euler form's kept by the kinematics (mu).
    if (coords == Coordinates::Quaternion)
      CHECK(t.has(eqs == Equations::Lagrange ? "upper.lambda_norm" : "upper.mu_norm"));
    CHECK(t.units.find("NOT error-controlled") != std::string::npos);
    const double g = 9.81;
    for (const auto& row : t.rows) {
      CAPTURE(row[t.col("t")]);
      CHECK(row[t.col("shoulder.force_x")] == doctest::Approx(0.0).epsilon(1e-7).scale(50));
      CHECK(row[t.col("shoulder.force_y")] == doctest::Approx(0.0).epsilon(1e-7).scale(50));
      CHECK(row[t.col("shoulder.force_z")] == doctest::Approx(5.0 * g).epsilon(1e-7));
      CHECK(row[t.col("elbow.force_z")] == doctest::Approx(3.0 * g).epsilon(1e-7));
      CHECK(row[t.col("elbow.force_x")] == doctest::Approx(0.0).epsilon(1e-7).scale(30));
      for (const char* c : {"shoulder.torque_x", "shoulder.torque_y", "shoulder.torque_z", "elbow.torque_x"})
        CHECK(row[t.col(c)] == doctest::Approx(0.0).epsilon(1e-7).scale(50));
      CHECK(row[t.col("shoulder.residual_position")] < 1e-8);
      CHECK(row[t.col("elbow.residual_position")] < 1e-8);
    }
  }
}

TEST_CASE("mechanism steps: a swinging near-point-mass pendulum's rod tension is m g (3 cos theta - 2 cos theta0)") {
  // Independent truth: energy conservation for a point mass on a massless
  // rod. Released at rest at theta0, v^2 = 2 g L (cos theta - cos theta0),
  // so the rod pulls with T = m g cos theta + m v^2 / L = m g (3 cos theta -
  // 2 cos theta0), along the rod, whose direction (so theta) is the force's:
  // cos theta = F_z / |F|. The body's own inertia (1e-7 kg m^2 against
  // m L^2 = 1 kg m^2) moves T by about 1e-7 relative.
  const double m = 1.0, L = 1.0, theta0 = 1.2, g = 9.81;
  Scene s = test::multibody_base(Coordinates::Quaternion, Equations::Euler, "ggl");
  MultibodySpec& mb = *s.multibody;
  BodySpec b;
  b.name = "bob";
  b.mass = m;
  b.inertia_com = Vec3(1e-7, 1e-7, 1e-7).asDiagonal();
  b.x0_W = Vec3(L * std::sin(theta0), 0, -L * std::cos(theta0));
  b.R0_WB = Mat3::Identity();
  b.where = {"built_in.toml", 2, 1};
  mb.bodies = {b};
  mb.joints.push_back(
      test::joint_at(mb, &joint_type("revolute"), kGround, 0, Vec3::Zero(), Vec3::UnitY(), Vec3::UnitX(), "pivot"));
  mb.gravity_W = Vec3(0, 0, -g);
  s.solver.rtol = s.solver.atol = 1e-10;
  s.time = {0.0, 2.0, 0.1};
  const fs::path dir = test::fresh_temp_dir("mb_swinging");
  const SolveOutcome o = solve_scene(s, dir);
  REQUIRE(o.run.status == RunStatus::Success);
  const Table t = read_table(dir / "steps.csv");
  REQUIRE(t.rows.size() > 50);
  double lowest = 1.0;  // the smallest cos theta seen: the swing must pass the bottom and come back up
  double highest = -1.0;
  for (const auto& row : t.rows) {
    CAPTURE(row[t.col("t")]);
    const Vec3 F(row[t.col("pivot.force_x")], row[t.col("pivot.force_y")], row[t.col("pivot.force_z")]);
    // The reaction on the bob points from the bob to the pivot.
    const double cos_theta = F.z() / F.norm();
    lowest = std::min(lowest, cos_theta);
    highest = std::max(highest, cos_theta);
    CHECK(F.norm() == doctest::Approx(m * g * (3.0 * cos_theta - 2.0 * std::cos(theta0))).epsilon(1e-5));
    CHECK(F.y() == doctest::Approx(0.0).scale(1e-6));
  }
  CHECK(lowest < std::cos(theta0) + 0.01);  // near the turning point
  CHECK(highest > 0.999);                   // through the bottom
}

TEST_CASE("mechanism steps: the reactions of a step that is an output time equal trajectory.csv's") {
  // IDA's steps do not depend on the output times (one-step mode, output by
  // interpolation): a second run whose output.times are some of the first
  // run's step times takes the same steps, and the interpolant at a step's
  // own time is that step's state. The two files' reactions must then agree.
  Scene s = test::two_body_chain(&joint_type("revolute"), Coordinates::Quaternion, Equations::Euler, "ggl");
  s.time = {0.0, 0.3, 0.1};
  s.solver.rtol = s.solver.atol = 1e-8;
  const fs::path first = test::fresh_temp_dir("mb_grid_first");
  REQUIRE(solve_scene(s, first).run.status == RunStatus::Success);
  const Table steps = read_table(first / "steps.csv");
  REQUIRE(steps.rows.size() > 20);
  std::vector<double> times;
  for (std::size_t k = 3; k + 1 < steps.rows.size(); k += 7) times.push_back(steps.rows[k][0]);
  s.time.output_times = times;
  const fs::path second = test::fresh_temp_dir("mb_grid_second");
  REQUIRE(solve_scene(s, second).run.status == RunStatus::Success);
  const Table again = read_table(second / "steps.csv");
  REQUIRE(again.rows.size() == steps.rows.size());
  const Table grid = read_table(second / "trajectory.csv");
  REQUIRE(grid.rows.size() == times.size());
  int compared = 0;
  for (const auto& g : grid.rows) {
    const auto* row = &again.rows.front();
    for (const auto& r : again.rows)
      if (r[0] == g[0]) row = &r;
    REQUIRE((*row)[0] == g[0]);
    for (const char* joint : {"j0", "j1"})
      for (const char* c : {".force_x", ".force_y", ".force_z", ".torque_x", ".torque_y", ".torque_z", ".residual_velocity"}) {
        const std::string name = std::string(joint) + c;
        CAPTURE(name);
        CHECK((*row)[again.col(name)] == doctest::Approx(g[grid.col(name)]).epsilon(1e-9).scale(1e-6));
        ++compared;
      }
  }
  CHECK(compared == 14 * static_cast<int>(times.size()));
}

TEST_CASE("mechanism steps: steps.npy holds the columns and numbers of steps.csv") {
  Scene s = hanging_chain(Coordinates::Quaternion, Equations::Lagrange, "ggl");
  s.time = {0.0, 0.2, 0.1};
  const fs::path csv_dir = test::fresh_temp_dir("mb_npy_csv");
  REQUIRE(solve_scene(s, csv_dir).run.status == RunStatus::Success);
  s.output.step_format = StepFormat::Npy;
  const fs::path npy_dir = test::fresh_temp_dir("mb_npy_npy");
  REQUIRE(solve_scene(s, npy_dir).run.status == RunStatus::Success);
  const Table csv = read_table(csv_dir / "steps.csv");
  const std::string npy = test::read_file(npy_dir / "steps.npy");
  REQUIRE(npy.rfind("\x93NUMPY", 0) == 0);
  std::uint16_t header_len = 0;
  std::memcpy(&header_len, npy.data() + 8, 2);
  const std::string header = npy.substr(10, header_len);
  // Every csv column is a field, in the same order.
  std::size_t at = 0;
  for (const std::string& name : csv.names) {
    const std::size_t k = header.find("('" + name + "'", at);
    CHECK_MESSAGE(k != std::string::npos, name);
    if (k != std::string::npos) at = k;
  }
  const std::size_t fields = static_cast<std::size_t>(std::count(header.begin(), header.end(), '(')) - 1;  // "(N,)" shape
  CHECK(fields == csv.names.size());
  // Rows of 8-byte numbers ('order' an int64), equal to the csv's text.
  const std::size_t row_bytes = 8 * csv.names.size();
  const std::size_t data = 10 + header_len;
  REQUIRE((npy.size() - data) % row_bytes == 0);
  REQUIRE((npy.size() - data) / row_bytes == csv.rows.size());
  for (std::size_t r = 0; r < csv.rows.size(); ++r)
    for (std::size_t c = 0; c < csv.names.size(); ++c) {
      const char* p = npy.data() + data + r * row_bytes + 8 * c;
      double v;
      if (csv.names[c] == "order") {
        std::int64_t i;
        std::memcpy(&i, p, 8);
        v = static_cast<double>(i);
      } else {
        std::memcpy(&v, p, 8);
      }
      CHECK(v == csv.rows[r][c]);
    }
}

TEST_CASE("mechanism steps: recording a step with every part's columns allocates nothing") {
  // The row of per-part numbers and the text buffer are kept from step to
  // step; once they have grown to a row's length, a step costs no heap.
  Scene s = test::two_body_chain(&joint_type("revolute"), Coordinates::Quaternion, Equations::Lagrange, "ggl");
  multibody::MultibodyProblem p(s);
  Eigen::VectorXd y(p.size()), yp(p.size());
  p.initial_state(0.0, y, yp);
  const fs::path dir = test::fresh_temp_dir("mb_step_alloc");
  const std::unique_ptr<RunColumns> columns = make_run_columns(p, s);
  RunRecorder rec(*columns, s.output, s.time, dir);
  REQUIRE(columns->value_names(columns::kSteps).size() > 2 * 8);
  rec.on_output(0.0, y);
  // In a run the accuracy monitor asks for the step's drift first and the
  // recorder gets the memo (MultibodyProblem::drift); the monitor's own call
  // is not the recorder's path, so it is made outside the count.
  for (int k = 1; k <= 3; ++k) {
    p.drift(1e-3 * k, y.data());
    rec.on_step(1e-3 * k, 1e-3, 1, y);
  }
  long allocations = 0;
  for (int k = 4; k <= 20; ++k) {
    p.drift(1e-3 * k, y.data());
    test::start_counting_allocations();
    rec.on_step(1e-3 * k, 1e-3, 2, y);
    allocations += test::stop_counting_allocations();
  }
  CHECK(allocations == 0);
  rec.close();
}

TEST_SUITE_END();
