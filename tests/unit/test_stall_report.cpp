// What a mechanism says when its step size collapses
// (MultibodyProblem::describe_stall, src/multibody/stall_report.cpp): its
// scheme and whether its constraint rows still have full rank. The CLI's
// step-size floor itself is tested in tests/python/test_stops.py.
#include <doctest/doctest.h>

#include <string>

#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

TEST_SUITE_BEGIN("unit");

using rigidae::multibody::MultibodyProblem;

TEST_CASE("stall report: a mechanism at a regular state names its scheme and full-rank rows") {
  for (const char* name : {"four_bar", "double_pendulum", "slider_mechanism"}) {
    CAPTURE(name);
    const rigidae::Scene s = rigidae::io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/" + name + ".toml");
    MultibodyProblem p(s);
    Eigen::VectorXd y, yp;
    p.initial_state(s.time.start, y, yp);
    const std::string text = p.describe_stall(s.time.start, y.data());
    CHECK(text.rfind("Formulation: " + p.bodies().front().rep->name() + " with scheme " + p.scheme().name + ", on " +
                         std::to_string(p.bodies().size()) + " bodies and " + std::to_string(s.multibody->joints.size()) +
                         " joints.",
                     0) == 0);
    CHECK(text.find("constraint rows keep full rank at t = 0 s") != std::string::npos);
    CHECK(text.find("lost rank") == std::string::npos);
  }
}

TEST_SUITE_END();
