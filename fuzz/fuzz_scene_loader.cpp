// libFuzzer target: the scene loader and validator on arbitrary bytes.
//
// Every input must end in one of two ways: an InputError (bad input, the
// CLI's exit 2) whose message is one line "fuzz.toml:LINE:COL: error: ..."
// of printable text and reasonable length, or a Scene that is physically
// valid -- a proper rotation, a positive mass, a positive definite inertia,
// a time span, and a DAE that assembles and starts with finite numbers.
// Anything else (a crash, a sanitizer report, another exception, a
// malformed message, a valid-looking scene that is not) is a finding.
// Build and run: tools/fuzz.sh (docs/robustness.md).
#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "fuzz_check.hpp"

const char* const rigidae_fuzz::kTarget = "fuzz_scene_loader";

namespace {

using namespace rigidae;

using rigidae_fuzz::require;

// The form the CLI and the docs promise for every scene-file error.
void check_message(const std::string& m) {
  const std::size_t i = std::string("fuzz.toml:").size();
  require(m.compare(0, i, "fuzz.toml:") == 0, "an error message without the file name");
  rigidae_fuzz::check_message_after_file(m, i);
}

void check_valid(const Scene& s) {
  require(s.body.mass > 0 && std::isfinite(s.body.mass), "a scene with a bad mass");
  require(s.body.inertia_com.allFinite() && s.body.inertia_com.isApprox(s.body.inertia_com.transpose()),
          "a non-symmetric inertia");
  require(Eigen::SelfAdjointEigenSolver<Mat3>(s.body.inertia_com).eigenvalues().minCoeff() > 0,
          "an inertia that is not positive definite");
  require(s.R0_WB.allFinite() && (s.R0_WB.transpose() * s.R0_WB - Mat3::Identity()).norm() < 1e-12 &&
              s.R0_WB.determinant() > 0,
          "an initial orientation that is not a rotation");
  require(s.omega0_B.allFinite() && s.gravity_W.allFinite() && s.body.com_B.allFinite(), "a non-finite vector");
}

void check_time_and_solver(const Scene& s) {
  require(std::isfinite(s.time.start) && std::isfinite(s.time.end) && s.time.end > s.time.start,
          "a bad time span");
  require(s.time.output_step > 0 && s.time.output_step <= s.time.end - s.time.start, "a bad output step");
  require(s.solver.rtol > 0 && s.solver.rtol < 1 && s.solver.atol > 0 && s.solver.atol < 1, "bad tolerances");
  require(s.solver.max_order >= 1 && s.solver.max_order <= 5 && s.solver.max_steps >= 1, "bad solver limits");
}

// A schema-2 scene: every body physical, every joint and force naming bodies
// that exist with finite unit axes, and an assembled problem whose consistent
// start (or its positioned refusal: a joint missed, dependent rows) is finite.
void check_multibody(const Scene& s) {
  const MultibodySpec& mb = *s.multibody;
  require(!mb.bodies.empty(), "a multibody scene without bodies");
  const int n = static_cast<int>(mb.bodies.size());
  for (const BodySpec& b : mb.bodies) {
    require(b.mass > 0 && std::isfinite(b.mass), "a body with a bad mass");
    require(b.inertia_com.allFinite() && b.inertia_com.isApprox(b.inertia_com.transpose()),
            "a body with a non-symmetric inertia");
    require(Eigen::SelfAdjointEigenSolver<Mat3>(b.inertia_com).eigenvalues().minCoeff() > 0,
            "a body whose inertia is not positive definite");
    require(b.R0_WB.allFinite() && (b.R0_WB.transpose() * b.R0_WB - Mat3::Identity()).norm() < 1e-12 &&
                b.R0_WB.determinant() > 0,
            "a body whose initial orientation is not a rotation");
    require(b.x0_W.allFinite() && b.v0_W.allFinite() && b.omega0_B.allFinite(), "a body with a non-finite vector");
  }
  auto body_ok = [n](int i) { return i == kGround || (i >= 0 && i < n); };
  for (const JointSpec& j : mb.joints) {
    require(body_ok(j.body_a) && body_ok(j.body_b) && j.body_a != j.body_b, "a joint naming bad bodies");
    for (const Vec3* a : {&j.axis_a, &j.axis_b, &j.normal_a, &j.normal_b})
      require(a->allFinite() && std::abs(a->norm() - 1) < 1e-12, "a joint axis that is not a unit vector");
    require(j.point_a.allFinite() && j.point_b.allFinite(), "a joint point that is not finite");
  }
  for (const SpringSpec& sp : mb.springs)
    require(body_ok(sp.body_a) && body_ok(sp.body_b) && std::isfinite(sp.stiffness) && sp.stiffness >= 0 &&
                std::isfinite(sp.damping) && sp.damping >= 0 && std::isfinite(sp.rest_length) && sp.rest_length >= 0,
            "a bad spring");
  for (const BodyLoadSpec& l : mb.loads)
    require(l.body >= 0 && l.body < n && l.force.allFinite() && l.torque.allFinite(), "a bad body load");
  require(mb.gravity_W.allFinite(), "a non-finite gravity");

  // Large mechanisms only slow the fuzzer down; the loader caps nothing here.
  if (n > 64) return;
  std::unique_ptr<multibody::MultibodyProblem> problem;
  try {
    problem = std::make_unique<multibody::MultibodyProblem>(s);
  } catch (const InputError& e) {
    check_message(e.what());
    return;
  }
  Eigen::VectorXd y, yp, F(problem->size());
  problem->initial_state(s.time.start, y, yp);
  require(y.allFinite() && yp.allFinite(), "a multibody start that is not finite");
  problem->residual(s.time.start, y.data(), yp.data(), F.data());
  require(F.allFinite(), "a multibody residual at the start that is not finite");
}

void check_start(const Scene& s) {
  // The scene as every scene runs: a system of one pivoted body.
  std::unique_ptr<multibody::MultibodyProblem> problem;
  try {
    problem = std::make_unique<multibody::MultibodyProblem>(one_body_system(s));
  } catch (const InputError&) {
    return;  // a formulation that does not apply to this scene, reported as bad input
  }
  Eigen::VectorXd y, yp, F(problem->size());
  problem->initial_state(s.time.start, y, yp);
  require(y.allFinite() && yp.allFinite(), "a start that is not finite");
  problem->residual(s.time.start, y.data(), yp.data(), F.data());
  require(F.allFinite(), "a residual at the start that is not finite");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::cerr.rdbuf(nullptr);  // the loader's warnings would flood the fuzzer's output
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Scene scene;
  try {
    scene = io::parse_scene(text, "fuzz.toml");
  } catch (const InputError& e) {
    check_message(e.what());
    return 0;
  }
  check_time_and_solver(scene);
  if (scene.multibody) {
    check_multibody(scene);
    return 0;
  }
  check_valid(scene);
  check_start(scene);
  return 0;
}
