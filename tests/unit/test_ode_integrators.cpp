// The ODE form of the single body on CVODE (Adams, BDF) and ARKODE (ERK),
// the scene run as every scene runs (a one-body system, MultibodyOde, through
// app's run_multibody; its state read through OneBodyView):
// against the closed forms (free body, Lagrange top) in every
// representation x equation form, the error falls with rtol, projection
// keeps the invariants at round-off, and the integrator/scheme table
// rejects pairs it does not run.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "app/run_system.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/one_body_view.hpp"
#include "rigidae/so3/rotation.hpp"
#include "rigidae/solver/integrators.hpp"
#include "rigidae/solver/ode_driver.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

// Keeps the last output point, and for every accepted step the state and
// whether a projection came with it.
class Sink final : public StepSink {
 public:
  Eigen::VectorXd y_last;
  double t_last = -1.0;
  std::vector<Eigen::VectorXd> step_states;
  std::vector<bool> step_projected;
  bool pending_projection = false;
  long projections = 0;
  void on_step(double, double, int, const Eigen::VectorXd& y) override {
    step_states.push_back(y);
    step_projected.push_back(pending_projection);
    pending_projection = false;
  }
  void on_output(double t, const Eigen::VectorXd& y) override {
    t_last = t;
    y_last = y;
  }
  void on_event(const EventNote& e) override {
    if (e.what != "projection") return;
    pending_projection = true;
    ++projections;
  }
};

struct Outcome {
  RunResult run;
  double error = NAN;  // rad, final orientation against the closed form
  Sink sink;
};

Scene scene_for(const std::string& file, Coordinates c, Equations e, const std::string& scheme, double rtol,
                double t_end) {
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/" + file);
  s.formulation.coordinates = c;
  s.formulation.equations = e;
  s.formulation.scheme = scheme;
  s.solver.rtol = s.solver.atol = rtol;
  s.time.end = t_end;
  s.time.output_step = t_end;
  return s;
}

// The scene on `integrator` as solve runs it: one_body_system(s) on the ODE form.
Outcome run(const Scene& scene, const std::string& integrator, const std::string& erk = "fehlberg78") {
  Scene s = scene;
  s.solver.integrator = integrator;
  s.solver.erk_method = erk;
  multibody::MultibodyProblem system(one_body_system(s));
  const OneBodyView view(system, s);
  Outcome o;
  o.run = run_multibody(system, s, o.sink);
  if (o.run.status == RunStatus::Success) {
    std::string why;
    const auto exact = exact::make_exact_solution(s, &why);
    REQUIRE(exact);
    // In the chart the run ended in (Euler angles may have switched).
    const Vec4 q = view.representation().orientation(view.coordinates(o.sink.y_last.data()));
    o.error = so3::quaternion_distance(q, so3::matrix_to_quaternion(exact->at(o.sink.t_last).R_WB));
  }
  return o;
}

struct Combo {
  Coordinates c;
  Equations e;
};
const Combo kSix[] = {{Coordinates::EulerAngles, Equations::Lagrange}, {Coordinates::EulerAngles, Equations::Euler},
                      {Coordinates::Quaternion, Equations::Lagrange},  {Coordinates::Quaternion, Equations::Euler},
                      {Coordinates::Linear, Equations::Lagrange},      {Coordinates::Linear, Equations::Euler}};

}  // namespace

TEST_CASE("ODE integrators: a sink that keeps only the last output gets the start and the end, the same bits, the same steps") {
  // Counts the outputs it is given; `every` is what it tells the driver.
  class Counting final : public StepSink {
   public:
    explicit Counting(bool every) : every_(every) {}
    void on_step(double, double, int, const Eigen::VectorXd&) override { ++steps; }
    void on_output(double t, const Eigen::VectorXd& y) override {
      times.push_back(t);
      y_last = y;
    }
    bool needs_every_output() const override { return every_; }
    std::vector<double> times;
    Eigen::VectorXd y_last;
    long steps = 0;

   private:
    bool every_;
  };
  Scene s = scene_for("heavy_top.toml", Coordinates::Quaternion, Equations::Euler, "projection", 1e-8, 0.5);
  s.time.output_step = 0.05;  // ten grid points after the start
  for (const std::string integrator : {"arkode-erk", "cvode-adams"}) {
    CAPTURE(integrator);
    s.solver.integrator = integrator;
    Counting all(true), last(false);
    multibody::MultibodyProblem system_all(one_body_system(s)), system_last(one_body_system(s));
    const RunResult a = run_multibody(system_all, s, all);
    const RunResult b = run_multibody(system_last, s, last);
    REQUIRE(a.status == RunStatus::Success);
    REQUIRE(b.status == RunStatus::Success);
    CHECK(all.times.size() == 11);  // t = 0, 0.05, ..., 0.5
    REQUIRE(last.times.size() == 2);
    CHECK(last.times[0] == 0.0);
    CHECK(last.times[1] == all.times.back());
    CHECK(a.counters.steps == b.counters.steps);
    CHECK(all.steps == last.steps);
    CHECK((last.y_last.array() == all.y_last.array()).all());
  }
}

TEST_CASE("ODE integrators: every representation x form meets the closed forms, and the error falls with rtol") {
  struct Case {
    const char* file;
    double t_end;
  };
  // Free body (Euler's closed form) and the Lagrange top (Jacobi elliptic
  // functions), short spans so that the suite stays fast.
  for (const Case& sc : {Case{"free_body.toml", 1.0}, Case{"lagrange_top.toml", 0.5}})
    for (const char* integrator : {"cvode-adams", "cvode-bdf", "arkode-erk"})
      for (const Combo& k : kSix) {
        const std::string label = std::string(sc.file) + " " + integrator + " " + to_string(k.c) + "/" + to_string(k.e);
        CAPTURE(label);
        const Outcome loose = run(scene_for(sc.file, k.c, k.e, "projection", 1e-6, sc.t_end), integrator);
        const Outcome tight = run(scene_for(sc.file, k.c, k.e, "projection", 1e-9, sc.t_end), integrator);
        REQUIRE(loose.run.status == RunStatus::Success);
        REQUIRE(tight.run.status == RunStatus::Success);
        CAPTURE(loose.error);
        CAPTURE(tight.error);
        // Tolerances bound the local error; the global error of a 30 rad
        // (Lagrange top) or 2 rad (free body) run accumulates over
        // hundreds of steps: measured up to 700 rtol (Euler form) and
        // 5000 rtol (Lagrange form, whose error control acts on the fast
        // coordinate velocities, as with IDA). The bounds are 1e3 and 1e4
        // rtol, and three decades of rtol must buy at least one of error.
        const double factor = k.e == Equations::Euler ? 1e3 : 1e4;
        CHECK(loose.error < factor * 1e-6);
        CHECK(tight.error < factor * 1e-9);
        CHECK(tight.error < 0.1 * loose.error);
      }
}

TEST_CASE("ODE integrators: each ERK table of ARKODE meets the closed form at its order") {
  for (const std::string& m : erk_method_names()) {
    CAPTURE(m);
    const Scene s6 = scene_for("lagrange_top.toml", Coordinates::Quaternion, Equations::Euler, "projection", 1e-6, 0.5);
    const Scene s10 = scene_for("lagrange_top.toml", Coordinates::Quaternion, Equations::Euler, "projection", 1e-10, 0.5);
    const Outcome a = run(s6, "arkode-erk", m), b = run(s10, "arkode-erk", m);
    REQUIRE(a.run.status == RunStatus::Success);
    REQUIRE(b.run.status == RunStatus::Success);
    CHECK(a.error < 1e-4);
    CHECK(b.error < 1e-8);
    CHECK(b.error < a.error);
    CHECK(b.run.counters.steps > a.run.counters.steps);
  }
}

TEST_CASE("ODE integrators: projection keeps |q|^2 - 1 and R^T R - I at round-off after each projected step") {
  for (const char* integrator : {"cvode-bdf", "arkode-erk"})
    for (Coordinates c : {Coordinates::Quaternion, Coordinates::Linear})
      for (Equations e : {Equations::Lagrange, Equations::Euler}) {
        const std::string label = std::string(integrator) + " " + to_string(c) + "/" + to_string(e);
        CAPTURE(label);
        Scene s = scene_for("heavy_top.toml", c, e, "projection", 1e-6, 0.2);
        s.formulation.projection.every_step = true;
        const Outcome o = run(s, integrator);
        REQUIRE(o.run.status == RunStatus::Success);
        CHECK(o.run.counters.projections > 0);
        multibody::MultibodyProblem system(one_body_system(s));
        const OneBodyView view(system, s);
        long checked = 0;
        double worst = 0.0;
        for (std::size_t k = 0; k < o.sink.step_states.size(); ++k) {
          if (!o.sink.step_projected[k]) continue;
          const Eigen::VectorXd& y = o.sink.step_states[k];
          const VecQ q = view.coordinates(y.data());
          if (c == Coordinates::Quaternion) {
            REQUIRE(q.size() == 4);
            worst = std::max(worst, std::abs(q.squaredNorm() - 1.0));
          } else {
            REQUIRE(q.size() == 9);
            Mat3 R;
            for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = q[i];  // either order: R^T R and R R^T both vanish
            worst = std::max(worst, (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff());
          }
          if (e == Equations::Lagrange) {  // and G v = 0 (velocity level)
            const ConstraintDrift d = view.drift(0.0, y.data());
            worst = std::max(worst, d.velocity / std::max(1.0, view.velocities(y.data()).norm()));
          }
          ++checked;
        }
        CHECK(checked == o.run.counters.projections);
        CHECK(worst < 1e-13);
      }
}

TEST_CASE("ODE integrators: without projection the drift grows, and the integrator/scheme table rejects other pairs") {
  Scene s = scene_for("heavy_top.toml", Coordinates::Quaternion, Equations::Euler, "index1", 1e-6, 0.5);
  const Outcome o = run(s, "arkode-erk");
  REQUIRE(o.run.status == RunStatus::Success);
  CHECK(o.run.counters.projections == 0);
  CHECK(std::abs(o.sink.y_last.head(4).squaredNorm() - 1.0) > 1e-12);  // a pivoted body: q first

  for (const char* i : {"cvode-adams", "cvode-bdf", "arkode-erk"}) {
    CHECK_NOTHROW(check_integrator_scheme(i, "projection"));
    CHECK_NOTHROW(check_integrator_scheme(i, "index1"));
    try {
      check_integrator_scheme(i, "ggl", "scene.toml:3:1");
      FAIL("ggl accepted");
    } catch (const InputError& e) {
      const std::string m = e.what();
      CHECK(m.find("scene.toml:3:1") != std::string::npos);
      CHECK(m.find("index1, projection") != std::string::npos);
    }
  }
  for (const std::string& scheme : scheme_names()) CHECK_NOTHROW(check_integrator_scheme("ida", scheme));
  CHECK_THROWS_AS(find_integrator("rk4"), InputError);
  CHECK_THROWS_AS(find_erk_method("verner87"), InputError);
}

TEST_SUITE_END();
