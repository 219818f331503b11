// A body whose Euler-angle chart is within the switching margin at its start
// pose starts in the most regular chart (MultibodyProblem::
// choose_start_charts, the one-body model's rule): the chart the
// representation itself names most regular there, the start written in it
// from the physical state; without switching the start is an error naming
// the body.
#include <doctest/doctest.h>

#include <string>

#include "rigidae/core/error.hpp"
#include "rigidae/coords/representation.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

TEST_CASE("multibody start chart: a body near its chart's singularity starts in the one-body model's chart") {
  // sleeping_top: z-x-z, the symmetry axis 1e-3 rad from the vertical (margin |sin b| ~ 1e-3 < 0.1).
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/sleeping_top.toml");
  // The scene's chart at the start pose, and the chart it calls most regular there.
  const RigidBodyModel model = make_rigid_body_model(s);
  const std::unique_ptr<Representation> scene_chart = make_representation(s, model);
  REQUIRE(scene_chart->chart_name() == "zxz");
  VecQ q0;
  VecV v0;
  scene_chart->from_physical(s.R0_WB, s.omega0_B, q0, v0);
  const double margin = scene_chart->chart_margin(q0);
  CHECK(margin < s.formulation.euler.switch_threshold);
  const int best = scene_chart->most_regular_chart(q0);
  REQUIRE(best != scene_chart->chart());
  const std::unique_ptr<Representation> best_chart = scene_chart->in_chart(best);
  VecQ q1;
  VecV v1;
  best_chart->from_physical(s.R0_WB, s.omega0_B, q1, v1);

  multibody::MultibodyProblem system(one_body_system(s));
  Eigen::VectorXd y2, yp2;
  system.initial_state(0.0, y2, yp2);
  const std::vector<EventNote> events = system.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0].what == "chart_switch");
  CHECK(events[0].t == 0.0);
  CHECK(events[0].body == "body");
  CHECK(events[0].from == "zxz");
  CHECK(events[0].to == best_chart->chart_name());
  CHECK(events[0].margin == doctest::Approx(margin).epsilon(1e-12));
  CHECK(system.bodies()[0].rep->chart_name() == best_chart->chart_name());
  // The start written in the new chart from the physical state (Euler
  // angles: no multipliers, y = (q, v)).
  REQUIRE(y2.size() == q1.size() + v1.size());
  CHECK((y2.head(q1.size()) - q1).cwiseAbs().maxCoeff() <= 1e-14);
  CHECK((y2.tail(v1.size()) - v1).cwiseAbs().maxCoeff() <= 1e-12 * std::max(1.0, v1.cwiseAbs().maxCoeff()));
  // A second run of the same problem notes the start's switch again.
  system.initial_state(0.0, y2, yp2);
  CHECK(system.take_events().size() == 1);

  s.formulation.euler.switching = false;
  try {
    multibody::MultibodyProblem refused(one_body_system(s));
    FAIL("a start within the singularity margin without switching must be refused");
  } catch (const InputError& e) {
    const std::string m = e.what();
    CAPTURE(m);
    CHECK(m.find("body 'body'") != std::string::npos);
    CHECK(m.find("'zxz' is within its singularity margin") != std::string::npos);
    CHECK(m.find("enable switching") != std::string::npos);
  }
}

TEST_SUITE_END();
