// Inputs the fuzzer (fuzz/fuzz_scene_loader.cpp) found to break the scene
// loader, kept in tests/fuzz_regressions/ after the fix: each must now give a
// clean InputError whose message is one printable line "FILE:LINE:COL: error: ...".
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>

#include "cli_runner.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"

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
