// Hostile and mistaken scene files, run through the real command line: each
// file in tests/bad_scenes/ states, in its first comment lines (or in a
// NAME.toml.expect file beside it when the file cannot hold a comment), the
// message it must get and the line that message must name:
//   # Bad input: what is wrong (the row of docs/bad_input.md)
//   # expect: a substring of the message
//   # expect-line: the line the message names
//   # exit: 0            (only for inputs that are fixed with a warning)
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
using rigidae::test::run_cli;

namespace {

const fs::path kCorpus = fs::path(RIGIDAE_SOURCE_DIR) / "tests" / "bad_scenes";

struct Expectation {
  std::string what, substring;
  int line = 0;
  int exit_code = 2;
};

Expectation read_expectation(const fs::path& scene) {
  const fs::path side = fs::path(scene.string() + ".expect");
  std::ifstream in(fs::exists(side) ? side : scene, std::ios::binary);
  Expectation e;
  std::string line;
  while (std::getline(in, line) && line.rfind("#", 0) == 0) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    auto value = [&](const std::string& key) -> const char* {
      return line.rfind(key, 0) == 0 ? line.c_str() + key.size() : nullptr;
    };
    if (const char* v = value("# Bad input: ")) e.what = v;
    if (const char* v = value("# expect: ")) e.substring = v;
    if (const char* v = value("# expect-line: ")) e.line = std::stoi(v);
    if (const char* v = value("# exit: ")) e.exit_code = std::stoi(v);
  }
  return e;
}

std::vector<fs::path> corpus() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kCorpus))
    if (entry.path().extension() == ".toml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// A control character other than the newline would let a file drive the terminal.
bool has_control_characters(const std::string& s) {
  return std::any_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\n') || u == 0x7f;
  });
}

std::string regex_escape(const std::string& s) {
  static const std::regex special(R"([.^$|()\[\]{}*+?\\])");
  return std::regex_replace(s, special, R"(\$&)");
}

}  // namespace

TEST_CASE("bad input: every scene in tests/bad_scenes gets FILE:LINE:COL, its message and its exit code" * doctest::test_suite("slow")) {
  const fs::path out = rigidae::test::fresh_temp_dir("bad_scenes");
  const std::vector<fs::path> files = corpus();
  CHECK(files.size() >= 90);
  for (const fs::path& scene : files) {
    const Expectation e = read_expectation(scene);
    const fs::path run_dir = out / scene.stem();
    const auto r = run_cli("solve '" + scene.string() + "' --quiet --out '" + run_dir.string() + "'");
    CAPTURE(scene.filename().string());
    CAPTURE(r.output);
    REQUIRE_FALSE(e.substring.empty());
    REQUIRE(e.line > 0);
    CHECK(r.exit_code == e.exit_code);
    CHECK_FALSE(has_control_characters(r.output));
    const std::string kind = e.exit_code == 2 ? "error" : "warning";
    // The message is one line: FILE:LINE:COL: error: ...
    const std::regex form("^" + regex_escape(scene.string()) + R"(:(\d+):(\d+): )" + kind + R"(: (.*)$)");
    std::smatch m;
    const std::string first_line = r.output.substr(0, r.output.find('\n'));
    REQUIRE(std::regex_match(first_line, m, form));
    CHECK(std::stoi(m[1]) == e.line);
    CHECK(std::stoi(m[2]) >= 1);
    CHECK(m[3].str().find(e.substring) != std::string::npos);
    if (e.exit_code == 2) {
      CHECK(r.output == first_line + "\n");  // nothing else
      CHECK_FALSE(fs::exists(run_dir));       // bad input creates no output folder
    } else {
      CHECK(fs::exists(run_dir / "summary.json"));
    }
  }
  fs::remove_all(out);
}

TEST_CASE("bad input: every expectation file belongs to a scene") {
  for (const auto& entry : fs::directory_iterator(kCorpus)) {
    const fs::path p = entry.path();
    CAPTURE(p.filename().string());
    CHECK((p.extension() == ".toml" || p.extension() == ".expect"));
    if (p.extension() == ".expect") CHECK(fs::exists(p.parent_path() / p.stem()));
  }
}

TEST_CASE("bad input: a huge file, a device, a folder and a missing file are refused without reading them") {
  const fs::path dir = rigidae::test::fresh_temp_dir("huge");
  // A valid scene followed by NUL bytes up to 65 MiB (a sparse file: nothing is written).
  const fs::path huge = dir / "huge.toml";
  {
    std::ofstream f(huge);
    f << rigidae::test::read_file(fs::path(RIGIDAE_SOURCE_DIR) / "problems" / "heavy_top.toml");
  }
  fs::resize_file(huge, std::uintmax_t{65} << 20);
  auto r = run_cli("solve '" + huge.string() + "' --out '" + (dir / "out").string() + "'");
  CAPTURE(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(huge.string() + ": error: ") == 0);
  CHECK(r.output.find("larger than 67108864 bytes") != std::string::npos);
  // /dev/zero never ends: only the size limit stops the reading.
  r = run_cli("solve /dev/zero");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("/dev/zero: error: ") == 0);
  r = run_cli("solve '" + dir.string() + "'");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("it is a directory") != std::string::npos);
  r = run_cli("solve '" + (dir / "nothing.toml").string() + "'");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("No such file or directory") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("bad input: command-line overrides obey the scene file's limits") {
  const std::string scene = (fs::path(RIGIDAE_SOURCE_DIR) / "problems" / "heavy_top.toml").string();
  struct Case {
    const char* options;
    const char* message;
  };
  for (const Case& c : {Case{"--rtol 1e-15", "option --rtol: 1e-15 must lie in [1e-14, 1)"},
                        Case{"--atol 1e-200", "option --atol: 1e-200 must lie in [1e-100, 1)"},
                        Case{"--t-end 1e300", "option --t-end: 1e+300 must lie in [-1e+09, 1e+09]"},
                        Case{"--t-end 1e7", "output intervals"},  // the scene's 0.01 s grid: 1e9 points
                        Case{"--t-end nan", "is not a finite number"},
                        Case{"--max-steps 1e99", "option --max-steps: 1e+99 must be an integer from 1 to 1e+15"},
                        Case{"--max-order 0", "option --max-order: 0 must be an integer from 1 to 5"},
                        Case{"--output-step -1", "option --output-step: -1 must be > 0"}}) {
    const auto r = run_cli("solve " + scene + " " + c.options);
    CAPTURE(std::string(c.options));
    CAPTURE(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.rfind("rigidae: error: ", 0) == 0);
    CHECK(r.output.find(c.message) != std::string::npos);
  }
  // Together they are fine: a longer run with a coarser grid.
  const fs::path out = rigidae::test::fresh_temp_dir("long_grid");
  const auto r = run_cli("solve " + scene + " --t-end 1e7 --output-step 1e6 --max-steps 10 --out " + out.string());
  CHECK(r.exit_code == 1);  // too much work, by design: the grid was accepted
  CHECK(r.output.find("too much work") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("bad input: a scene path that is not UTF-8 still gives a valid summary.json") {
  const fs::path dir = rigidae::test::fresh_temp_dir("latin1");
  const fs::path scene = dir / "k\xf6rper.toml";  // "koerper" in Latin-1, not UTF-8
  fs::copy_file(fs::path(RIGIDAE_SOURCE_DIR) / "problems" / "free_body.toml", scene);
  const auto r = run_cli("solve '" + scene.string() + "' --t-end 0.1 --quiet --out '" + (dir / "out").string() + "'");
  CAPTURE(r.output);
  CHECK(r.exit_code == 0);
  const std::string summary = rigidae::test::read_file(dir / "out" / "summary.json");
  CHECK(summary.find("\"status\": \"success\"") != std::string::npos);
  CHECK(summary.find("k\xef\xbf\xbdrper.toml") != std::string::npos);  // the byte replaced by U+FFFD
  fs::remove_all(dir);
}

TEST_SUITE_END();
