// The single-body pins (tests/guard/pinned.json) through the multibody
// model, without the command line: each pinned run's scene as a one-body
// system (model/one_body_system.hpp: a pivoted body), integrated by IDA with
// the scene's settings, must give the pinned counters (every one) and the
// pinned final orientation and body angular velocity, read through
// OneBodyView as the records read them. The pins were recorded from the
// one-body model (the deleted src/dae, commit 4f13209), held bit for bit by the
// multibody model while both existed; with the one-body model deleted they
// are the independent record of its runs. Measured (MESSAGE per run): steps,
// residuals, Jacobians and the distance to the pinned orientation. 34 runs:
// all but long_run (2 million steps, guarded by the CLI's guard test).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/multibody/one_body_view.hpp"
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
  double t = 0.0;
  Vec4 q;
  Vec3 omega_B;
  bool ok = false;
};

Outcome run_system(const Scene& s) {
  multibody::MultibodyProblem p(one_body_system(s));
  const OneBodyView view(p, s);
  LastState last;
  const RunResult r = integrate(p, s.solver, s.time, last);
  // In the chart the run ended in (Euler angles switch).
  const Representation& rep = view.representation();
  const VecQ q = view.coordinates(last.y_.data());
  return {r.counters, last.t_, rep.orientation(q), rep.body_angular_velocity(q, view.velocities(last.y_.data())),
          r.status == RunStatus::Success};
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

Vec4 pinned_vec4(const json& a) { return Vec4(a[0].get<double>(), a[1].get<double>(), a[2].get<double>(), a[3].get<double>()); }

}  // namespace

TEST_CASE("pivot: the single-body pins through the multibody model" * doctest::test_suite("slow")) {
  std::ifstream in(std::string(RIGIDAE_SOURCE_DIR) + "/tests/guard/pinned.json");
  REQUIRE(in.good());
  const json runs = json::parse(in)["runs"];
  int identical = 0, measured = 0;
  double farthest = 0.0;
  for (const json& pin : runs) {
    const std::string name = pin["name"];
    if (name == "long_run/default") continue;  // 2 million steps: the CLI guard's
    CAPTURE(name);
    const Outcome b = run_system(pinned_scene(pin));
    REQUIRE(b.ok == (pin["status"] == "success"));
    ++measured;
    bool same = true;
    for (const auto& [key, value] : pin["counters"].items()) {
      const long got = key == "steps"                  ? b.counters.steps
                       : key == "residual_evals"       ? b.counters.residual_evals
                       : key == "jacobian_evals"       ? b.counters.jacobian_evals
                       : key == "nonlinear_iters"      ? b.counters.nonlinear_iters
                       : key == "error_test_fails"     ? b.counters.error_test_fails
                       : key == "nonlinear_conv_fails" ? b.counters.nonlinear_conv_fails
                       : key == "restarts"             ? b.counters.restarts
                       : key == "projections"          ? b.counters.projections
                       : key == "linear_setups"        ? b.counters.linear_setups
                       : key == "root_evals"           ? b.counters.root_evals
                                                       : -1;
      INFO("counter " << key);
      REQUIRE(got >= 0);
      CHECK(got == value.get<long>());
      same = same && got == value.get<long>();
    }
    CHECK(b.t == pin["t"].get<double>());
    const double angle = so3::quaternion_distance(b.q, pinned_vec4(pin["q_WB"]));
    farthest = std::max(farthest, angle);
    CHECK(angle <= 1e-12);
    for (int i = 0; i < 3; ++i) {
      const double w = pin["omega_B"][i].get<double>();
      CHECK(std::abs(b.omega_B[i] - w) <= 1e-9 * std::max(1.0, std::abs(w)));
    }
    identical += same && angle == 0.0 ? 1 : 0;
    MESSAGE(name << ": steps " << b.counters.steps << ", residuals " << b.counters.residual_evals << ", jacobians "
                 << b.counters.jacobian_evals << "; angle to the pinned orientation " << angle << " rad");
  }
  MESSAGE(identical << " of " << measured << " pinned runs with identical counters and orientation; farthest "
                    << farthest << " rad");
  CHECK(measured == 34);
  CHECK(identical == measured);  // measured: 34 of 34, bit for bit
}

TEST_SUITE_END();
