// The table of settings and the command line built on it: a setting given in
// a scene file and on the command line gives the same value and, when out of
// range, the same message; every command has --help; --x=v is --x v; misspelt
// options, values and subcommands get a suggestion.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigidae/app/command_line.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/settings/settings.hpp"

TEST_SUITE_BEGIN("system");

namespace fs = std::filesystem;
using rigidae::InputError;
using rigidae::Scene;
using rigidae::test::run_cli;
namespace settings = rigidae::settings;

namespace {

const std::string kHeavyTop = std::string(RIGIDAE_SOURCE_DIR) + "/problems/heavy_top.toml";

// A minimal valid scene with `key = value` added in its table.
std::string scene_with(std::string_view key, const std::string& value) {
  std::map<std::string, std::vector<std::string>> tables{
      {"body", {"mass = 2.0", "inertia_principal = [2.0, 3.0, 4.0]"}},
      {"initial", {"quaternion = [1.0, 0.0, 0.0, 0.0]", "angular_velocity = [0.0, 0.0, 1.0]"}},
      {"time", {"end = 1.0"}}};
  std::string root = "schema_version = 1\n";
  const std::size_t dot = key.rfind('.');
  if (dot == std::string_view::npos) {
    root += std::string(key) + " = " + value + "\n";
  } else {
    auto& lines = tables[std::string(key.substr(0, dot))];
    const std::string leaf(key.substr(dot + 1));
    std::erase_if(lines, [&](const std::string& l) { return l.rfind(leaf + " =", 0) == 0; });
    lines.push_back(leaf + " = " + value);
  }
  for (const auto& [table, lines] : tables) {
    root += "[" + table + "]\n";
    for (const auto& l : lines) root += l + "\n";
  }
  return root;
}

std::string scene_error(const std::string& text) {
  try {
    rigidae::io::parse_scene(text, "t.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string cli_error(const std::vector<std::string>& args, std::string_view command = "solve") {
  try {
    rigidae::cli::parse_arguments(args, rigidae::cli::command_info(command));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The scene loaded from `text` with the command line `args` applied, as `solve` does.
Scene scene_with_options(const std::string& text, const std::vector<std::string>& args) {
  Scene scene = rigidae::io::parse_scene(text, "t.toml");
  const auto cl = rigidae::cli::parse_arguments(args, rigidae::cli::command_info("solve"));
  for (const auto& [s, v] : cl.options)
    if (s->set) s->set(scene, v);
  return scene;
}

// A value inside the setting's domain, as TOML and as a command-line word.
struct Sample {
  std::string toml, word;
};
Sample valid_sample(const settings::Setting& s) {
  switch (s.kind) {
    case settings::Kind::Real:
      if (s.max && s.max->value < 0.5) {  // a small range (solver.min_step_fraction): half its top
        const std::string half = fmt::format("{:g}", s.max->value / 2);
        return {half, half};
      }
      return {"0.5", "0.5"};
    case settings::Kind::Integer:
      return {"2", "2"};
    case settings::Kind::Choice: {
      const std::string w = s.choices().back();
      return {"\"" + w + "\"", w};
    }
    case settings::Kind::Boolean:
      return {"false", "false"};
    default:
      return {"\"x\"", "x"};
  }
}

// A number just outside the range (or the excluded bound itself).
std::optional<double> outside(const settings::Setting& s) {
  if (s.max) return s.max->inclusive ? s.max->value + 1 : s.max->value;
  if (s.min) return s.min->inclusive ? s.min->value - 1 : s.min->value;
  return std::nullopt;
}

std::string after(const std::string& text, const std::string& marker) {
  const std::size_t at = text.find(marker);
  return at == std::string::npos ? "<" + marker + " not in: " + text + ">" : text.substr(at + marker.size());
}

}  // namespace

TEST_CASE("settings: every setting given in a scene file and on the command line gives the same value") {
  int checked = 0;
  for (const settings::Setting& s : settings::all()) {
    if (s.scene_key.empty() || s.option.empty() || !s.set || !(s.commands & settings::kSolve)) continue;
    CAPTURE(std::string(s.scene_key));
    const Sample v = valid_sample(s);
    const std::string base = scene_with("solver.max_order", "5");
    const Scene from_file = rigidae::io::parse_scene(scene_with(s.scene_key, v.toml), "t.toml");
    const bool flag = s.flag_value.has_value();
    const Scene from_cli = scene_with_options(base, flag ? std::vector<std::string>{std::string(s.option)}
                                                         : std::vector<std::string>{std::string(s.option), v.word});
    CHECK(settings::to_text(s.get(from_file)) == settings::to_text(s.get(from_cli)));
    // ... and differs from the default, so the value did arrive.
    CHECK(settings::to_text(s.get(from_file)) != settings::to_text(s.get(rigidae::io::parse_scene(base, "t.toml"))));
    if (!flag) {
      const Scene joined = scene_with_options(base, {std::string(s.option) + "=" + v.word});
      CHECK(settings::to_text(s.get(joined)) == settings::to_text(s.get(from_cli)));
    }
    ++checked;
  }
  CHECK(checked >= 17);
}

TEST_CASE("settings: a value out of range gets the same message from a scene file and the command line") {
  int checked = 0;
  for (const settings::Setting& s : settings::all()) {
    if (s.scene_key.empty() || s.option.empty() || s.flag_value) continue;
    CAPTURE(std::string(s.scene_key));
    std::string toml, word;
    if (s.kind == settings::Kind::Choice) {
      word = s.choices().front() + "q";  // one letter too many: a suggestion must follow
      toml = "\"" + word + "\"";
    } else if (const auto x = outside(s)) {
      word = toml = s.kind == settings::Kind::Integer ? fmt::format("{}", static_cast<long long>(std::round(*x)))
                                                      : fmt::format("{}", *x);
      if (s.kind == settings::Kind::Real && toml.find_first_of(".e") == std::string::npos) toml += ".0";
    } else {
      continue;
    }
    const std::string file_message = scene_error(scene_with(s.scene_key, toml));
    const std::string cli_message =
        cli_error({std::string(s.option), word}, (s.commands & settings::kSolve) ? "solve" : "compare");
    const std::string common = after(file_message, fmt::format("'{}' = ", s.scene_key));
    CHECK_FALSE(common.empty());
    CHECK(after(cli_message, fmt::format("option {}: ", s.option)) == common);
    if (s.kind == settings::Kind::Choice) CHECK(common.find("did you mean \"" + s.choices().front() + "\"?") != std::string::npos);
    ++checked;
  }
  CHECK(checked >= 15);
}

TEST_CASE("settings: --reference-rtol has the limit and the words of --rtol, and compare refuses it before running") {
  const auto solve = run_cli("solve " + kHeavyTop + " --rtol 1e-16");
  const fs::path out = rigidae::test::fresh_temp_dir("reference_rtol");
  const auto compare = run_cli("compare " + kHeavyTop + " --reference-rtol 1e-16 --out " + (out / "c").string());
  CAPTURE(solve.output);
  CAPTURE(compare.output);
  CHECK(solve.exit_code == 2);
  CHECK(compare.exit_code == 2);
  CHECK(after(solve.output, "option --rtol: ") == after(compare.output, "option --reference-rtol: "));
  CHECK(compare.output.find("1e-16 must lie in [1e-14, 1)") != std::string::npos);
  CHECK_FALSE(fs::exists(out / "c"));  // refused before the reference or any run started
  fs::remove_all(out);
}

TEST_CASE("cli: every command has --help and -h, exit 0, with the table's ranges and defaults") {
  for (const char* args : {"--help", "-h", "solve --help", "solve -h", "compare --help", "compare -h", "study --help",
                           "study list -h", "solve " "problems/nothing.toml --help"}) {
    const auto r = run_cli(args);
    CAPTURE(std::string(args));
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("--quiet") != std::string::npos);
  }
  const auto solve = run_cli("solve --help");
  CHECK(solve.output.find("--rtol X") != std::string::npos);
  CHECK(solve.output.find("1e-14 <= X < 1") != std::string::npos);
  CHECK(solve.output.find("default 1e-08") != std::string::npos);
  CHECK(solve.output.find("scene key solver.rtol") != std::string::npos);
  CHECK(solve.output.find("--t-end T") != std::string::npos);
  CHECK(solve.output.find("-1e+09 <= T <= 1e+09, in s") != std::string::npos);  // the unit of a time
  CHECK(solve.output.find("ggl") != std::string::npos);       // the scheme registry's names
  const auto compare = run_cli("compare --help");
  CHECK(compare.output.find("--reference-rtol X") != std::string::npos);
  CHECK(compare.output.find("--coordinates") == std::string::npos);  // compare runs them all
}

TEST_CASE("cli: --name=value is --name value") {
  const fs::path out = rigidae::test::fresh_temp_dir("equals");
  const auto a = run_cli("solve " + kHeavyTop + " --t-end=0.02 --rtol=1e-6 --coordinates=linear --quiet --out=" +
                         (out / "a").string());
  const auto b = run_cli("solve " + kHeavyTop + " --t-end 0.02 --rtol 1e-6 --coordinates linear --quiet --out " +
                         (out / "b").string());
  CHECK(a.exit_code == 0);
  CHECK(b.exit_code == 0);
  CHECK(rigidae::test::read_file(out / "a" / "steps.csv") == rigidae::test::read_file(out / "b" / "steps.csv"));
  const std::string summary = rigidae::test::read_file(out / "a" / "summary.json");
  CHECK(summary.find("\"coordinates\": \"linear\"") != std::string::npos);
  CHECK(summary.find("\"rtol\": 1e-06") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("cli: misspelt options, values, commands and subcommands get a suggestion") {
  struct Case {
    std::string args, message;
  };
  for (const Case& c : std::vector<Case>{
           {"solve " + kHeavyTop + " --rtl 1e-6", "unknown option '--rtl' for solve; did you mean '--rtol'?"},
           {"solve " + kHeavyTop + " --coordinates quaternoin",
            "option --coordinates: \"quaternoin\" is not valid; did you mean \"quaternion\"?"},
           {"solve " + kHeavyTop + " --scheme=gll", "did you mean \"ggl\"?"},
           {"compare " + kHeavyTop + " --reference tigth", "did you mean \"tight\"?"},
           {"compare " + kHeavyTop + " --scheme ggl", "option --scheme does not apply to compare"},
           {"study lst studies/heavy_top.toml", "unknown study subcommand 'lst'; did you mean 'list'?"},
           {"study colect", "unknown study subcommand 'colect'; did you mean 'collect'?"},
           {"slove " + kHeavyTop, "unknown command 'slove'; did you mean 'solve'?"},
           {"solve " + kHeavyTop + " -x", "unknown option '-x' for solve"},
           {"solve " + kHeavyTop + " --quiet=yes", "option --quiet takes no value"},
           {"solve " + kHeavyTop + " --rtol", "option --rtol needs a value"},
           {"solve " + kHeavyTop + " --max-order 2.5", "option --max-order: 2.5 is not a whole number"},
       }) {
    const auto r = run_cli(c.args);
    CAPTURE(c.args);
    CAPTURE(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(c.message) != std::string::npos);
  }
}

TEST_CASE("settings: a study file refuses what the command line refuses, in the same words") {
  const fs::path dir = rigidae::test::fresh_temp_dir("study_settings");
  auto study_error = [&](const std::string& body) {
    const fs::path file = dir / "s.toml";
    std::ofstream(file) << "schema_version = 1\nscenes = [\"" << kHeavyTop << "\"]\n" << body;
    try {
      rigidae::load_study(file.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(after(study_error("[grid]\nrtol = [1e-6, 1e-16]\n"), "'grid.rtol[1]' = ") ==
        after(cli_error({"--rtol", "1e-16"}), "option --rtol: "));
  CHECK(after(study_error("[grid]\nrtol = [1e-6]\natol = 2.0\n"), "'grid.atol' = ") ==
        after(cli_error({"--atol=2"}), "option --atol: "));
  CHECK(after(study_error("reference_rtol = 1e-16\n[grid]\nrtol = [1e-6]\n"), "'reference_rtol' = ") ==
        after(cli_error({"--reference-rtol", "1e-16"}, "compare"), "option --reference-rtol: "));
  CHECK(after(study_error("reference = \"tigth\"\n[grid]\nrtol = [1e-6]\n"), "'reference' = ") ==
        after(cli_error({"--reference", "tigth"}, "compare"), "option --reference: "));
  CHECK(after(study_error("[grid]\nrtol = [1e-6]\n[timing]\nrepeats = 0\n"), "'timing.repeats' = ") ==
        after(cli_error({"--repeat", "0"}, "compare"), "option --repeat: "));
  fs::remove_all(dir);
}

TEST_SUITE_END();
