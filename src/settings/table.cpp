// The table of settings (include/rigidae/settings/settings.hpp): one row per
// value a user can set. Adding a setting is one row here (and, for a scene
// key, its name in the scene loader's key list of its table).
#include <array>
#include <cmath>
#include <string>

#include "rigidae/coords/representation.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/settings/settings.hpp"
#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/solver/integrators.hpp"

// Rows name only the fields they set; the others keep their defaults by design.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace rigidae::settings {

namespace {

constexpr double kInf = INFINITY;
constexpr unsigned kRun = kSolve | kCompare;  // scene overrides

// Value accessors: the variant holds the kind the row declares (checked before set).
double real(const Value& v) { return std::get<double>(v); }
long long whole(const Value& v) { return std::get<long long>(v); }
bool flag(const Value& v) { return std::get<bool>(v); }
const std::string& word(const Value& v) { return std::get<std::string>(v); }

std::vector<std::string> equations_names() { return {"lagrange", "euler"}; }
std::vector<std::string> reference_names() { return {"auto", "exact", "tight"}; }
std::vector<std::string> jacobian_names() { return {"exact", "central", "ida_dq"}; }
std::vector<std::string> linear_solver_names() { return {"auto", "dense", "klu"}; }
std::vector<std::string> record_names() { return {"steps", "grid", "none"}; }
std::vector<std::string> step_format_names() { return {"csv", "npy"}; }
std::vector<std::string> projection_when_names() { return {"threshold", "every_step"}; }
std::vector<std::string> sequence_names() {
  std::vector<std::string> v{"auto"};
  for (const so3::EulerSequence& s : so3::all_euler_sequences()) v.push_back(s.name());
  return v;
}

template <typename T, std::size_t N>
T pick(const std::array<T, N>& values, std::vector<std::string> (*names)(), const std::string& w) {
  const std::vector<std::string> n = names();
  for (std::size_t i = 0; i < N; ++i)
    if (n[i] == w) return values[i];
  return values[0];  // unreachable: `problem` checked the word
}
template <typename T, std::size_t N>
std::string name_of(const std::array<T, N>& values, std::vector<std::string> (*names)(), T v) {
  for (std::size_t i = 0; i < N; ++i)
    if (values[i] == v) return names()[i];
  return names()[0];
}
constexpr std::array<Equations, 2> kEquations{Equations::Lagrange, Equations::Euler};
constexpr std::array<RecordMode, 3> kRecordModes{RecordMode::Steps, RecordMode::Grid, RecordMode::None};
constexpr std::array<StepFormat, 2> kStepFormats{StepFormat::Csv, StepFormat::Npy};
constexpr std::array<ReferenceKind, 3> kReferences{ReferenceKind::Auto, ReferenceKind::Exact, ReferenceKind::Tight};

// The coordinates' help reads the registry's phrases; the table keeps
// string views, so the text lives here for the program's lifetime.
std::string_view coordinates_help_text() {
  static const std::string text = "rotation coordinates: " + coordinates_help();
  return text;
}

constexpr std::string_view kRtolWhy =
    "below 1e-14 round-off in double precision exceeds the tolerance and the step size collapses";

std::vector<Setting> make_table() {
  std::vector<Setting> t;
  auto row = [&](Setting s) { t.push_back(std::move(s)); };

  // --- formulation --------------------------------------------------------
  row({.scene_key = "formulation.coordinates", .option = "--coordinates", .commands = kSolve, .kind = Kind::Choice,
       .choices = coordinates_names,
       .help = coordinates_help_text(),
       .set = [](Scene& s, const Value& v) { s.formulation.coordinates = Coordinates(word(v)); },
       .get = [](const Scene& s) -> Value { return s.formulation.coordinates.name(); }});
  row({.scene_key = "formulation.equations", .option = "--equations", .commands = kSolve, .kind = Kind::Choice,
       .choices = equations_names,
       .help = "Lagrange form (mass matrix in the coordinates) or Euler form (body angular velocity states and "
               "kinematics)",
       .set = [](Scene& s, const Value& v) { s.formulation.equations = pick(kEquations, equations_names, word(v)); },
       .get = [](const Scene& s) -> Value { return name_of(kEquations, equations_names, s.formulation.equations); }});
  row({.scene_key = "formulation.scheme", .option = "--scheme", .commands = kSolve, .kind = Kind::Choice,
       .choices = scheme_names,
       .help = "constraint treatment, a name in the scheme registry (README, \"Choosing a scheme\")",
       .set = [](Scene& s, const Value& v) { s.formulation.scheme = word(v); },
       .get = [](const Scene& s) -> Value { return s.formulation.scheme; }});
  row({.scene_key = "formulation.euler_angles.sequence", .option = "--euler-sequence", .commands = kRun,
       .kind = Kind::Choice, .metavar = "SEQ", .choices = sequence_names, .ignore_case = true,
       .help = "initial Euler-angle chart: 'auto' (the most regular at the start) or three axis letters, intrinsic "
               "(a scene file may say convention = \"extrinsic\")",
       .set = [](Scene& s, const Value& v) {
         if (word(v) == "auto") s.formulation.euler.sequence.reset();
         else s.formulation.euler.sequence = so3::parse_euler_sequence(word(v), false);
       },
       .get = [](const Scene& s) -> Value {
         return s.formulation.euler.sequence ? s.formulation.euler.sequence->name() : std::string("auto");
       }});
  row({.scene_key = "formulation.euler_angles.switching", .option = "--no-chart-switching", .commands = kRun,
       .kind = Kind::Boolean, .flag_value = "false",
       .help = "switch to a more regular Euler-angle chart at the threshold; off (--no-chart-switching): stop there",
       .set = [](Scene& s, const Value& v) { s.formulation.euler.switching = flag(v); },
       .get = [](const Scene& s) -> Value { return s.formulation.euler.switching; }});
  row({.scene_key = "formulation.euler_angles.switch_threshold", .option = "--switch-threshold", .commands = kRun,
       .kind = Kind::Real, .metavar = "X", .min = Bound{0, false}, .max = Bound{1, false},
       .why = "a margin |sin b| or |cos b|",
       .help = "Euler-angle chart margin |det B| at which the chart is switched",
       .set = [](Scene& s, const Value& v) { s.formulation.euler.switch_threshold = real(v); },
       .get = [](const Scene& s) -> Value { return s.formulation.euler.switch_threshold; }});
  row({.scene_key = "formulation.baumgarte.a", .option = "--baumgarte-a", .commands = kRun, .kind = Kind::Real,
       .metavar = "X", .unit = "1/s", .min = Bound{0, true}, .max = Bound{1e8, true},
       .why = "1/s; a rate of the constraint feedback", .default_text = "|omega_0|, at least 1",
       .help = "baumgarte scheme: damping a of the drift",
       .set = [](Scene& s, const Value& v) { s.formulation.baumgarte.a = real(v); },
       .get = [](const Scene& s) -> Value { return baumgarte_gains(s).first; }});
  row({.scene_key = "formulation.baumgarte.b", .option = "--baumgarte-b", .commands = kRun, .kind = Kind::Real,
       .metavar = "X", .unit = "1/s", .min = Bound{0, true}, .max = Bound{1e8, true},
       .why = "1/s; a rate of the constraint feedback", .default_text = "|omega_0|, at least 1",
       .help = "baumgarte scheme: stiffness b of the drift",
       .set = [](Scene& s, const Value& v) { s.formulation.baumgarte.b = real(v); },
       .get = [](const Scene& s) -> Value { return baumgarte_gains(s).second; }});
  row({.scene_key = "formulation.projection.when", .option = "--project-every-step", .commands = kRun,
       .kind = Kind::Choice, .choices = projection_when_names, .flag_value = "every_step",
       .help = "projection scheme: project when the drift passes the threshold, or after every step "
               "(--project-every-step)",
       .set = [](Scene& s, const Value& v) { s.formulation.projection.every_step = word(v) == "every_step"; },
       .get = [](const Scene& s) -> Value {
         return std::string(s.formulation.projection.every_step ? "every_step" : "threshold");
       }});
  row({.scene_key = "formulation.projection.threshold", .option = "--projection-threshold", .commands = kRun,
       .kind = Kind::Real, .metavar = "X", .min = Bound{0, false}, .max = Bound{1, false},
       .why = "a drift |Phi|, e.g. 1e-8", .default_text = "100 atol",
       .help = "projection scheme: project when |Phi| or |dPhi/dt| exceeds this",
       .set = [](Scene& s, const Value& v) { s.formulation.projection.threshold = real(v); },
       .get = [](const Scene& s) -> Value { return projection_threshold(s); }});

  // --- solver -------------------------------------------------------------
  row({.scene_key = "solver.rtol", .option = "--rtol", .commands = kRun, .kind = Kind::Real, .metavar = "X",
       .min = Bound{kMinRelativeTolerance, true}, .max = Bound{1, false}, .why = kRtolWhy,
       .help = "relative tolerance of IDA's error test",
       .set = [](Scene& s, const Value& v) { s.solver.rtol = real(v); },
       .get = [](const Scene& s) -> Value { return s.solver.rtol; }});
  row({.scene_key = "solver.atol", .option = "--atol", .commands = kRun, .kind = Kind::Real, .metavar = "X",
       .min = Bound{kMinAbsoluteTolerance, true}, .max = Bound{1, false}, .example = "1e-8",
       .why = "below 1e-100 IDA's weighted norms overflow",
       .help = "absolute tolerance of coordinates and velocities",
       .set = [](Scene& s, const Value& v) { s.solver.atol = real(v); },
       .get = [](const Scene& s) -> Value { return s.solver.atol; }});
  row({.scene_key = "solver.max_steps", .option = "--max-steps", .commands = kRun, .kind = Kind::Integer,
       .metavar = "N", .min = Bound{1, true}, .max = Bound{1e15, true},
       .help = "limit on internal IDA steps over the whole run",
       .set = [](Scene& s, const Value& v) { s.solver.max_steps = static_cast<long>(whole(v)); },
       .get = [](const Scene& s) -> Value { return static_cast<long long>(s.solver.max_steps); }});
  row({.scene_key = "solver.max_order", .option = "--max-order", .commands = kRun, .kind = Kind::Integer,
       .metavar = "N", .min = Bound{1, true}, .max = Bound{5, true}, .help = "BDF order limit",
       .set = [](Scene& s, const Value& v) { s.solver.max_order = static_cast<int>(whole(v)); },
       .get = [](const Scene& s) -> Value { return static_cast<long long>(s.solver.max_order); }});
  row({.scene_key = "solver.initial_step", .option = "--initial-step", .commands = kRun, .kind = Kind::Real,
       .metavar = "X", .unit = "s", .min = Bound{0, true}, .why = "0: estimated at the start",
       .help = "first step; 0: estimated so that its order-1 error meets the tolerance",
       .set = [](Scene& s, const Value& v) { s.solver.initial_step = real(v); },
       .get = [](const Scene& s) -> Value { return s.solver.initial_step; }});
  row({.scene_key = "solver.min_step_fraction", .option = "--min-step-fraction", .commands = kRun,
       .kind = Kind::Real, .metavar = "X", .min = Bound{0, true}, .max = Bound{1e-6, true},
       .why = "0 turns the floor off; above 1e-6 it would stop runs that merely resolve a fast transient",
       .help = "step-size floor relative to the time scale: a run whose steps stay below X * max(|end - start|, "
               "|t|) for 20 steps in a row fails as stalled, naming t, the step, the floor and the formulation "
               "(at 1e-12 the rest of the span would take over 1e12 steps)",
       .set = [](Scene& s, const Value& v) { s.solver.min_step_fraction = real(v); },
       .get = [](const Scene& s) -> Value { return s.solver.min_step_fraction; }});
  row({.scene_key = "solver.jacobian", .option = "--jacobian", .commands = kRun, .kind = Kind::Choice,
       .choices = jacobian_names,
       .help = "iteration matrix: exact derivatives, rigidae's central differences or IDA's forward difference "
               "quotients",
       .set = [](Scene& s, const Value& v) { s.solver.jacobian = word(v); },
       .get = [](const Scene& s) -> Value { return s.solver.jacobian; }});
  row({.scene_key = "solver.linear_solver", .option = "--linear-solver", .commands = kRun, .kind = Kind::Choice,
       .choices = linear_solver_names,
       .help = "Newton's linear solver: auto (KLU from 120 unknowns on, a measured size; dense below and with "
               "--jacobian ida_dq), dense LU or KLU sparse LU (not with --jacobian ida_dq)",
       .set = [](Scene& s, const Value& v) { s.solver.linear_solver = word(v); },
       .get = [](const Scene& s) -> Value { return s.solver.linear_solver; }});
  // Which integrator runs which schemes: solver/integrators.hpp (checked in cross_problem).
  // Not compare's: the integrator is one of its axes (rows such as quaternion/euler/projection@cvode-adams).
  row({.scene_key = "solver.integrator", .option = "--integrator", .commands = kSolve, .kind = Kind::Choice,
       .choices = integrator_names, .default_text = "ida, or arkode-erk for a non-stiff index1/projection scene",
       .help = "ida: BDF on the DAE, every scheme; cvode-adams, cvode-bdf, arkode-erk: the ODE form (single "
               "bodies and mechanisms), schemes "
               "index1 (plain ODE) and projection (ODE + projection; a scene file naming one of them and no "
               "scheme gets projection). Unnamed, chosen by measurement (docs/benchmarks.md): ida for a scheme "
               "only IDA runs and for a stiff scene (an overdamped spring-damper's or torsional damper's decay "
               "rate, at most c/m, times the output step above 10, or a spring's sqrt(k/m) times it above 1000), "
               "arkode-erk otherwise; summary.json's integrator_choice says why",
       .set =
           [](Scene& s, const Value& v) {
             s.solver.integrator = word(v);
             s.solver.integrator_named = true;
           },
       .get = [](const Scene& s) -> Value { return s.solver.integrator; }});
  row({.scene_key = "solver.erk_method", .option = "--erk-method", .commands = kRun, .kind = Kind::Choice,
       .choices = erk_method_names,
       .help = "arkode-erk's Butcher table: Prince-Dormand 8(7), Fehlberg 7(8), Verner 6(5) or Dormand-Prince 5(4)",
       .set = [](Scene& s, const Value& v) { s.solver.erk_method = word(v); },
       .get = [](const Scene& s) -> Value { return s.solver.erk_method; }});

  // --- time grid ----------------------------------------------------------
  row({.scene_key = "time.start", .kind = Kind::Real, .unit = "s", .min = Bound{-kMaxTimeMagnitude, true},
       .max = Bound{kMaxTimeMagnitude, true}, .why = "s; beyond about 32 years t + h loses the digits of small steps",
       .help = "start time",
       .set = [](Scene& s, const Value& v) { s.time.start = real(v); },
       .get = [](const Scene& s) -> Value { return s.time.start; }});
  row({.scene_key = "time.end", .option = "--t-end", .commands = kRun, .kind = Kind::Real, .metavar = "T",
       .unit = "s", .min = Bound{-kMaxTimeMagnitude, true}, .max = Bound{kMaxTimeMagnitude, true},
       .why = "s; beyond about 32 years t + h loses the digits of small steps", .default_text = "required",
       .help = "end time, > time.start (the output step is kept, shortened to the span if longer)",
       .set = [](Scene& s, const Value& v) {
         s.time.end = real(v);
         if (s.time.end > s.time.start) s.time.output_step = std::min(s.time.output_step, s.time.end - s.time.start);
       },
       .get = [](const Scene& s) -> Value { return s.time.end; }});
  row({.scene_key = "time.output_step", .option = "--output-step", .commands = kRun, .kind = Kind::Real,
       .metavar = "X", .unit = "s", .min = Bound{0, false}, .default_text = "(end - start) / 100",
       .help = "spacing of the output grid (trajectory.csv); at most 1e8 intervals; replaces the scene's output.times",
       .set = [](Scene& s, const Value& v) { s.time.output_step = real(v); },
       .get = [](const Scene& s) -> Value { return s.time.output_step; }});

  // --- output (output.times, an array, is read by the scene loader) ---------
  row({.scene_key = "output.record", .option = "--record", .commands = kSolve, .kind = Kind::Choice,
       .choices = record_names,
       .help = "what is written besides summary.json: 'steps' every step (steps.csv or .npy) and the output grid "
               "(trajectory.csv), 'grid' the output grid only, 'none' neither (events.csv stays)",
       .set = [](Scene& s, const Value& v) { s.output.record = pick(kRecordModes, record_names, word(v)); },
       .get = [](const Scene& s) -> Value { return name_of(kRecordModes, record_names, s.output.record); }});
  row({.scene_key = "output.step_format", .option = "--step-format", .commands = kSolve, .kind = Kind::Choice,
       .choices = step_format_names,
       .help = "format of the step file: 'csv' (steps.csv) or 'npy' (steps.npy, NumPy's binary format: a "
               "structured array with the CSV's column names, read by numpy.load)",
       .set = [](Scene& s, const Value& v) { s.output.step_format = pick(kStepFormats, step_format_names, word(v)); },
       .get = [](const Scene& s) -> Value { return name_of(kStepFormats, step_format_names, s.output.step_format); }});

  // --- reference ----------------------------------------------------------
  row({.scene_key = "reference", .study_key = "reference", .option = "--reference", .commands = kCompare,
       .kind = Kind::Choice, .choices = reference_names,
       .help = "what accuracy is measured against: 'exact' the closed-form solution (free body, symmetric "
               "Lagrange top), 'tight' a run of quaternion/euler/ggl at the reference rtol checked against Euler "
               "angles, 'auto' exact when there is one",
       .set = [](Scene& s, const Value& v) { s.reference = pick(kReferences, reference_names, word(v)); },
       .get = [](const Scene& s) -> Value { return name_of(kReferences, reference_names, s.reference); }});
  row({.study_key = "reference_rtol", .option = "--reference-rtol", .commands = kCompare, .kind = Kind::Real,
       .metavar = "X", .min = Bound{kMinRelativeTolerance, true}, .max = Bound{1, false},
       .why = kRtolWhy, .default_text = "rtol/100, clamped to [1e-13, 1e-12]",
       .help = "relative tolerance of the tight reference runs"});

  // --- commands -----------------------------------------------------------
  row({.study_key = "timing.repeats", .option = "--repeat", .commands = kCompare, .kind = Kind::Integer,
       .metavar = "N", .min = Bound{1, true}, .max = Bound{1000, true}, .default_text = "3",
       .help = "timed runs of each combination; wall time is their median (study: minimum and median)"});
  row({.study_key = "timing.warmups", .kind = Kind::Integer, .min = Bound{0, true}, .max = Bound{1000, true},
       .default_text = "1", .help = "untimed runs before the timed ones"});
  row({.option = "--run-timeout", .commands = kCompare, .kind = Kind::Real, .metavar = "S", .unit = "s",
       .min = Bound{0, true}, .default_text = "max(300, 10 x the reference's wall time)",
       .help = "wall-time limit of each combination's run; a run past it is a failed row whose message says it "
               "timed out (its steps kept), and compare goes on with the next; 0: no limit"});
  row({.option = "--keep-going", .commands = kCompare, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off",
       .help = "run every combination even when the reference failed (errors are then not reported; the exit "
               "code stays 1); without it compare stops there"});
  row({.option = "--only", .commands = kCompare, .kind = Kind::Text, .metavar = "LIST",
       .default_text = "every combination",
       .help = "comma-separated patterns of combinations to run: 'quaternion/*/ggl' globs the whole name, a bare "
               "word ('ggl', 'linear', 'index*') matches any one part ('euler' matches both Euler angles and the "
               "Euler form); '@INTEGRATOR' selects ODE-integrator rows ('*@cvode-adams', 'quaternion/*/*@*'), "
               "without it a pattern selects IDA rows, and a bare integrator name ('arkode-erk') its rows"});
  row({.option = "--skip", .commands = kCompare, .kind = Kind::Text, .metavar = "LIST", .default_text = "none",
       .help = "patterns of combinations to leave out"});
  row({.option = "--shard", .commands = kStudy, .kind = Kind::Text, .metavar = "i/N", .default_text = "none",
       .help = "(study run) slice i of N: runs k with k % N == i"});
  row({.option = "--run", .commands = kStudy, .kind = Kind::Text, .metavar = "ID", .default_text = "none",
       .help = "(study run) one run, by the id 'study list' prints"});
  row({.option = "--out", .commands = kSolve | kCompare | kStudy, .kind = Kind::Text, .metavar = "DIR",
       .default_text = "out/NAME-COORDINATES-EQUATIONS-SCHEME, out/NAME-compare, out/STUDY_NAME",
       .help = "output folder"});
  row({.option = "--error-estimate", .commands = kSolve, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off",
       .help = "the accuracy verdict of a scene without a closed form: run it again at rtol/100 and atol/100 "
               "(into DIR/error_estimate, its wall time in summary.json) and warn when the two differ by more than "
               "300 x max(rtol, atol) over the output grid (orientation, and mechanisms' positions relative to "
               "their size); off by default because it adds ~180 % to the wall time (a scene with a closed form is "
               "judged by it without a second run; without either solve notes 'accuracy not estimated'; needs "
               "--record steps or grid)"});
  row({.option = "--no-error-estimate", .commands = kCompare | kStudy, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off (every row gets a verdict)",
       .help = "no companion runs: by default each run of a scene without a closed form is run again at rtol/100 "
               "(into its folder's error_estimate/) and warned about when the two differ by more than 300 x "
               "max(rtol, atol) over the output grid (docs/accuracy_check.md); a closed form decides without one"});
  row({.option = "--plot", .commands = kSolve | kCompare, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off",
       .help = "draw figures into DIR/figures (PNG and PDF) with tools/plot_solve.py or tools/plot_compare.py"});
  row({.option = "--view", .commands = kSolve | kCompare, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off",
       .help = "write DIR/view.html: a page that plays the run (a compare's runs side by side) in a browser, "
               "offline (rigidae view; docs/viewer.md)"});
  row({.option = "--vtk", .commands = kSolve, .kind = Kind::Boolean, .flag_value = "true", .default_text = "off",
       .help = "write DIR/vtk/run.pvd: the bodies' shapes and points at each output time for ParaView "
               "(rigidae vtk; docs/viewer.md)"});
  row({.option = "--keep-steps", .commands = kCompare | kStudy, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off",
       .help = "keep each run's steps.csv (otherwise only summary.json, trajectory.csv and events.csv stay; "
               "compare --plot keeps them, the figures read them)"});
  row({.option = "--no-plot", .commands = kStudy, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off", .help = "(study, study collect) skip the figures (tools/plot_study.py)"});
  row({.option = "--partial", .commands = kStudy, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off", .help = "(study collect) exit 0 even if some runs are missing"});
  row({.option = "--quiet", .short_option = "-q", .commands = kSolve | kCompare | kStudy, .kind = Kind::Boolean, .flag_value = "true",
       .default_text = "off", .help = "no progress lines; solve prints nothing on success"});
  return t;
}

}  // namespace

std::span<const Setting> all() {
  static const std::vector<Setting> table = make_table();  // built on first use: safe from other statics
  return table;
}

}  // namespace rigidae::settings
