// Redundant constraints and mobility (multibody_problem.hpp, "Redundant
// constraints"), against independent truth:
// - the planar four-bar of four revolute hinges (problems/four_bar_revolute.toml,
//   20 rows, rank 17) moves as the same four-bar with the redundant
//   conditions relaxed by a spherical and a universal joint
//   (problems/four_bar.toml, 17 independent rows), run tighter as the
//   reference: crank angle over time, every IDA scheme in quaternion
//   coordinates and a few other representations;
// - the rows set aside stay implied (their Phi stays at round-off), energy is
//   conserved (no forces but gravity);
// - mobility: rank 1, Gruebler-Kutzbach 6*3 - 20 = -2; expected_dof warns;
// - a loop that cannot close, in plane or out of plane (where only the rows
//   set aside see it), stays a positioned error.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "scene_edit.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ida_driver.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
using multibody::MultibodyProblem;
namespace fs = std::filesystem;

namespace {

fs::path problem_path(const std::string& name) { return fs::path(RIGIDAE_SOURCE_DIR) / "problems" / name; }

std::string problem_text(const std::string& name) { return rigidae::test::read_file(problem_path(name)); }

// The crank's angle about space y from its orientation (w, x, y, z).
double crank_angle(MultibodyProblem& p, const double* y) {
  const Vec4 q = p.body_orientation(0, y);
  return 2.0 * std::atan2(q(2), q(0));
}

double wrap(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

struct Trace {
  std::vector<double> t, angle, energy, dropped_phi;
  RunStatus status = RunStatus::Failed;
};

class TraceSink final : public StepSink {
 public:
  TraceSink(MultibodyProblem& p, Trace& out) : p_(p), out_(out) {}
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double t, const Eigen::VectorXd& y) override {
    out_.t.push_back(t);
    out_.angle.push_back(crank_angle(p_, y.data()));
    out_.energy.push_back(p_.kinetic_energy(y.data()) + p_.potential_energy(y.data()));
    out_.dropped_phi.push_back(p_.dropped_drift(y.data()).first);
  }

 private:
  MultibodyProblem& p_;
  Trace& out_;
};

Trace run(Scene s, double end, double tol) {
  s.time = {0.0, end, 0.01};
  s.solver.rtol = s.solver.atol = tol;
  MultibodyProblem p(s);
  Trace tr;
  TraceSink sink(p, tr);
  tr.status = integrate(p, s.solver, s.time, sink).status;
  return tr;
}

}  // namespace

TEST_CASE("redundant: the revolute four-bar's rank, mobility and rows set aside") {
  const Scene s = io::load_scene(problem_path("four_bar_revolute.toml").string());
  MultibodyProblem p(s);
  const multibody::RedundancyReport& r = p.redundancy();
  CHECK(r.velocities == 18);
  CHECK(r.joint_rows == 20);
  CHECK(r.rank == 17);
  CHECK(r.rank_dof == 1);
  CHECK(r.gruebler_dof == -2);
  REQUIRE(r.dropped.size() == 3);
  CHECK_FALSE(r.singular_start);
  CHECK(r.nearby_rank == 17);  // the redundancy persists along the motion
  // Every joint takes part in the out-of-plane dependency: all four have
  // indeterminate reactions.
  CHECK(r.indeterminate_joints.size() == 4);
  std::string rows;
  for (int k = 0; k < 3; ++k) {
    CHECK(std::regex_search(p.dropped_row_source(k), std::regex(R"(four_bar_revolute\.toml:[0-9]+:1$)")));
    rows += s.multibody->joints[r.dropped[k].joint].name + "." + r.dropped[k].row + " ";
  }
  MESSAGE("rows set aside: " << rows);
  // The warning names them, positioned.
  bool named = false;
  for (const std::string& w : p.warnings()) named |= w.find("3 of the 20 constraint rows are redundant") != std::string::npos;
  CHECK(named);
  // expected_dof = 1 in the scene: no mobility warning.
  CHECK(r.mobility_warning.empty());

  // The relaxed four-bar: independent rows, the same mobility.
  const Scene relaxed = io::load_scene(problem_path("four_bar.toml").string());
  MultibodyProblem q(relaxed);
  CHECK(q.redundancy().rank == 17);
  CHECK(q.redundancy().rank_dof == 1);
  CHECK(q.redundancy().gruebler_dof == 1);
  CHECK(q.redundancy().dropped.empty());
  CHECK(q.redundancy().indeterminate_joints.empty());
}

TEST_CASE("redundant: the revolute four-bar moves as the relaxed one, every IDA scheme") {
  // Reference: the relaxed four-bar (spherical B, universal C), tight.
  const Scene relaxed = io::load_scene(problem_path("four_bar.toml").string());
  const double end = 1.0;
  const Trace ref = run(relaxed, end, 1e-11);
  REQUIRE(ref.status == RunStatus::Success);
  const Scene base = io::load_scene(problem_path("four_bar_revolute.toml").string());
  struct Combo {
    Coordinates c;
    Equations e;
    const char* scheme;
  };
  std::vector<Combo> combos;
  for (const char* scheme : {"index3", "index2", "index1", "baumgarte", "ggl", "projection"})
    combos.push_back({Coordinates::Quaternion, Equations::Euler, scheme});
  combos.push_back({Coordinates::Quaternion, Equations::Lagrange, "ggl"});
  combos.push_back({Coordinates::EulerAngles, Equations::Euler, "ggl"});
  combos.push_back({Coordinates::EulerAngles, Equations::Lagrange, "index2"});
  combos.push_back({Coordinates::Linear, Equations::Euler, "ggl"});
  combos.push_back({Coordinates::Linear, Equations::Lagrange, "ggl"});
  for (const Combo& k : combos) {
    const std::string label = to_string(k.c) + "/" + to_string(k.e) + "/" + k.scheme;
    CAPTURE(label);
    Scene s = base;
    s.formulation.coordinates = k.c;
    s.formulation.equations = k.e;
    s.formulation.scheme = k.scheme;
    const Trace tr = run(s, end, 1e-9);
    REQUIRE(tr.status == RunStatus::Success);
    REQUIRE(tr.t.size() == ref.t.size());
    // The relaxed four-bar in the same combination: its own error against
    // the reference bounds what the scheme itself costs (index3's is large).
    Scene rs = relaxed;
    rs.formulation = s.formulation;
    const Trace same = run(rs, end, 1e-9);
    REQUIRE(same.status == RunStatus::Success);
    double angle = 0.0, angle_relaxed = 0.0, phi = 0.0, energy = 0.0, energy_relaxed = 0.0;
    for (std::size_t i = 0; i < tr.t.size(); ++i) {
      angle = std::max(angle, std::abs(wrap(tr.angle[i] - ref.angle[i])));
      angle_relaxed = std::max(angle_relaxed, std::abs(wrap(same.angle[i] - ref.angle[i])));
      phi = std::max(phi, tr.dropped_phi[i]);
      energy = std::max(energy, std::abs(tr.energy[i] - tr.energy[0]) / std::abs(tr.energy[0]));
      energy_relaxed = std::max(energy_relaxed, std::abs(same.energy[i] - same.energy[0]) / std::abs(same.energy[0]));
    }
    MESSAGE(label << ": crank angle vs relaxed reference " << angle << " rad (relaxed, same combination: "
                  << angle_relaxed << "), rows set aside |Phi| " << phi << ", energy " << energy
                  << " relative (relaxed: " << energy_relaxed << ")");
    // The crank turns about 6 rad in 1 s: agreement to the tolerance's order,
    // or within a few times what the scheme costs on the relaxed mechanism.
    CHECK(angle < std::max(1e-5, 3.0 * angle_relaxed));
    CHECK(energy < std::max(1e-6, 3.0 * energy_relaxed));
    CHECK(phi < 1e-9);
  }
}

TEST_CASE("redundant: expected_dof warns when the mobility differs, and bad values are positioned errors") {
  std::string text = problem_text("four_bar_revolute.toml");
  const std::string key = "expected_dof = 1";
  const std::size_t at = text.find(key);
  REQUIRE(at != std::string::npos);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  {
    std::string t2 = text;
    t2.replace(at, key.size(), "expected_dof = 2");
    MultibodyProblem p(io::parse_scene(t2, "fb.toml"));
    CHECK(p.redundancy().mobility_warning.find(fmt::format("fb.toml:{}:", line)) == 0);
    CHECK(p.redundancy().mobility_warning.find("expected_dof = 2, but the mechanism's mobility is 1") !=
          std::string::npos);
    bool warned = false;
    for (const std::string& w : p.warnings()) warned |= w == p.redundancy().mobility_warning;
    CHECK(warned);
  }
  const auto error_of = [&](const std::string& replacement) {
    return rigidae::test::parse_error_with(text, at, key.size(), replacement, "fb.toml");
  };
  for (const std::string bad : {"expected_dof = -1", "expected_dof = 1.5", "expected_dof = \"one\"",
                                "expected_dof = 19", "expected_dofs = 1"}) {
    CAPTURE(bad);
    const std::string msg = error_of(bad);
    CHECK(msg.find(fmt::format("fb.toml:{}:", line)) == 0);
  }
  // Top level and [mechanism] together: refused.
  std::string both = text;
  both.insert(both.find("schema_version = 2\n") + 19, "expected_dof = 1\n");
  CHECK_THROWS_AS(io::parse_scene(both, "fb.toml"), InputError);
  // Top level alone is accepted.
  std::string top = text;
  top.replace(at, key.size(), "");
  top.insert(top.find("schema_version = 2\n") + 19, "expected_dof = 3\n");
  MultibodyProblem p(io::parse_scene(top, "fb.toml"));
  CHECK(p.redundancy().mobility_warning.find("expected_dof = 3") != std::string::npos);
}

TEST_CASE("redundant: a loop that cannot close is still a positioned error, in plane and out of plane") {
  const std::string text = problem_text("four_bar_revolute.toml");
  const std::size_t joint_d = text.find("name = \"D\"");
  REQUIRE(joint_d != std::string::npos);
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(joint_d), '\n'));
  // D's point on the ground moved: in the plane (a kept row misses) and out
  // of it (only D.y, a row set aside, misses).
  for (const Vec3& moved : {Vec3(1e-3, 0, 0), Vec3(0, 1e-3, 0)}) {
    CAPTURE(moved.transpose());
    Scene s = io::parse_scene(text, "fb.toml");
    REQUIRE(s.multibody->joints[3].body_b == kGround);
    s.multibody->joints[3].point_b += moved;
    std::string msg = "no error";
    try {
      MultibodyProblem p(s);
    } catch (const InputError& e) {
      msg = e.what();
    }
    MESSAGE(msg);
    CHECK(msg.find(fmt::format("fb.toml:{}:1: error: joint 'D' (revolute) row '", line)) == 0);
    CHECK(msg.find("miss the joint by 0.001") != std::string::npos);
  }
}

TEST_CASE("redundant: summary.json names the rows set aside, the mobility and the undetermined reactions") {
  const fs::path out = rigidae::test::fresh_temp_dir("redundant_summary");
  Scene s = io::load_scene(problem_path("four_bar_revolute.toml").string());
  s.time = {0.0, 0.2, 0.01};
  const SolveOutcome o = solve_scene(s, out);
  REQUIRE(o.run.status == RunStatus::Success);
  const nlohmann::json j = nlohmann::json::parse(rigidae::test::read_file(out / "summary.json"));
  CHECK(j["mobility"]["rank_dof"] == 1);
  CHECK(j["mobility"]["gruebler_dof"] == -2);
  CHECK(j["mobility"]["redundant_rows"] == 3);
  REQUIRE(j["redundant_rows"].size() == 3);
  CHECK(j["redundant_rows"][0]["source"].get<std::string>().find("four_bar_revolute.toml:") != std::string::npos);
  CHECK(j["reactions_determined"] == false);
  CHECK(j["reactions_indeterminate_joints"].size() == 4);
  CHECK(o.note.find("mobility 1 (rank), -2 (Gruebler-Kutzbach), 3 redundant rows set aside") != std::string::npos);
  // The relaxed four-bar: determined.
  Scene r = io::load_scene(problem_path("four_bar.toml").string());
  r.time = {0.0, 0.05, 0.01};
  const fs::path out2 = rigidae::test::fresh_temp_dir("redundant_summary_relaxed");
  REQUIRE(solve_scene(r, out2).run.status == RunStatus::Success);
  const nlohmann::json j2 = nlohmann::json::parse(rigidae::test::read_file(out2 / "summary.json"));
  CHECK(j2["reactions_determined"] == true);
  CHECK(j2["redundant_rows"].empty());
  CHECK(j2["mobility"]["gruebler_dof"] == 1);
}

TEST_CASE("redundant: Bricard's 6R loop has mobility 1 from the rank, 0 by Gruebler-Kutzbach, and runs") {
  const Scene s = io::load_scene(problem_path("bricard.toml").string());
  MultibodyProblem p(s);
  const multibody::RedundancyReport& r = p.redundancy();
  CHECK(r.joint_rows == 30);
  CHECK(r.rank == 29);
  CHECK(r.rank_dof == 1);
  CHECK(r.gruebler_dof == 0);
  CHECK(r.dropped.size() == 1);
  // Rank 29 at the nearby poses too: redundancy, not a singular start.
  CHECK_FALSE(r.singular_start);
  CHECK(r.nearby_rank == 29);
  CHECK(r.mobility_warning.empty());  // the scene says expected_dof = 1
  // Gravity drives the one freedom; energy is conserved and the row set
  // aside, implied only on the constraint manifold, drifts like the others.
  for (const char* scheme : {"ggl", "index2", "projection"}) {
    CAPTURE(std::string(scheme));
    Scene t = s;
    t.formulation.scheme = scheme;
    const Trace tr = run(t, 0.5, 1e-9);
    REQUIRE(tr.status == RunStatus::Success);
    double phi = 0.0, energy = 0.0;
    for (std::size_t i = 0; i < tr.t.size(); ++i) {
      phi = std::max(phi, tr.dropped_phi[i]);
      energy = std::max(energy, std::abs(tr.energy[i] - tr.energy[0]));
    }
    MESSAGE("bricard " << std::string(scheme) << ": dropped row |Phi| " << phi << ", |energy change| " << energy << " J");
    CHECK(phi < 1e-6);
    CHECK(energy < 1e-5);
  }
}

TEST_SUITE_END();
