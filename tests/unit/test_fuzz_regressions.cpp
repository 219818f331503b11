// Inputs the fuzzer (fuzz/fuzz_scene_loader.cpp) found to break the scene
// loader, kept in tests/fuzz_regressions/ after the fix: each must now give a
// clean InputError whose message is one printable line "FILE:LINE:COL: error: ...".
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <regex>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/multibody/multibody_problem.hpp"

TEST_SUITE_BEGIN("unit");

namespace fs = std::filesystem;

TEST_CASE("fuzz regressions: every input the fuzzer found gives a clean one-line InputError") {
  const fs::path dir = fs::path(RIGIDAE_SOURCE_DIR) / "tests" / "fuzz_regressions";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".md") continue;
    ++files;
    const std::string text = rigidae::test::read_file(entry.path());
    std::string message;
    CAPTURE(entry.path().filename().string());
    // NAME.study.toml: a study file (fuzz/fuzz_study_loader.cpp), read from its
    // path; anything else: a scene (fuzz/fuzz_scene_loader.cpp), from memory.
    const std::string name = entry.path().filename().string();
    const bool study = name.size() > 11 && name.compare(name.size() - 11, 11, ".study.toml") == 0;
    try {
      if (study)
        (void)rigidae::load_study(entry.path().string());
      else
        (void)rigidae::io::parse_scene(text, "fuzz.toml");
    } catch (const rigidae::InputError& e) {
      message = e.what();
    }
    CAPTURE(message);
    const std::string file = study ? std::regex_replace(entry.path().string(), std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)")
                                   : std::string(R"(fuzz\.toml)");
    CHECK(std::regex_match(message, std::regex(file + R"(:[1-9][0-9]*:[1-9][0-9]*: error: [^\n]+)")));
    CHECK(std::none_of(message.begin(), message.end(),
                       [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }));
  }
  CHECK(files >= 1);
}

// Found by fuzz/fuzz_scene_loader.cpp (ASan: stack-use-after-scope): a chain
// whose joint j8 closes a loop (link7 back to link4) with all links on the x
// axis, where the loop's rows depend on one another. The start's rank check
// listed the dependent rows through a reference to a temporary permutation.
// Truth: the four links of the loop are collinear, so the closing joint's
// rows along the chain repeat the others. Dependent rows are now set aside
// (multibody_problem.hpp, "Redundant constraints"): the start must accept
// the loop, name every row set aside in one positioned warning, and count
// them as rows minus rank; the rank check at nearby poses decides whether
// the collinear pose is a singular start, and then says so.
TEST_CASE("fuzz regressions: a collinear loop of spherical joints starts with its dependent rows set aside") {
  std::string text = rigidae::test::read_file(fs::path(RIGIDAE_SOURCE_DIR) / "problems" / "chain_10.toml");
  const std::string joint = "bodies = [\"link7\", \"link8\"]";
  const std::size_t at = text.find(joint);
  REQUIRE(at != std::string::npos);
  text.replace(at, joint.size(), "bodies = [\"link7\", \"link4\"]");
  const rigidae::Scene scene = rigidae::io::parse_scene(text, "loop.toml");
  std::unique_ptr<rigidae::multibody::MultibodyProblem> problem;
  REQUIRE_NOTHROW(problem = std::make_unique<rigidae::multibody::MultibodyProblem>(scene));
  const rigidae::multibody::RedundancyReport& r = problem->redundancy();
  const int dependent = static_cast<int>(r.dropped.size());
  CHECK(dependent >= 1);
  CHECK(dependent == r.rows - r.rank);
  REQUIRE(!problem->warnings().empty());
  const std::string& message = problem->warnings()[0];
  CAPTURE(message);
  CHECK(message.find('\n') == std::string::npos);
  CHECK(std::regex_search(
      message, std::regex(R"(^loop\.toml:[0-9]+:[0-9]+: [0-9]+ of the [0-9]+ constraint rows (is|are) redundant)")));
  for (const auto& d : r.dropped)
    CHECK(message.find(scene.multibody->joints[d.joint].name + "." + d.row) != std::string::npos);
  bool singular_warned = false;
  for (const std::string& w : problem->warnings()) singular_warned |= w.find("singular start") != std::string::npos;
  CHECK(singular_warned == r.singular_start);
  MESSAGE("collinear loop: " << dependent << " rows set aside, rank " << r.rank << " at the start, " << r.nearby_rank
                             << " nearby; singular start: " << r.singular_start);
}

TEST_SUITE_END();
