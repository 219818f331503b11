// Studies over multibody scenes and over integrators: a multibody study runs
// end to end against its tight reference (errors fall as rtol falls), its
// rows carry the timing of runs that record nothing and the machine they ran
// on; the integrators axis runs ODE integrators where they are valid, and an
// integrator a study cannot run is a positioned error.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <sstream>

#include "cli_runner.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"

TEST_SUITE_BEGIN("system");

using namespace rigidae;
namespace fs = std::filesystem;

namespace {

// A shipped multibody scene over a short span (its name kept).
void short_copy(const std::string& problem, const fs::path& to, const std::string& end) {
  std::string text = test::read_file(std::string(RIGIDAE_SOURCE_DIR) + "/problems/" + problem);
  const std::size_t at = text.find("\n[time]");
  REQUIRE(at != std::string::npos);
  const std::size_t end_line = text.find("\nend = ", at);
  REQUIRE(end_line != std::string::npos);
  text.replace(end_line + 7, text.find('\n', end_line + 1) - end_line - 7, end);
  std::ofstream(to) << text;
}

std::string load_error(const fs::path& file) {
  try {
    load_study(file.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("a study over a multibody scene: errors against the tight reference fall as rtol falls") {
  const fs::path dir = test::fresh_temp_dir("study_multibody");
  short_copy("double_pendulum.toml", dir / "dp.toml", "0.3");
  std::ofstream(dir / "study.toml") << "schema_version = 1\nname = \"mb\"\nscenes = [\"dp.toml\"]\n"
                                       "[grid]\ncombinations = [\"quaternion/euler/ggl\", \"euler/lagrange/index1\"]\n"
                                       "rtol = [1e-5, 1e-7, 1e-9]\n[timing]\nwarmups = 0\nrepeats = 2\n";
  const StudySpec spec = load_study((dir / "study.toml").string());
  const std::vector<StudyRun> plan = plan_study(spec);
  REQUIRE(plan.size() == 6);
  StudyRunOptions opt;
  opt.out = dir / "out";
  REQUIRE(run_study(spec, plan, opt));
  for (std::size_t c = 0; c < 2; ++c) {
    double previous = INFINITY;
    for (std::size_t k = 0; k < 3; ++k) {
      const StudyRun& r = plan[3 * c + k];  // loose to tight
      CAPTURE(r.id(spec));
      const nlohmann::json j = nlohmann::json::parse(test::read_file(run_folder(opt.out, spec, r) / "run.json"));
      REQUIRE(j["status"] == "success");
      const double err = j["errors"]["orientation_rad"]["final"].get<double>();
      MESSAGE(r.id(spec) << ": final error " << err << " rad, position "
                         << j["errors"]["position_m"]["final"].get<double>() << " m");
      CHECK(err < previous);
      CHECK(err < 1e3 * r.rtol);
      previous = err;
      // The timed runs record nothing and take the same steps; their final
      // state gives the same error as the recorded run's last grid point.
      CHECK(j["wall_s"].size() == 2);
      CHECK(j["timing"]["same_steps_as_recorded"] == true);
      CHECK(j["timing"]["final_error_rad"].get<double>() == doctest::Approx(err).epsilon(1e-6));
      for (const char* key : {"host", "cpu_model", "load_average", "commit", "compiler"})
        CHECK_FALSE(j["machine"][key].get<std::string>().empty());
      // The verdict (app/error_estimate.hpp): a companion at rtol/100 in the
      // run's folder; its estimate is the error against the reference within a
      // factor 3 (here well above the reference's own error), and it warns
      // exactly past 300 x rtol.
      const nlohmann::json& v = j["error_estimate"];
      REQUIRE(v["source"] == "companion");
      CHECK(v["companion"]["wall_time_s"].get<double>() > 0);
      CHECK(fs::exists(run_folder(opt.out, spec, r) / "error_estimate" / "summary.json"));
      const double estimate = v["orientation"]["max_orientation_rad"].get<double>();
      const double truth = j["errors"]["orientation_rad"]["max"].get<double>();
      if (truth > 1e-9) {
        CHECK(estimate / truth > 1.0 / 3);
        CHECK(estimate / truth < 3.0);
      }
      bool warned = false;
      for (const auto& w : j["warnings"]) warned = warned || w["quantity"] == "orientation_error";
      CHECK(warned == (estimate > 300 * r.rtol));
    }
  }
  std::vector<std::string> missing;
  collect_study(spec, opt.out, &missing);
  CHECK(missing.empty());
  const std::string csv = test::read_file(opt.out / "results.csv");
  for (const char* column : {",integrator,", ",position_error_final_m,", ",final_state_error_rad,", ",cpu_model,",
                             ",load_average,", ",commit,", ",compiler"})
    CHECK(csv.find(column) != std::string::npos);
}

TEST_CASE("a study's integrators axis: valid pairs only, and positioned errors") {
  const fs::path dir = test::fresh_temp_dir("study_integrators");
  short_copy("heavy_top.toml", dir / "top.toml", "0.2");
  short_copy("four_bar.toml", dir / "four_bar.toml", "0.1");
  const std::string head = "schema_version = 1\nscenes = [\"top.toml\"]\n[grid]\nrtol = [1e-6]\n";
  std::ofstream(dir / "ok.toml") << head
                                 << "integrators = [\"ida\", \"cvode-adams\", \"arkode-erk:dopri5\"]\n"
                                    "combinations = [\"quaternion/euler/*\"]\n";
  const StudySpec spec = load_study((dir / "ok.toml").string());
  std::vector<std::string> names;
  for (const StudyRun& r : plan_study(spec)) names.push_back(r.combination.name());
  // IDA runs every scheme; the ODE integrators index1 and projection only.
  CHECK(names.size() == 6 + 2 + 2);
  CHECK(std::count(names.begin(), names.end(), "quaternion/euler/projection@cvode-adams") == 1);
  CHECK(std::count(names.begin(), names.end(), "quaternion/euler/index1@arkode-erk:dopri5") == 1);
  CHECK(std::count(names.begin(), names.end(), "quaternion/euler/ggl@cvode-adams") == 0);
  // The ODE rows run end to end: against the closed-form Lagrange top, within the tolerance's order,
  // and their timed runs (recording nothing) end in the same state.
  std::vector<StudyRun> ode;
  for (const StudyRun& r : plan_study(spec))
    if (r.combination.integrator != "ida") ode.push_back(r);
  StudyRunOptions opt;
  opt.out = dir / "out";
  REQUIRE(run_study(spec, ode, opt));
  for (const StudyRun& r : ode) {
    CAPTURE(r.id(spec));
    const nlohmann::json j = nlohmann::json::parse(test::read_file(run_folder(opt.out, spec, r) / "run.json"));
    CHECK(j["status"] == "success");
    CHECK(j["integrator"] == r.combination.integrator_label());
    const double err = j["errors"]["orientation_rad"]["final"].get<double>();
    CHECK(err < 1e-4);
    CHECK(j["timing"]["final_error_rad"].get<double>() == doctest::Approx(err).epsilon(1e-6));
    CHECK(j["timing"]["same_steps_as_recorded"] == true);
  }

  std::ofstream(dir / "bad1.toml") << head << "integrators = [\"ida\", \"cvode-adam\"]\n";
  std::string m = load_error(dir / "bad1.toml");
  CHECK(m.find("bad1.toml:5:23: error: 'grid.integrators[1]' = \"cvode-adam\" is not an integrator; valid: ida, "
               "cvode-adams") != std::string::npos);
  std::ofstream(dir / "bad2.toml") << head << "integrators = [\"arkode-erk:rk4\"]\n";
  m = load_error(dir / "bad2.toml");
  CHECK(m.find("bad2.toml:5:16: error: 'grid.integrators[0]'") != std::string::npos);
  CHECK(m.find("arkode-erk:fehlberg78") != std::string::npos);
  // Mechanisms run on the ODE integrators too (their ODE form, multibody_ode.hpp).
  std::ofstream(dir / "ode.toml") << "schema_version = 1\nscenes = [\"four_bar.toml\"]\n[grid]\nrtol = [1e-6]\n"
                                     "integrators = [\"ida\", \"cvode-adams\"]\n";
  CHECK(load_study((dir / "ode.toml").string()).integrators.size() == 2);
  std::ofstream(dir / "bad4.toml") << head << "integrators = [\"ida\"]\ncombinations = [\"*@cvode-adams\"]\n";
  m = load_error(dir / "bad4.toml");
  CHECK(m.find("bad4.toml:6:17: error: 'grid.combinations[0]' = \"*@cvode-adams\" matches no combination") !=
        std::string::npos);
}

TEST_SUITE_END();
