// rigidae._core: the C++ side of the Python module. Thin: every check and
// message comes from the library (the scene loader, the CLI's option
// parser), runs are the library's solve/compare/study, and the pure-Python
// package (python/rigidae/) turns the results into dicts and numpy arrays.
//
// Integration runs with the GIL released. Ctrl-C during a run: while it runs
// (from the main thread) SIGINT sets g_interrupt_requested, which stops the
// run after the current step exactly as in the CLI; the Python layer then
// raises rigidae.Interrupted (a KeyboardInterrupt) carrying the records.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <limits>
#include <cstring>
#include <fstream>
#include <iterator>
#include <filesystem>
#include <optional>

#include "rigidae/app/command_line.hpp"
#include "rigidae/app/compare.hpp"
#include "rigidae/app/error_estimate.hpp"
#include "rigidae/app/provenance.hpp"
#include "rigidae/app/solve.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/coords/representation.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/model/recorded_parts.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/record/error_control.hpp"
#include "rigidae/record/recorder.hpp"
#include "rigidae/record/run_columns.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/settings/default_integrator.hpp"
#include "rigidae/settings/settings.hpp"
#include "rigidae/so3/rotation.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace rigidae;

namespace {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    if (comma > start) items.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  return items;
}

bool in_main_thread() {
  py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

void on_sigint(int) {
  g_interrupt_signal.store(SIGINT);
  g_interrupt_requested.store(true);
}

// While alive: SIGINT stops a run between steps instead of waiting for the
// GIL (Python's own handler only runs between bytecodes). Signal handlers
// can only be changed from the main thread; elsewhere Ctrl-C is Python's.
class InterruptScope {
 public:
  InterruptScope() {
    g_interrupt_requested.store(false);
    g_interrupt_signal.store(0);
    if (!in_main_thread()) return;
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    installed_ = sigaction(SIGINT, &sa, &previous_) == 0;
  }
  ~InterruptScope() {
    if (installed_) sigaction(SIGINT, &previous_, nullptr);
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  bool interrupted() const { return g_interrupt_requested.load(); }

 private:
  struct sigaction previous_ {};
  bool installed_ = false;
};

[[noreturn]] void raise_keyboard_interrupt() {
  PyErr_SetNone(PyExc_KeyboardInterrupt);
  throw py::error_already_set();
}

// rows x cols doubles, copied into a new numpy array.
py::array_t<double> table(const std::vector<double>& flat, std::size_t cols) {
  const std::size_t rows = cols ? flat.size() / cols : 0;
  py::array_t<double> a(std::vector<py::ssize_t>{static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  if (!flat.empty()) std::memcpy(a.mutable_data(), flat.data(), flat.size() * sizeof(double));
  return a;
}

// The scene with a command's options applied as its command line applies
// them (cli::parse_arguments and cli::scene_from: same checks, same words).
Scene with_options(const Scene& scene, const std::string& command, const std::vector<std::string>& args) {
  const cli::CommandLine cl = cli::parse_arguments(args, cli::command_info(command));
  if (!cl.positional.empty())
    throw InputError(fmt::format("unexpected argument '{}': give options as keywords", cl.positional.front()));
  Scene s = scene;
  for (const auto& [setting, value] : cl.options)
    if (setting->set && !setting->scene_key.empty()) setting->set(s, value);
  settings::resolve_integrator(s);  // as scene_from: the default rule reads the final settings
  if (const auto p = settings::cross_problem(s))
    throw InputError(fmt::format("{} = {}", settings::scene_setting(p->scene_key).label(), p->message));
  return s;
}

// The scene overrides of a command (settings with an option and a place in
// the scene), for the Python keywords and their docstrings.
py::list scene_options(const std::string& command) {
  const cli::CommandInfo& info = cli::command_info(command);
  py::list out;
  for (const settings::Setting& s : settings::all()) {
    if (s.option.empty() || !(s.commands & info.bit)) continue;
    py::dict d;
    d["option"] = std::string(s.option);
    d["scene_key"] = std::string(s.scene_key);
    d["flag"] = s.flag_value.has_value();
    d["metavar"] = std::string(s.metavar);
    d["unit"] = std::string(s.unit);
    d["domain"] = settings::domain_text(s);
    d["default"] = settings::default_text(s);
    d["help"] = std::string(s.help);
    out.append(d);
  }
  return out;
}

// Which rows a run keeps in memory: record = steps (both), grid, none.
MemoryRows memory_rows(const std::string& record) {
  if (record != "steps" && record != "grid" && record != "none")
    throw InputError(fmt::format("record='{}' is not valid (valid: 'steps', 'grid' or 'none')", record));
  MemoryRows rows;
  rows.keep_steps = record == "steps";
  rows.keep_grid = record != "none";
  return rows;
}

// An event field events.csv leaves empty: NaN.
double or_nan(double x, bool given) { return given ? x : std::numeric_limits<double>::quiet_NaN(); }

// The accuracy verdict `rigidae solve` gives without a companion run: the
// closed form's error (app/error_estimate.hpp) on the output grid kept in
// memory, as summary.json's "error_estimate" and warnings (also in
// out/summary.json when the run wrote one).
void add_verdict(const Scene& scene, SolveOutcome& o, const MemoryRows& memory, const std::optional<std::string>& out) {
  if (o.run.status != RunStatus::Success || o.summary.empty()) return;
  ErrorEstimate e;
  if (!memory.keep_grid || memory.grid_columns.empty()) {
    e.not_estimated = "record='none' keeps no output grid to compare";
    judge(e, scene);
  } else {
    // The grid as trajectory.csv's text (the shortest text of each double reads back to it).
    std::string text = fmt::format("{}\n", fmt::join(memory.grid_columns, ","));
    const std::size_t width = memory.grid_columns.size();
    for (std::size_t k = 0; k < memory.grid.size(); k += width)
      text += fmt::format("{}\n", fmt::join(memory.grid.begin() + static_cast<long>(k),
                                            memory.grid.begin() + static_cast<long>(k + width), ","));
    e = closed_form_verdict(scene, read_trajectory_text(text, "the run's output grid"));
    if (!e.estimated())
      e.not_estimated = "the scene has no closed form and no companion run was made (rigidae solve --error-estimate "
                        "runs one at rtol/100)";
  }
  apply_verdict(o, e);
  o.summary = with_error_estimate(o.summary, e);
  if (out) write_file_atomically(fs::path(*out) / "summary.json", o.summary);
}

// A one-body run held in memory (and written to `out` when given): the CLI's
// run (app/solve.hpp, run_scene) with the rows kept by the recorder.
py::dict solve(const Scene& scene, const std::string& record, const std::optional<std::string>& out) {
  MemoryRows memory = memory_rows(record);
  SolveOutcome o;
  bool interrupted = false;
  {
    InterruptScope interrupt;
    py::gil_scoped_release release;
    o = run_scene(scene, out ? fs::path(*out) : fs::path(), &memory);
    interrupted = interrupt.interrupted();
  }
  add_verdict(scene, o, memory, out);
  // The events a single body's events.csv holds, its fields empty (NaN) where the file leaves them so.
  py::list events;
  for (const EventNote& e : memory.events) {
    const bool chart = e.what == "chart_switch";
    if (!chart && e.what != "projection") continue;
    events.append(py::make_tuple(e.t, e.what, chart ? e.from : "", chart ? e.to : "", or_nan(e.margin, chart),
                                 or_nan(e.drift_position, !chart), or_nan(e.drift_velocity, !chart)));
  }
  py::dict r;
  r["summary"] = o.summary;
  r["status"] = to_string(o.run.status);
  r["message"] = o.run.message;
  r["interrupted"] = interrupted;
  r["record"] = record;
  r["step_columns"] = memory.step_columns;
  r["grid_columns"] = memory.grid_columns;
  r["integer_columns"] = memory.integer_columns;
  r["steps"] = table(memory.steps, memory.step_columns.size());
  r["grid"] = table(memory.grid, memory.grid_columns.size());
  r["charts"] = memory.charts;
  r["events"] = events;
  r["out"] = out ? py::cast(*out) : py::object(py::none());
  return r;
}

// A multibody run held in memory (and written to `out` when given): the same
// run, per step the columns of steps.csv and on the output grid those of
// trajectory.csv, with the names and units read off the assembled system.
py::dict solve_multibody(const Scene& scene, const std::string& record, const std::optional<std::string>& out) {
  MemoryRows memory = memory_rows(record);
  std::vector<std::string> units{"s"}, bodies, joints;
  const auto names = [&](const multibody::MultibodyProblem& problem) -> StepSink* {
    for (const std::string& u : problem.output_units(recorded_parts(problem.spec(), false))) units.push_back(u);
    for (const auto& b : problem.bodies()) bodies.push_back(b.name);
    for (const auto& j : problem.spec().joints) joints.push_back(j.name);
    return nullptr;
  };
  SolveOutcome o;
  bool interrupted = false;
  {
    InterruptScope interrupt;
    py::gil_scoped_release release;
    o = run_scene(scene, out ? fs::path(*out) : fs::path(), &memory, names);
    interrupted = interrupt.interrupted();
  }
  add_verdict(scene, o, memory, out);
  py::list events;
  for (const EventNote& e : memory.events)
    events.append(py::make_tuple(e.t, e.what, e.body, e.from, e.to, e.margin, e.drift_position, e.drift_velocity));
  py::dict r;
  r["status"] = to_string(o.run.status);
  r["message"] = o.run.message;
  r["interrupted"] = interrupted;
  r["bodies"] = bodies;
  r["joints"] = joints;
  r["record"] = record;
  r["step_columns"] = memory.step_columns;
  r["steps"] = table(memory.steps, memory.step_columns.size());
  r["grid_columns"] = memory.grid_columns;
  r["grid_units"] = units;
  r["grid"] = table(memory.grid, memory.grid_columns.size());
  r["events"] = events;
  r["out"] = out ? py::cast(*out) : py::object(py::none());
  r["summary"] = o.summary;  // summary.json's text
  return r;
}

py::dict compare(const Scene& base, const std::vector<std::string>& args, const std::string& out,
                 const std::function<void(const std::string&)>& progress) {
  const cli::CommandLine cl = cli::parse_arguments(args, cli::command_info("compare"));
  const Scene scene = with_options(base, "compare", args);
  CompareOptions opt;
  opt.out = out;
  if (const auto* n = cl.last("--repeat")) opt.repeat = static_cast<int>(std::get<long long>(*n));
  if (cl.has("--only")) opt.only = split_list(cl.text("--only"));
  if (cl.has("--skip")) opt.skip = split_list(cl.text("--skip"));
  if (const auto* x = cl.last("--reference-rtol")) opt.reference_rtol = std::get<double>(*x);
  opt.error_estimate = !cl.has("--no-error-estimate");
  std::error_code ec;
  fs::create_directories(opt.out, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create output folder: {}", out, ec.message()));
  CompareReport report;
  {
    InterruptScope interrupt;
    {
      py::gil_scoped_release release;
      report = compare_scene(scene, opt, [&](const std::string& line) {
        if (!progress) return;
        py::gil_scoped_acquire acquire;
        progress(line);
      });
      write_compare_outputs(report, opt.out);
    }
    if (interrupt.interrupted()) raise_keyboard_interrupt();
  }
  py::dict r;
  r["table"] = format_compare_table(report);
  r["reference_ok"] = report.reference.ok;
  r["reference"] = report.reference.describe();
  r["reference_message"] = report.reference.message;
  return r;
}

bool run_study_slice(const StudySpec& spec, const std::string& out, const std::optional<std::string>& shard,
                     const std::optional<std::string>& run_id,
                     const std::function<void(int, int, int, int, const std::string&)>& progress) {
  const std::vector<StudyRun> plan = plan_study(spec);
  std::vector<StudyRun> todo = plan;
  if (run_id) {
    todo.clear();
    for (const StudyRun& r : plan)
      if (r.id(spec) == *run_id) todo.push_back(r);
    if (todo.empty()) throw InputError(fmt::format("run='{}': no such run in {}", *run_id, spec.source));
  } else if (shard) {
    todo = select_shard(plan, parse_shard(*shard));
  }
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the study folder: {}", out, ec.message()));
  StudyRunOptions opt;
  opt.out = out;
  opt.progress = [&](const StudyProgress& p) {
    if (!progress) return;
    py::gil_scoped_acquire acquire;
    progress(p.done, p.skipped, p.failed, p.total, p.last);
  };
  InterruptScope interrupt;
  bool complete = false;
  {
    py::gil_scoped_release release;
    complete = run_study(spec, todo, opt);
  }
  if (!complete || interrupt.interrupted()) raise_keyboard_interrupt();
  return complete;
}

py::dict exact_solution(const Scene& scene, const std::vector<double>& times) {
  std::string why;
  const std::unique_ptr<exact::ExactSolution> s = exact::find_exact_solution(scene, &why);
  if (!s) throw InputError(fmt::format("{}: no closed-form solution: {}", scene.source, why));
  std::vector<double> rows;
  rows.reserve(times.size() * 8);
  Vec4 last(1, 0, 0, 0);
  for (double t : times) {
    const exact::RotationState x = s->at(t);
    Vec4 q = so3::matrix_to_quaternion(x.R_WB);
    if (q.dot(last) < 0) q = -q;  // continuous in time, as the recorded runs are
    last = q;
    rows.push_back(t);
    rows.insert(rows.end(), q.data(), q.data() + 4);
    rows.insert(rows.end(), x.omega_B.data(), x.omega_B.data() + 3);
  }
  py::dict r;
  r["name"] = s->name();
  r["accuracy_rad"] = s->accuracy();
  r["columns"] = std::vector<std::string>{"t", "qw", "qx", "qy", "qz", "omega_x", "omega_y", "omega_z"};
  r["rows"] = table(rows, 8);
  return r;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "rigidae's C++ core (use the package rigidae, not this module)";
  m.attr("version") = RIGIDAE_VERSION;

  // The exception classes live in the pure-Python layer (rigidae/errors.py),
  // which adds the parsed position and suggestion.
  py::module_ errors = py::module_::import("rigidae.errors");
  // Handles kept for the process's lifetime (a static py::object would be
  // destroyed after the interpreter).
  static const py::handle input_error = py::object(errors.attr("InputError")).release();
  static const py::handle solver_error = py::object(errors.attr("SolverError")).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const SolverError& e) {
      PyErr_SetString(solver_error.ptr(), e.what());
    }
  });

  py::class_<Scene>(m, "Scene")
      .def_readonly("name", &Scene::name)
      .def_readonly("source", &Scene::source)
      .def_readonly("description", &Scene::description)
      .def_property_readonly("coordinates", [](const Scene& s) { return to_string(s.formulation.coordinates); })
      .def_property_readonly("equations", [](const Scene& s) { return to_string(s.formulation.equations); })
      .def_property_readonly("scheme", [](const Scene& s) { return s.formulation.scheme; })
      .def_property_readonly("rtol", [](const Scene& s) { return s.solver.rtol; })
      .def_property_readonly("atol", [](const Scene& s) { return s.solver.atol; })
      .def_property_readonly("t_start", [](const Scene& s) { return s.time.start; })
      .def_property_readonly("t_end", [](const Scene& s) { return s.time.end; })
      .def_property_readonly("output_step", [](const Scene& s) { return s.time.output_step; })
      // Whether its runs record the mechanism columns (solve gives a
      // MultibodyRun): the column-set rule of record/run_columns.hpp on the
      // system the scene runs as, not the scene's kind.
      .def_property_readonly("is_multibody",
                             [](const Scene& s) { return !records_one_body_columns(*as_system(s).multibody); })
      .def_property_readonly("run_name", [](const Scene& s) { return default_run_name(s); })
      .def("_with_options", &with_options, py::arg("command"), py::arg("args"));

  m.def("load_scene", &io::load_scene, py::arg("path"));
  m.def("parse_scene", &io::parse_scene, py::arg("text"), py::arg("source_name"));
  m.def("scheme_names", &scheme_names);
  m.def("scene_options", &scene_options, py::arg("command"));
  m.def("units_line", [] { return columns::units_line(); });
  m.def("solve", &solve, py::arg("scene"), py::arg("record"), py::arg("out"));
  m.def("solve_multibody", &solve_multibody, py::arg("scene"), py::arg("record"), py::arg("out"));
  m.def("compare", &compare, py::arg("scene"), py::arg("args"), py::arg("out"), py::arg("progress"));
  m.def("exact_solution", &exact_solution, py::arg("scene"), py::arg("times"));

  py::class_<StudySpec>(m, "StudySpec")
      .def_readonly("name", &StudySpec::name)
      .def_readonly("source", &StudySpec::source)
      .def_readonly("description", &StudySpec::description)
      .def("run_ids", [](const StudySpec& spec) {
        std::vector<std::string> ids;
        for (const StudyRun& r : plan_study(spec)) ids.push_back(r.id(spec));
        return ids;
      });
  m.def("load_study", &load_study, py::arg("path"));
  m.def("run_study", &run_study_slice, py::arg("spec"), py::arg("out"), py::arg("shard"), py::arg("run"),
        py::arg("progress"));
  m.def("collect_study", [](const StudySpec& spec, const std::string& out) {
    std::vector<std::string> missing;
    std::string best = collect_study(spec, out, &missing);
    return py::make_tuple(best, missing);
  });
}
