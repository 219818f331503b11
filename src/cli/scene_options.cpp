#include "scene_options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/solver/integrators.hpp"

namespace rigidae::cli {

namespace {

constexpr std::array<std::string_view, 19> kValued{
    "--coordinates",  "--equations",        "--scheme",      "--rtol",      "--atol",        "--t-end",
    "--euler-sequence", "--switch-threshold", "--max-steps", "--jacobian",  "--baumgarte-a", "--baumgarte-b",
    "--projection-threshold", "--max-order", "--initial-step", "--output-step", "--linear-solver",
    "--integrator", "--erk-method"};
constexpr std::array<std::string_view, 2> kFlags{"--no-chart-switching", "--project-every-step"};

template <typename T>
T parse_choice(const std::string& opt, const std::string& text, const std::vector<std::pair<std::string, T>>& choices) {
  std::vector<std::string> names;
  for (const auto& [name, value] : choices) {
    if (name == text) return value;
    names.push_back(name);
  }
  throw InputError(fmt::format("option {}: unknown value '{}'; valid values: {}", opt, text, valid_list(names)));
}

double parse_in_open_unit(const std::string& opt, const std::string& text) {
  const double x = parse_number(opt, text);
  if (!(x > 0 && x < 1)) throw InputError(fmt::format("option {}: {} is outside (0, 1)", opt, text));
  return x;
}

}  // namespace

const char* kSceneOptionsHelp = R"(  --rtol X                relative tolerance, 1e-14 <= X < 1
  --atol X                absolute tolerance, 1e-100 <= X < 1
  --t-end T               end time in s (> the scene's start time)
  --output-step X         output grid spacing in s
  --max-steps N           limit on internal IDA steps
  --max-order N           BDF order limit, 1..5
  --initial-step X        first step in s (default: estimated from y'')
  --jacobian exact|central|ida_dq
                          iteration matrix: exact derivatives (default),
                          rigidae's central differences or IDA's forward
                          difference quotients
  --linear-solver dense|klu
                          Newton's linear solver: dense LU (default) or KLU
                          sparse LU (not with --jacobian ida_dq)
  --integrator ida|cvode-adams|cvode-bdf|arkode-erk
                          ida (default): BDF on the DAE, every scheme; the
                          others run the ODE form, schemes index1 (plain
                          ODE) and projection (ODE + projection)
  --erk-method fehlberg78|verner65|dopri5
                          arkode-erk's table: Fehlberg 7(8) (default),
                          Verner 6(5), Dormand-Prince 5(4)
  --euler-sequence SEQ    initial Euler-angle chart: 'auto' or three letters (e.g. zxz)
  --no-chart-switching    stop at the Euler-angle chart's singularity margin
                          instead of switching charts
  --switch-threshold X    chart margin |det B| at which to switch, 0 < X < 1
  --baumgarte-a X         baumgarte damping a in 1/s (default |omega_0|)
  --baumgarte-b X         baumgarte stiffness b in 1/s (default |omega_0|)
  --projection-threshold X
                          projection: project when |Phi| or |dPhi/dt| exceeds X
                          (default 100 atol)
  --project-every-step    projection: project after every step
)";

std::string valid_list(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

double parse_number(const std::string& opt, const std::string& text) {
  try {
    std::size_t used = 0;
    const double x = std::stod(text, &used);
    if (used == text.size() && std::isfinite(x)) return x;
  } catch (const std::exception&) {
  }
  throw InputError(fmt::format("option {}: '{}' is not a finite number", opt, text));
}

long parse_count(const std::string& opt, const std::string& text) {
  const double x = parse_number(opt, text);
  if (!(x >= 1 && x <= 1e15) || x != std::floor(x))
    throw InputError(fmt::format("option {}: {} must be a whole number from 1 to 1e15", opt, text));
  return static_cast<long>(x);
}

bool is_scene_option(const std::string& opt, bool& takes_value) {
  takes_value = std::find(kValued.begin(), kValued.end(), opt) != kValued.end();
  return takes_value || std::find(kFlags.begin(), kFlags.end(), opt) != kFlags.end();
}

void apply_scene_option(Scene& scene, const std::string& opt, const std::string& text) {
  Formulation& form = scene.formulation;
  if (opt == "--coordinates")
    form.coordinates = parse_choice<Coordinates>(opt, text,
                                                 {{"euler", Coordinates::EulerAngles},
                                                  {"quaternion", Coordinates::Quaternion},
                                                  {"linear", Coordinates::Linear}});
  else if (opt == "--equations")
    form.equations = parse_choice<Equations>(opt, text, {{"lagrange", Equations::Lagrange}, {"euler", Equations::Euler}});
  else if (opt == "--scheme") {
    const auto names = scheme_names();
    if (std::find(names.begin(), names.end(), text) == names.end())
      throw InputError(fmt::format("option --scheme: unknown value '{}'; valid values: {}", text, valid_list(names)));
    form.scheme = text;
  } else if (opt == "--rtol") {
    scene.solver.rtol = parse_in_open_unit(opt, text);
    if (scene.solver.rtol < kMinRelativeTolerance)
      throw InputError(fmt::format("option --rtol: {} is below {:g}, where round-off in double precision exceeds "
                                   "the tolerance and the step size collapses",
                                   text, kMinRelativeTolerance));
  } else if (opt == "--atol") {
    scene.solver.atol = parse_in_open_unit(opt, text);
    if (scene.solver.atol < kMinAbsoluteTolerance)
      throw InputError(fmt::format("option --atol: {} is below {:g}, where IDA's weighted norms overflow", text,
                                   kMinAbsoluteTolerance));
  } else if (opt == "--switch-threshold")
    form.euler.switch_threshold = parse_in_open_unit(opt, text);
  else if (opt == "--projection-threshold")
    form.projection.threshold = parse_in_open_unit(opt, text);
  else if (opt == "--project-every-step")
    form.projection.every_step = true;
  else if (opt == "--baumgarte-a" || opt == "--baumgarte-b") {
    const double x = parse_number(opt, text);
    if (!(x >= 0 && x <= 1e8)) throw InputError(fmt::format("option {}: {} must lie in [0, 1e8] (1/s)", opt, text));
    (opt == "--baumgarte-a" ? form.baumgarte.a : form.baumgarte.b) = x;
  } else if (opt == "--t-end") {
    const double x = parse_number(opt, text);
    if (!(x > scene.time.start))
      throw InputError(
          fmt::format("option --t-end: {} must be greater than the scene's start time {}", text, scene.time.start));
    scene.time.end = x;
    scene.time.output_step = std::min(scene.time.output_step, x - scene.time.start);
  } else if (opt == "--output-step") {
    const double x = parse_number(opt, text);
    const double span = scene.time.end - scene.time.start;
    if (!(x > 0 && x <= span) || span / x > 1e8)
      throw InputError(fmt::format("option --output-step: {} must be > 0, <= end - start = {} s and give at most "
                                   "1e8 intervals",
                                   text, span));
    scene.time.output_step = x;
  } else if (opt == "--max-steps")
    scene.solver.max_steps = parse_count(opt, text);
  else if (opt == "--max-order") {
    const double k = parse_number(opt, text);
    if (!(k >= 1 && k <= 5) || k != std::floor(k))
      throw InputError(fmt::format("option --max-order: {} must be a whole number from 1 to 5", text));
    scene.solver.max_order = static_cast<int>(k);
  } else if (opt == "--initial-step") {
    const double x = parse_number(opt, text);
    if (!(x > 0 && x < scene.time.end - scene.time.start))
      throw InputError(fmt::format("option --initial-step: {} must be > 0 and < the time span", text));
    scene.solver.initial_step = x;
  } else if (opt == "--euler-sequence") {
    if (text == "auto")
      form.euler.sequence.reset();
    else {
      try {
        form.euler.sequence = so3::parse_euler_sequence(text, false);
      } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("option --euler-sequence: {} (or 'auto')", e.what()));
      }
    }
  } else if (opt == "--jacobian")
    scene.solver.jacobian =
        parse_choice<std::string>(opt, text, {{"exact", "exact"}, {"central", "central"}, {"ida_dq", "ida_dq"}});
  else if (opt == "--linear-solver")
    scene.solver.linear_solver = parse_choice<std::string>(opt, text, {{"dense", "dense"}, {"klu", "klu"}});
  else if (opt == "--integrator")
    scene.solver.integrator = find_integrator(text, "option --integrator").name;
  else if (opt == "--erk-method")
    scene.solver.erk_method = find_erk_method(text, "option --erk-method").name;
  else if (opt == "--no-chart-switching")
    form.euler.switching = false;
  else
    throw InputError(fmt::format("unknown option '{}'; see rigidae --help", opt));
}

Scene parse_command_line(const std::vector<std::string>& args, const std::string& command,
                         const std::function<bool(const std::string& opt, const NextValue& value)>& own) {
  std::string scene_path;
  std::vector<std::pair<std::string, std::string>> overrides;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const NextValue value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw InputError(fmt::format("option {} needs a value (see rigidae --help)", a));
      return args[++i];
    };
    bool takes_value = false;
    if (own(a, value)) continue;
    if (is_scene_option(a, takes_value)) overrides.emplace_back(a, takes_value ? value() : "");
    else if (a.rfind("--", 0) == 0)
      throw InputError(fmt::format("unknown option '{}' for {}; see rigidae --help", a, command));
    else if (scene_path.empty()) scene_path = a;
    else throw InputError(fmt::format("unexpected argument '{}': {} takes one scene file", a, command));
  }
  if (scene_path.empty())
    throw InputError(fmt::format("{0} needs a scene file: rigidae {0} SCENE.toml", command));
  Scene scene = io::load_scene(scene_path);
  for (const auto& [opt, text] : overrides) apply_scene_option(scene, opt, text);
  // The integrator and the scheme as file and options left them.
  if (command == "solve") check_integrator_scheme(scene.solver.integrator, scene.formulation.scheme, "options");
  // The grid as the options left it (--t-end keeps the scene's output step).
  const TimeGrid& g = scene.time;
  if (std::abs(g.end) > kMaxTimeMagnitude)
    throw InputError(fmt::format("option --t-end: {} s is too large; times must lie within +-{:g} s", g.end,
                                 kMaxTimeMagnitude));
  if ((g.end - g.start) / g.output_step > kMaxOutputIntervals)
    throw InputError(fmt::format("the output step {} s gives {:.3g} output intervals from {} s to {} s; at most {:g} "
                                 "are allowed: give a larger --output-step",
                                 g.output_step, (g.end - g.start) / g.output_step, g.start, g.end,
                                 kMaxOutputIntervals));
  return scene;
}

}  // namespace rigidae::cli
