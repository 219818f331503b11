// Study files: TOML, schema_version 1 (docs/studies.md).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../io/parse_hints.hpp"
#include "../io/toml_reader.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/settings/settings.hpp"

namespace rigidae {

namespace {

using io::SectionKeys;
using io::TomlReader;

constexpr std::array<std::string_view, 9> kRootKeys{"schema_version", "name",           "description",
                                                    "scenes",         "reference",      "reference_rtol",
                                                    "targets",        "grid",           "timing"};
constexpr std::array<std::string_view, 6> kGridKeys{"combinations", "skip", "rtol", "atol", "atol_ratio",
                                                   "integrators"};
constexpr std::array<std::string_view, 2> kTimingKeys{"warmups", "repeats"};
const std::array<SectionKeys, 3> kSchema{{{"", kRootKeys}, {"grid", kGridKeys}, {"timing", kTimingKeys}}};

const toml::array& array_of(const TomlReader& r, const toml::node& n, std::string_view name, std::string_view what) {
  const toml::array* a = n.as_array();
  if (!a) r.fail(n, fmt::format("'{}' must be an array of {}, not {}", name, what, io::type_name(n)));
  if (a->empty()) r.fail(n, fmt::format("'{}' must not be empty", name));
  return *a;
}

std::vector<std::string> strings(const TomlReader& r, const toml::node& n, std::string_view name) {
  std::vector<std::string> v;
  const toml::array& a = array_of(r, n, name, "strings");
  for (std::size_t i = 0; i < a.size(); ++i) v.push_back(r.string(*a.get(i), fmt::format("{}[{}]", name, i)));
  return v;
}

// A value of the table of settings (rigidae/settings) read from a study
// file: checked by settings::problem, so a study refuses what a scene file
// and the command line refuse, in the same words.
settings::Value setting_value(const TomlReader& r, const toml::node& n, const settings::Setting& s,
                              std::string_view name) {
  settings::Value v;
  switch (s.kind) {
    case settings::Kind::Real: v = r.number(n, name); break;
    case settings::Kind::Integer: v = r.integer(n, name); break;
    case settings::Kind::Boolean: v = r.boolean(n, name); break;
    case settings::Kind::Choice:
    case settings::Kind::Text: v = r.string(n, name); break;
  }
  const std::string why = settings::problem(s, v);
  if (!why.empty()) r.fail(n, fmt::format("'{}' = {}", name, why));
  return v;
}

// Values of setting `s` (solver.rtol, solver.atol), distinct.
std::vector<double> tolerances(const TomlReader& r, const toml::node& n, std::string_view name,
                               const settings::Setting& s) {
  std::vector<double> v;
  const toml::array& a = array_of(r, n, name, fmt::format("numbers, {}", settings::domain_text(s)));
  for (std::size_t i = 0; i < a.size(); ++i) {
    const toml::node& e = *a.get(i);
    const std::string item = fmt::format("{}[{}]", name, i);
    const double x = std::get<double>(setting_value(r, e, s, item));
    if (std::find(v.begin(), v.end(), x) != v.end()) r.fail(e, fmt::format("'{}' = {:g} is listed twice", item, x));
    v.push_back(x);
  }
  return v;
}

// Error targets in rad: numbers in (0, 1), distinct.
std::vector<double> targets(const TomlReader& r, const toml::node& n, std::string_view name) {
  std::vector<double> v;
  const toml::array& a = array_of(r, n, name, "numbers in (0, 1)");
  for (std::size_t i = 0; i < a.size(); ++i) {
    const toml::node& e = *a.get(i);
    const std::string item = fmt::format("{}[{}]", name, i);
    const double x = r.number(e, item);
    if (!(x > 0.0 && x < 1.0)) r.fail(e, fmt::format("'{}' = {} must lie in (0, 1) (an angle in rad)", item, x));
    if (std::find(v.begin(), v.end(), x) != v.end()) r.fail(e, fmt::format("'{}' = {:g} is listed twice", item, x));
    v.push_back(x);
  }
  return v;
}

// Names that become folder names and CSV cells unquoted.
bool folder_name(const std::string& s) {
  return !s.empty() && s.size() <= 100 && s.front() != '.' && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

void check_patterns(const TomlReader& r, const toml::node& n, const std::vector<std::string>& patterns,
                    std::string_view name, const StudySpec& spec) {
  std::vector<Combination> all;
  for (const Scene& scene : spec.scenes)
    for (const Combination& c : combinations_for(scene, spec.integrators, spec.source)) all.push_back(c);
  for (std::size_t i = 0; i < patterns.size(); ++i) {
    if (patterns[i] == "all") continue;
    if (std::none_of(all.begin(), all.end(), [&](const Combination& c) { return matches(c, patterns[i], "*"); }))
      r.fail(*n.as_array()->get(i),
             fmt::format("'{}[{}]' = \"{}\" matches no combination (patterns: a glob over "
                         "coordinates/equations/scheme such as \"quaternion/*/ggl\", a word such as \"ggl\", "
                         "either followed by @INTEGRATOR (one of grid.integrators), or \"all\")",
                         name, i, patterns[i]));
  }
}

StudySpec read_study(const TomlReader& r, const toml::table& root) {
  StudySpec spec;
  spec.source = r.file();
  if (!root.get("schema_version")) r.check_keys(root, "", kRootKeys, kSchema);
  const toml::node& ver = r.required(root, "", "schema_version", "schema_version = 1");
  if (r.integer(ver, "schema_version") != 1)
    r.fail(ver, "unsupported schema_version; this version of rigidae reads study files with schema_version = 1");
  r.check_keys(root, "", kRootKeys, kSchema);

  spec.name = std::filesystem::path(r.file()).stem().string();
  if (const toml::node* n = root.get("name")) {
    spec.name = r.string(*n, "name");
    if (!folder_name(spec.name)) r.fail(*n, "'name' must be a folder name: letters, digits, '_', '-', '.', not "
                                            "starting with '.'");
  }
  if (const toml::node* n = root.get("description")) spec.description = r.string(*n, "description");

  const toml::node& scenes = r.required(root, "", "scenes", "scene files, relative to the study file");
  const std::vector<std::string> files = strings(r, scenes, "scenes");
  const std::filesystem::path base = std::filesystem::path(r.file()).parent_path();
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::filesystem::path p = base / files[i];
    const toml::node& e = *scenes.as_array()->get(i);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec))
      r.fail(e, fmt::format("scene file '{}' (scenes[{}], relative to the study file) does not exist", p.string(), i));
    spec.scenes.push_back(io::load_scene(p.lexically_normal().string()));
    if (!folder_name(spec.scenes.back().name))
      r.fail(e, fmt::format("scene '{}' is named \"{}\"; a study names run folders and CSV rows by scene, so "
                            "scene names must be letters, digits, '_', '-' or '.' (set 'name' in the scene file)",
                            p.string(), io::printable(spec.scenes.back().name)));
    for (std::size_t k = 0; k + 1 < spec.scenes.size(); ++k)
      if (spec.scenes[k].name == spec.scenes.back().name)
        r.fail(e, fmt::format("two scenes are named '{}': run folders are named by scene, so names must differ",
                              spec.scenes.back().name));
  }

  if (const toml::node* n = root.get("reference")) {
    spec.reference = std::get<std::string>(setting_value(r, *n, settings::study_setting("reference"), "reference"));
    for (const Scene& scene : spec.scenes) {
      std::string why;
      if (spec.reference == "exact" && !exact::find_exact_solution(scene, &why))
        r.fail(*n, fmt::format("'reference' = \"exact\" but scene '{}' has no closed-form solution: {} (use "
                               "\"auto\" or \"tight\")",
                               scene.name, why));
    }
  }
  if (const toml::node* n = root.get("targets")) spec.targets = targets(r, *n, "targets");

  const toml::table& grid = r.required_table(root, "", "grid");
  r.check_keys(grid, "grid", kGridKeys, kSchema);
  if (const toml::node* n = grid.get("integrators")) {
    const std::vector<std::string> names = strings(r, *n, "grid.integrators");
    spec.integrators.clear();
    for (std::size_t i = 0; i < names.size(); ++i) {
      const toml::node& e = *n->as_array()->get(i);
      const std::string item = fmt::format("grid.integrators[{}]", i);
      IntegratorChoice c;
      try {
        c = parse_integrator_choice(names[i], SolverSettings{}.erk_method, "");
      } catch (const InputError&) {
        r.fail(e, fmt::format("'{}' = \"{}\" is not an integrator; valid: {}", item, names[i],
                              integrator_choices_text()));
      }
      for (const IntegratorChoice& seen : spec.integrators)
        if (seen.label() == c.label()) r.fail(e, fmt::format("'{}' = \"{}\" is listed twice", item, c.label()));
      spec.integrators.push_back(c);
    }
  }
  if (const toml::node* n = grid.get("combinations")) {
    spec.only = strings(r, *n, "grid.combinations");
    check_patterns(r, *n, spec.only, "grid.combinations", spec);
    if (std::find(spec.only.begin(), spec.only.end(), "all") != spec.only.end()) spec.only.clear();
  }
  if (const toml::node* n = grid.get("skip")) {
    spec.skip = strings(r, *n, "grid.skip");
    check_patterns(r, *n, spec.skip, "grid.skip", spec);
  }
  const settings::Setting& rtol = settings::scene_setting("solver.rtol");
  spec.rtols = tolerances(r, r.required(grid, "grid", "rtol", "relative tolerances, " + settings::domain_text(rtol)),
                          "grid.rtol", rtol);
  if (plan_study(spec).empty())
    r.fail(grid.source(), "[grid] combinations and skip leave no combination to run (see rigidae compare --help "
                          "for the patterns)");
  if (const toml::node* n = root.get("reference_rtol")) {
    const double x = std::get<double>(setting_value(r, *n, settings::study_setting("reference_rtol"), "reference_rtol"));
    const double smallest = *std::min_element(spec.rtols.begin(), spec.rtols.end());
    if (x > smallest)
      r.fail(*n, fmt::format("'reference_rtol' = {} must be <= {:g}, the smallest grid.rtol (no looser than the "
                             "tightest run)",
                             x, smallest));
    spec.reference_rtol = x;
  }
  if (const toml::node* n = grid.get("atol")) {
    if (n->is_string()) {
      if (r.string(*n, "grid.atol") != "rtol")
        r.fail(*n, "'grid.atol' must be \"rtol\" (tied: atol = atol_ratio * rtol) or a number > 0");
    } else {
      spec.atol_tied = false;
      spec.atol = std::get<double>(setting_value(r, *n, settings::scene_setting("solver.atol"), "grid.atol"));
    }
  }
  if (const toml::node* n = grid.get("atol_ratio")) {
    if (!spec.atol_tied) r.fail(*n, "'grid.atol_ratio' applies only with atol = \"rtol\"");
    spec.atol_ratio = r.number(*n, "grid.atol_ratio");
    if (!(spec.atol_ratio > 0.0)) r.fail(*n, fmt::format("'grid.atol_ratio' = {} must be > 0", spec.atol_ratio));
  }

  if (const toml::table* t = r.optional_table(root, "", "timing")) {
    r.check_keys(*t, "timing", kTimingKeys, kSchema);
    auto count = [&](const char* key, int& into) {
      const std::string name = fmt::format("timing.{}", key);
      if (const toml::node* n = t->get(key))
        into = static_cast<int>(std::get<long long>(setting_value(r, *n, settings::study_setting(name), name)));
    };
    count("warmups", spec.warmups);
    count("repeats", spec.repeats);
  }
  return spec;
}

}  // namespace

StudySpec load_study(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  if (!in || std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: error: cannot read study file '{}'", path, path));
  std::ostringstream buf;
  buf << in.rdbuf();
  const TomlReader reader(path);
  const std::string text = buf.str();
  toml::table root;
  try {
    root = toml::parse(text, std::string_view(path));
  } catch (const toml::parse_error& e) {
    reader.fail(e.source(), io::explain_parse_error(text, e));
  }
  return read_study(reader, root);
}

}  // namespace rigidae
