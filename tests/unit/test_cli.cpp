// The command line as a user meets it: exit codes, messages, output files.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.hpp"

TEST_SUITE_BEGIN("system");

namespace {

using Result = rigidae::test::CliResult;
using rigidae::test::run_cli;

std::filesystem::path temp_scene(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "rigidae_cli_tests";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

const std::string kScene = std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml";

}  // namespace

TEST_CASE("cli: solve writes the three outputs and exits 0") {
  const auto out = std::filesystem::temp_directory_path() / "rigidae_cli_tests" / "ok";
  std::filesystem::remove_all(out);
  const Result r = run_cli("solve " + kScene + " --t-end 0.2 --out " + out.string());
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("status        success") != std::string::npos);
  for (const char* f : {"steps.csv", "trajectory.csv", "summary.json", "events.csv"})
    CHECK(std::filesystem::exists(out / f));
}

TEST_CASE("cli: unknown option values are errors that list the valid ones") {
  Result r = run_cli("solve " + kScene + " --coordinates rodrigues");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("'euler', 'quaternion' or 'linear'") != std::string::npos);
  r = run_cli("solve " + kScene + " --scheme magic");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("ggl") != std::string::npos);
  r = run_cli("solve " + kScene + " --rtol 2");
  CHECK(r.exit_code == 2);
  r = run_cli("solve " + kScene + " --bogus 1");
  CHECK(r.exit_code == 2);
  r = run_cli("frobnicate");
  CHECK(r.exit_code == 2);
}

TEST_CASE("cli: --help explains the options") {
  const Result r = run_cli("--help");
  CHECK(r.exit_code == 0);
  for (const char* opt : {"--coordinates", "--equations", "--scheme", "--rtol", "--atol", "--t-end", "--out"})
    CHECK(r.output.find(opt) != std::string::npos);
}

TEST_CASE("cli: a scene with a syntax error names its line and exits 2") {
  const auto p = temp_scene("syntax.toml", "schema_version = 1\n[body\nmass = 1\n");
  const Result r = run_cli("solve " + p.string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(p.string() + ":2:") != std::string::npos);
}

TEST_CASE("cli: a scene with an unknown key names its line and exits 2") {
  std::ifstream in(kScene);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("mass = 15.0"), 11, "mas = 15.0");
  const auto p = temp_scene("unknown_key.toml", text);
  const Result r = run_cli("solve " + p.string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("mas") != std::string::npos);
  CHECK(r.output.find("mass") != std::string::npos);
  CHECK(r.output.find(p.string() + ":") != std::string::npos);
}

TEST_CASE("cli: a non-physical body is rejected with its line") {
  std::ifstream in(kScene);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("mass = 15.0"), 11, "mass = -1.0");
  const auto p = temp_scene("negative_mass.toml", text);
  const Result r = run_cli("solve " + p.string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(p.string() + ":") != std::string::npos);
}

TEST_CASE("cli: a solver failure exits 1 and says why") {
  const auto out = std::filesystem::temp_directory_path() / "rigidae_cli_tests" / "fail";
  const Result r = run_cli("solve " + kScene + " --max-steps 20 --out " + out.string());
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("too much work") != std::string::npos);
  CHECK(std::filesystem::exists(out / "summary.json"));
}

TEST_CASE("cli: compare writes the table, the CSV and a folder per combination") {
  const auto out = std::filesystem::temp_directory_path() / "rigidae_cli_tests" / "compare";
  std::filesystem::remove_all(out);
  const Result r = run_cli("compare " + kScene + " --t-end 0.05 --repeat 2 --only 'quaternion/*/ggl,euler/*/*,projection' "
                           "--skip linear --reference tight --out " + out.string());
  CAPTURE(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("reference: quaternion/euler/ggl") != std::string::npos);
  for (const char* dir : {"quaternion-lagrange-ggl", "quaternion-euler-ggl", "euler-lagrange-any", "euler-euler-any",
                          "quaternion-euler-projection", "reference", "reference-check"})
    CHECK(std::filesystem::exists(out / dir / "summary.json"));
  CHECK_FALSE(std::filesystem::exists(out / "linear-euler-projection"));
  std::ifstream csv(out / "compare.csv");
  std::string line;
  long rows = -2;  // units and header
  while (std::getline(csv, line)) ++rows;
  CHECK(rows == 6);
  CHECK(std::filesystem::exists(out / "compare.txt"));
}

TEST_CASE("cli: compare rejects options that pick one combination, and empty selections") {
  Result r = run_cli("compare " + kScene + " --scheme ggl");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--only") != std::string::npos);
  r = run_cli("compare " + kScene + " --only nothing_matches");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("no combination") != std::string::npos);
  r = run_cli("compare " + kScene + " --repeat 0");
  CHECK(r.exit_code == 2);
}

TEST_CASE("cli: scheme parameters are options with checked values") {
  const auto out = std::filesystem::temp_directory_path() / "rigidae_cli_tests" / "baumgarte";
  Result r = run_cli("solve " + kScene + " --scheme baumgarte --coordinates linear --equations lagrange --baumgarte-a 50 "
                     "--baumgarte-b 40 --t-end 0.05 --out " + out.string());
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("a = 50 1/s, b = 40 1/s") != std::string::npos);
  r = run_cli("solve " + kScene + " --baumgarte-a -1");
  CHECK(r.exit_code == 2);
  r = run_cli("solve " + kScene + " --projection-threshold 0");
  CHECK(r.exit_code == 2);
}

TEST_CASE("rigidae study: list prints one command per run, run needs a slice, collect reports what is missing") {
  const auto dir = std::filesystem::temp_directory_path() / "rigidae_cli_tests" / "study";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "s.toml") << "schema_version = 1\nname = \"s\"\nscenes = [\"" << RIGIDAE_SOURCE_DIR
                                << "/problems/free_body.toml\"]\n[grid]\ncombinations = [\"euler/euler/any\", "
                                   "\"quaternion/euler/index1\"]\nrtol = [1e-4, 1e-5]\n[timing]\nwarmups = 0\nrepeats = 1\n";
  const std::string study = (dir / "s.toml").string() + " --out " + (dir / "out").string();
  const Result list = run_cli("study list " + study);
  CHECK(list.exit_code == 0);
  int commands = 0;
  for (std::size_t at = list.output.find(" study run "); at != std::string::npos;
       at = list.output.find(" study run ", at + 1))
    ++commands;
  CHECK(commands == 4);
  CHECK(list.output.find("--run free_body/euler-euler-any/rtol_0.0001_atol_0.0001") != std::string::npos);

  const Result no_slice = run_cli("study run " + study);
  CHECK(no_slice.exit_code == 2);
  CHECK(no_slice.output.find("needs --shard i/N, --run ID") != std::string::npos);

  CHECK(run_cli("study run " + study + " --shard 0/2 --quiet").exit_code == 0);
  const Result partial = run_cli("study collect " + study + " --no-plot --quiet");
  CHECK(partial.exit_code == 1);
  CHECK(partial.output.find("2 runs of the study have no complete folder yet") != std::string::npos);
  CHECK(run_cli("study run " + study + " --shard 1/2 --quiet").exit_code == 0);
  CHECK(run_cli("study collect " + study + " --no-plot --quiet").exit_code == 0);
  CHECK(std::filesystem::exists(dir / "out" / "results.csv"));
  CHECK(std::filesystem::exists(dir / "out" / "best.md"));
}

TEST_SUITE_END();
