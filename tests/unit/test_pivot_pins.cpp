// The single-body pins (tests/guard/pinned.json) through the multibody
// model: each pinned run's scene as a one-body system
// (model/one_body_system.hpp: a pivoted body), integrated by the same IDA
// driver with the same settings, beside the single-body model's own run.
// Measured (MESSAGE per run): steps, residuals and Jacobians of both, and
// the final orientation's distance to a tight single-body reference of the
// scene (rtol 1e-12) for both. Asserted: the single-body run reproduces its
// pin (so the comparison is the CLI's), the README's heavy top and every
// quaternion Euler-form run are the same bit for bit, 15 runs in all, and
// the others' steps move by at most 3 % except under the projection scheme.
// The errors are reported, not asserted: 3 Lagrange-form runs end 1.8x to
// 2.7x the single-body run's error (docs/architecture.md has the table's
// summary).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "rigidae/dae/dae_system.hpp"
#include "rigidae/dae/single_body_problem.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/ida_driver.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
using nlohmann::json;

namespace {

// Keeps the last output's y.
class LastState final : public StepSink {
 public:
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double t, const Eigen::VectorXd& y) override {
    t_ = t;
    y_ = y;
  }
  double t_ = 0.0;
  Eigen::VectorXd y_;
};

struct Outcome {
  IdaCounters counters;
  Vec4 q;
  bool ok = false;
};

Outcome run_single(const Scene& s) {
  const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
  SingleBodyProblem p(*dae, s.formulation.euler, s.R0_WB, s.omega0_B, s.source);
  LastState last;
  const RunResult r = integrate(p, s.solver, s.time, last);
  return {r.counters, p.representation().orientation(dae->coordinates(last.y_.data())), r.status == RunStatus::Success};
}

Outcome run_system(const Scene& s) {
  multibody::MultibodyProblem p(one_body_system(s));
  LastState last;
  const RunResult r = integrate(p, s.solver, s.time, last);
  return {r.counters, p.body_orientation(0, last.y_.data()), r.status == RunStatus::Success};
}

Scene pinned_scene(const json& pin) {
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/" + pin["scene"].get<std::string>());
  const auto& a = pin["args"];
  for (std::size_t k = 0; k + 1 < a.size(); k += 2) {
    const std::string key = a[k], value = a[k + 1];
    if (key == "--coordinates") s.formulation.coordinates = Coordinates(value);
    else if (key == "--equations") s.formulation.equations = value == "euler" ? Equations::Euler : Equations::Lagrange;
    else if (key == "--scheme") s.formulation.scheme = value;
    else FAIL("an argument this measurement does not apply: " << key);
  }
  return s;
}

}  // namespace

TEST_CASE("pivot: the single-body pins through the multibody model (measured)" * doctest::test_suite("slow")) {
  std::ifstream in(std::string(RIGIDAE_SOURCE_DIR) + "/tests/guard/pinned.json");
  REQUIRE(in.good());
  const json runs = json::parse(in)["runs"];
  std::map<std::string, Vec4> tight;  // per scene file
  int identical = 0, measured = 0;
  for (const json& pin : runs) {
    const std::string name = pin["name"];
    if (name == "long_run/default") continue;  // 2 million steps: measured by hand (docs/architecture.md)
    CAPTURE(name);
    const Scene s = pinned_scene(pin);
    const std::string file = pin["scene"];
    if (!tight.count(file)) {
      Scene t = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/" + file);
      t.solver.rtol = t.solver.atol = 1e-12;
      const Outcome o = run_single(t);
      REQUIRE(o.ok);
      tight[file] = o.q;
    }
    const Outcome a = run_single(s), b = run_system(s);
    REQUIRE(a.ok == (pin["status"] == "success"));
    CHECK(a.counters.steps == pin["counters"]["steps"].get<long>());
    CHECK(a.counters.residual_evals == pin["counters"]["residual_evals"].get<long>());
    ++measured;
    const double err_a = so3::quaternion_distance(a.q, tight[file]), err_b = so3::quaternion_distance(b.q, tight[file]);
    const double between = so3::quaternion_distance(a.q, b.q);
    const bool same = a.counters.steps == b.counters.steps && a.counters.residual_evals == b.counters.residual_evals &&
                      a.counters.jacobian_evals == b.counters.jacobian_evals && between == 0.0;
    identical += same ? 1 : 0;
    MESSAGE(name << ": steps " << a.counters.steps << " -> " << b.counters.steps << " ("
                 << 100.0 * (b.counters.steps - a.counters.steps) / a.counters.steps << " %), residuals "
                 << a.counters.residual_evals << " -> " << b.counters.residual_evals << ", jacobians "
                 << a.counters.jacobian_evals << " -> " << b.counters.jacobian_evals << "; error " << err_a << " -> "
                 << err_b << " rad (x" << err_b / std::max(err_a, 1e-300) << "), between " << between
                 << std::string(same ? " [identical]" : ""));
    REQUIRE(b.ok == a.ok);
    // The README's heavy top and the Euler form in quaternions: the same
    // operations in the same order.
    if (name == "heavy_top/default" ||
        (s.formulation.equations == Equations::Euler && s.formulation.coordinates == Coordinates::Quaternion))
      CHECK(same);
    // Round-off moves the others' step sequences by at most 3 % (measured
    // 2.45 %), except the projection scheme, whose trigger differs
    // (docs/architecture.md: 2-norm against max norm of the drift).
    if (s.formulation.scheme != "projection")
      CHECK(std::abs(b.counters.steps - a.counters.steps) <= 0.03 * a.counters.steps);
  }
  MESSAGE(identical << " of " << measured << " pinned runs identical through the multibody model");
  CHECK(identical >= 15);  // measured: 15 of 34
}

TEST_SUITE_END();
