// A mechanism body whose Euler-angle chart is within the switching margin at
// its start pose starts in the most regular chart, as the one-body model
// does (MultibodyProblem::choose_start_charts against SingleBodyProblem::
// initial_state), and without switching the start is an error naming the body.
#include <doctest/doctest.h>

#include <string>

#include "rigidae/core/error.hpp"
#include "rigidae/dae/dae_system.hpp"
#include "rigidae/dae/single_body_problem.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

TEST_CASE("multibody start chart: a body near its chart's singularity starts in the one-body model's chart") {
  // sleeping_top: z-x-z, the symmetry axis 1e-3 rad from the vertical (margin |sin b| ~ 1e-3 < 0.1).
  Scene s = io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/sleeping_top.toml");
  const std::unique_ptr<DaeSystem> dae = assemble_dae(s);
  SingleBodyProblem one(*dae, s.formulation.euler, s.R0_WB, s.omega0_B, s.source);
  Eigen::VectorXd y1, yp1;
  one.initial_state(0.0, y1, yp1);
  const std::vector<EventNote> one_events = one.take_events();
  REQUIRE(one_events.size() == 1);

  multibody::MultibodyProblem system(one_body_system(s));
  Eigen::VectorXd y2, yp2;
  system.initial_state(0.0, y2, yp2);
  const std::vector<EventNote> events = system.take_events();
  REQUIRE(events.size() == 1);
  CHECK(events[0].what == "chart_switch");
  CHECK(events[0].t == 0.0);
  CHECK(events[0].body == "body");
  CHECK(events[0].from == "zxz");
  CHECK(events[0].from == one_events[0].from);
  CHECK(events[0].to == one_events[0].to);
  CHECK(events[0].margin == one_events[0].margin);
  CHECK(system.bodies()[0].rep->chart_name() == one.representation().chart_name());
  // The same start, written in the new chart from the physical state.
  REQUIRE(y2.size() == y1.size());
  CHECK((y2 - y1).cwiseAbs().maxCoeff() == 0.0);
  CHECK((yp2 - yp1).cwiseAbs().maxCoeff() == 0.0);
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
