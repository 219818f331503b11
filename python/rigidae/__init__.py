"""rigidae: rigid-body rotation as differential-algebraic equations, solved
with SUNDIALS IDA, from Python.

    import rigidae
    scene = rigidae.load_scene("problems/heavy_top.toml")
    run = rigidae.solve(scene, coordinates="quaternion", equations="euler", scheme="ggl", rtol=1e-10)
    run.summary["counters"]["steps"], run.grid["qw"], run.steps["drift_position"]
    table = rigidae.compare(scene, only="quaternion/euler/*", repeat=1)

Scenes: load_scene(path), scene_from_dict(dict) (the keys of
docs/scene_format.md; read_scene_dict(path) gives a file's dict to modify).
Runs: solve(), compare(), study(), read_study(), exact_solution().
Options: every scene override of the CLI, as a keyword with '-' written '_'
(--t-end is t_end=, --no-chart-switching is no_chart_switching=True);
see rigidae.OPTIONS and help(rigidae.solve).
Errors: InputError (a ValueError), SolverError, Interrupted (Ctrl-C).
Tables: pandas DataFrames when pandas is importable, else dicts of numpy arrays.
"""
import inspect
import json
import os
import re
import tempfile
import tomllib
from difflib import get_close_matches

import numpy as np

from . import _scene_dict, _tables
from .errors import InputError, Interrupted, SolverError

from . import _core  # noqa: E402  (imports rigidae.errors, which must exist first)

__all__ = ["Scene", "Run", "MultibodyRun", "load_scene", "scene_from_dict", "read_scene_dict", "solve", "compare", "study",
           "read_study", "collect_study", "exact_solution", "quaternion_angle", "InputError", "SolverError",
           "Interrupted", "OPTIONS", "UNITS", "HAVE_PANDAS"]
__version__ = _core.version

Scene = _core.Scene
HAVE_PANDAS = _tables.HAVE_PANDAS


# --------------------------------------------------------------------------
# Options: the CLI's scene overrides, named as keywords
# --------------------------------------------------------------------------

def _keyword(option):
    return option[2:].replace("-", "_")


def _describe(o):
    if o["flag"]:
        # A flag's keyword takes True or False; the domain and default are
        # the scene key's, which the flag turns to its other value.
        return (f"{o['option']}: {o['help']} [{_keyword(o['option'])}=True as the flag; default False: the scene's "
                f"{o['scene_key']} (default {o['default']})]")
    value = f" {o['metavar']}" if o["metavar"] else ""
    extra = [x for x in (o["domain"], f"default {o['default']}" if o["default"] else "", o["unit"]) if x]
    return f"{o['option']}{value}: {o['help']}" + (f" [{'; '.join(extra)}]" if extra else "")


_SOLVE_OPTIONS = [o for o in _core.scene_options("solve") if o["scene_key"]]
#: Every scene option of solve, keyword name -> its help (from rigidae's table of settings).
#: solve's own `record` keyword (what is kept in memory) stands where the CLI has --record.
OPTIONS = {_keyword(o["option"]): _describe(o) for o in _SOLVE_OPTIONS if o["option"] != "--record"}
_FLAGS = {_keyword(o["option"]) for c in ("solve", "compare") for o in _core.scene_options(c) if o["flag"]}


def _option_text(value):
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return repr(value)  # shortest text that reads back to the same double
    if isinstance(value, (list, tuple)):
        return ",".join(map(str, value))
    return str(value)


def _option_args(options):
    """Command-line words for the options, in the order given; the command
    line parser checks them (unknown names, values) with its own words."""
    args = []
    for name, value in options.items():
        if value is None:
            continue
        flag = "--" + name.replace("_", "-")
        if name in _FLAGS:
            if value is True:
                args.append(flag)
            elif value is not False:
                raise InputError(f"option {flag}: {name}= takes True or False, not {value!r}")
        else:
            args.append(f"{flag}={_option_text(value)}")
    return args


# --------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------

def load_scene(path, **options):
    """The scene of a TOML file (docs/scene_format.md), checked by the same code
    as the CLI; options override it as on the command line (t_end=1.0, ...).
    Raises InputError with FILE:LINE:COL and what would be valid."""
    scene = _core.load_scene(os.fspath(path))
    return _with_options(scene, options)


def read_scene_dict(path):
    """A scene file's contents as a dict (tomllib), to modify and pass to
    scene_from_dict or solve (e.g. for a parameter sweep)."""
    with open(path, "rb") as f:
        return tomllib.load(f)


def scene_from_dict(d, **options):
    """A scene from a dict with the keys of a scene file, e.g.
    {"schema_version": 1, "body": {"mass": 1.0, "inertia_principal": [1, 2, 3]}, ...}.
    Checked by the scene loader with the same messages, whose position is the
    key path: a misspelt key raises InputError("scene['body']['mas']: error:
    unknown key 'mas' in [body]; did you mean 'mass'? ...") with .key =
    ('body', 'mas') and .suggestion = 'mass'."""
    text, where = _scene_dict.to_toml(d)
    try:
        scene = _core.parse_scene(text, _scene_dict.SOURCE)
    except InputError as e:
        message, key = _scene_dict.relabel(e.message, where)
        raise InputError(message, key=key) from None
    return _with_options(scene, options)


_UNKNOWN_OPTION = re.compile(r"^unknown option '--(?P<name>[^']*)' for (?P<command>\w+)(?:; did you mean "
                             r"'--(?P<close>[^']*)'\?)?")


def _as_keywords(e):
    """The command line's "unknown option '--rtoll' ... did you mean '--rtol'"
    in the words of a Python call: keyword arguments."""
    m = _UNKNOWN_OPTION.match(e.message)
    if not m:
        return e
    name, command = _keyword("--" + m["name"]), m["command"]
    text = f"unknown keyword argument {name}= for rigidae.{command}()"
    if m["close"]:
        text += f"; did you mean {_keyword('--' + m['close'])}=?"
    text += f" (the keywords: rigidae.OPTIONS, or help(rigidae.{command}))"
    out = InputError(text)
    out.option, out.suggestion = name, _keyword("--" + m["close"]) if m["close"] else None
    return out


def _with_options(scene, options, command="solve"):
    args = _option_args(options)
    try:
        return scene._with_options(command, args) if args else scene
    except InputError as e:
        raise _as_keywords(e) from None


def _as_scene(scene, options, command="solve"):
    if isinstance(scene, dict):
        scene = scene_from_dict(scene)
    elif isinstance(scene, (str, os.PathLike)):
        scene = _core.load_scene(os.fspath(scene))
    if isinstance(scene, Scene):
        return _with_options(scene, options, command)
    raise TypeError(f"scene must be a rigidae.Scene, a path or a dict, not {type(scene).__name__}")


def _scene_repr(self):
    return (f"<rigidae.Scene {self.name!r} from {self.source!r}: {self.coordinates}/{self.equations}/{self.scheme}, "
            f"t {self.t_start:g}..{self.t_end:g} s, rtol {self.rtol:g}>")


Scene.__repr__ = _scene_repr


# --------------------------------------------------------------------------
# Runs
# --------------------------------------------------------------------------

def _units_by_key():
    """{"t": "s", "qw..qz": "unit quaternion ...", "omega_*": "rad/s body frame", ...} from the units line."""
    line = _core.units_line().split(":", 1)[1]
    return dict(seg.strip().split(" ", 1) for seg in line.split(";") if " " in seg.strip())


_UNITS_BY_KEY = _units_by_key()


def _unit(column):
    """The unit of a column of steps.csv / trajectory.csv, as their first line states it."""
    for key, unit in _UNITS_BY_KEY.items():
        if key == column or (key.endswith("*") and column.startswith(key[:-1])):
            return unit
        if ".." in key:
            first, last = key.split("..")
            if len(column) == len(first) and column[:-1] == first[:-1] and first[-1] <= column[-1] <= last[-1]:
                return unit
    return {"order": "1 (BDF order)", "chart": "Euler sequence"}.get(column, "?")


class _Units(dict):
    def __missing__(self, column):
        return _unit(column)


#: The unit of any column of Run.steps / Run.grid: UNITS["omega_x"] == "rad/s (body frame)".
UNITS = _Units()


def _structured(columns, rows, charts, integers=("order",)):
    """A numpy structured array: float64 columns, whole numbers ('order') int64, 'chart' str."""
    width = max([3] + [len(c) for c in charts])
    dtype = [(c, np.int64 if c in integers else f"<U{width}" if c == "chart" else np.float64) for c in columns]
    a = np.empty(rows.shape[0], dtype=dtype)
    names = np.array(charts if charts else [""], dtype=f"<U{width}")
    for i, c in enumerate(columns):
        a[c] = names[rows[:, i].astype(np.intp)] if c == "chart" else rows[:, i]
    return a


_EVENT_DTYPE = [("t", np.float64), ("event", "<U12"), ("from", "<U3"), ("to", "<U3"), ("margin", np.float64),
                ("drift_position", np.float64), ("drift_velocity", np.float64)]


class _RunOutcome:
    """What Run and MultibodyRun share: the status and the integrator's counters."""

    @property
    def ok(self):
        return self.status == "success"

    @property
    def counters(self):
        """The integrator's counters (summary['counters'])."""
        return self.summary["counters"]


class Run(_RunOutcome):
    """One run's results (what `rigidae solve` writes, in memory).

    summary  dict: summary.json (configuration, status, counters, maxima, final state)
    steps    numpy structured array, one row per IDA step, the columns of
             steps.csv (t, h, order, qw..qz, omega_x..z, drift_position,
             drift_velocity, lambda_*/mu_*, energy, energy_rel_error,
             vertical_momentum, vertical_momentum_rel_error[, chart]);
             None unless record="steps"
    grid     the same on the output grid (trajectory.csv's columns: no h, order);
             None when record="none"
    events   structured array: chart switches and projections (events.csv)
    status   "success", "failed" or "interrupted"; message: why it stopped
    out      the folder the files went to, or None
    Dtypes: float64, except order (int64) and chart (str, e.g. 'zxz').
    Units: rigidae.UNITS[column] (SI; as the CSV files' first line).
    """

    def __init__(self, raw, scene):
        self.scene = scene
        self.summary = json.loads(raw["summary"])
        self.status = raw["status"]
        self.message = raw["message"]
        self.out = raw["out"]
        record = raw["record"]
        charts = list(raw["charts"])
        ints = list(raw["integer_columns"])
        self.steps = _structured(raw["step_columns"], raw["steps"], charts, ints) if record == "steps" else None
        self.grid = _structured(raw["grid_columns"], raw["grid"], charts, ints) if record != "none" else None
        self.events = np.array([tuple(e) for e in raw["events"]], dtype=_EVENT_DTYPE)

    @property
    def final(self):
        """The state at the last step (summary['final'])."""
        return self.summary["final"]

    def __repr__(self):
        c = self.counters
        return (f"<rigidae.Run {self.summary['representation']} / {self.summary['scheme']}: {self.status}, "
                f"t = {self.summary['t_reached']:g} s, {c['steps']} steps, {self.summary['wall_time_s']:.3g} s>")


# A joint's one-number columns: residuals and coordinates (JOINT.angle, ...).
_JOINT_VECTOR_COLUMNS = {"force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z"}


def _joint_scalars(table, name):
    prefix = name + "."
    out = {}
    for column in table.dtype.names:
        if not column.startswith(prefix):
            continue
        key = column[len(prefix):]
        if key in _JOINT_VECTOR_COLUMNS or key.startswith(("lambda_", "mu_")):
            continue
        out[key] = table[column]
    return out


class MultibodyRun(_RunOutcome):
    """One run of a multibody scene (schema_version 2), in memory.

    grid       numpy structured array on the output grid: the columns of the
               CLI's trajectory.csv (t, BODY.qw..qz, BODY.wx..wz in space,
               BODY.x..z, BODY.vx..vz, JOINT.force_x..z and torque_x..z on
               the joint's second body in space, JOINT.residual_position,
               JOINT.residual_velocity, the joint's coordinates JOINT.angle,
               JOINT.displacement (angle_a, angle_b for a universal joint)
               and their rates JOINT.*_rate,
               energy, p_x..p_z, L_x..L_z); None when record="none"
    steps      per IDA step, the columns of steps.csv: t, h, order,
               drift_position, drift_velocity, energy, energy_rel_error, then
               per recorded body its own constraints' multipliers
               (BODY.lambda_*, BODY.mu_*) and per recorded joint its
               multipliers (JOINT.lambda_<row>, JOINT.mu_<row>), reaction
               (JOINT.force_x..z, JOINT.torque_x..z on the second body, space
               frame), drift (JOINT.residual_position, JOINT.residual_velocity)
               and coordinates (JOINT.angle, ..., as grid's); the scene's
               [output] bodies / joints choose the parts (by default all of
               a mechanism of at most 50 joints, none of a larger one);
               None unless record="steps". summary["multipliers_error_controlled"]
               says whether the multipliers and reactions are held to rtol/atol
               (with IDA they are not: summary["multipliers_error_note"])
    units      {column: unit} of grid's columns (as trajectory.csv's first line)
    bodies, joints   names, in the scene's order
    body(name)  {"t", "q" (n x 4, scalar first), "omega" (n x 3, rad/s, space),
                 "x" (n x 3, m), "v" (n x 3, m/s)} from the grid (a particle:
                 no "q", "omega")
    joint(name) {"t", "force" (n x 3, N), "torque" (n x 3, N m), "residual_position",
                 "residual_velocity", and its coordinates: "angle", "angle_rate" (rad,
                 rad/s; revolute, cylindrical), "displacement", "displacement_rate"
                 (m, m/s; prismatic, cylindrical), "angle_a", "angle_b" and rates
                 (universal)}: the reaction on the joint's second body, in space,
                 on the grid
    joint_steps(name)  the same at every IDA step (from steps)
    summary    summary.json as the CLI writes it (with out= or without): status,
               counters, warnings, mobility, recorded parts, build and run
               provenance, the accuracy verdict ("error_estimate": the closed
               form's error where the scene has one, e.g. the simple pendulum;
               no companion run, which is the CLI's --error-estimate), ... The
               run is the CLI's: any integrator the scene or the options name
    out        the folder steps.csv, trajectory.csv and events.csv went to, or None
    """

    def __init__(self, raw, scene):
        self.scene = scene
        self.status = raw["status"]
        self.message = raw["message"]
        self.out = raw["out"]
        self.bodies = list(raw["bodies"])
        self.joints = list(raw["joints"])
        self.units = dict(zip(raw["grid_columns"], raw["grid_units"]))
        self.summary = json.loads(raw["summary"])  # summary.json, written to out or not
        record = raw["record"]
        self.steps = _structured(raw["step_columns"], raw["steps"], [], ("order",)) if record == "steps" else None
        self.grid = _structured(raw["grid_columns"], raw["grid"], [], ()) if record != "none" else None
        self.events = list(raw["events"])

    def _columns(self, prefix, names):
        if self.grid is None:
            raise ValueError("no output grid recorded (record='none')")
        return np.column_stack([self.grid[f"{prefix}.{n}"] for n in names])

    def body(self, name):
        if name not in self.bodies:
            raise KeyError(f"{name!r} is not a body of this scene; bodies: {', '.join(self.bodies)}")
        out = {"t": self.grid["t"], "x": self._columns(name, ["x", "y", "z"]),
               "v": self._columns(name, ["vx", "vy", "vz"])}
        if f"{name}.qw" in self.grid.dtype.names:  # a particle has no rotation
            out["q"] = self._columns(name, ["qw", "qx", "qy", "qz"])
            out["omega"] = self._columns(name, ["wx", "wy", "wz"])
        return out

    def joint(self, name):
        if name not in self.joints:
            raise KeyError(f"{name!r} is not a joint of this scene; joints: {', '.join(self.joints)}")
        return {"t": self.grid["t"], "force": self._columns(name, ["force_x", "force_y", "force_z"]),
                "torque": self._columns(name, ["torque_x", "torque_y", "torque_z"]),
                **_joint_scalars(self.grid, name)}

    def joint_steps(self, name):
        if name not in self.joints:
            raise KeyError(f"{name!r} is not a joint of this scene; joints: {', '.join(self.joints)}")
        if self.steps is None:
            raise ValueError("no steps recorded (record='steps' records them)")
        if f"{name}.force_x" not in self.steps.dtype.names:
            raise KeyError(f"joint {name!r} is not recorded per step: the scene's [output] joints leaves it out "
                           "(or the mechanism has more than 50 joints and names none)")
        cols = lambda names: np.column_stack([self.steps[f"{name}.{n}"] for n in names])
        return {"t": self.steps["t"], "force": cols(["force_x", "force_y", "force_z"]),
                "torque": cols(["torque_x", "torque_y", "torque_z"]),
                **_joint_scalars(self.steps, name)}

    def __repr__(self):
        return (f"<rigidae.MultibodyRun {len(self.bodies)} bodies, {len(self.joints)} joints: {self.status}, "
                f"t = {self.summary['t_reached']:g} s, {self.counters['steps']} steps>")


def solve(scene, *, record="steps", out=None, **options):
    scene = _as_scene(scene, options)
    if scene.is_multibody:
        raw = _core.solve_multibody(scene, record, None if out is None else os.fspath(out))
        run = MultibodyRun(raw, scene)
    else:
        raw = _core.solve(scene, record, None if out is None else os.fspath(out))
        run = Run(raw, scene)
    if raw["interrupted"] or run.status == "interrupted":
        raise Interrupted(run.message, run)
    if run.status != "success":
        raise SolverError(run.message, run)
    return run


def _options_doc():
    import textwrap
    return "\n".join(textwrap.fill(f"{name}= ({text})", width=100, initial_indent="    ",
                                   subsequent_indent="        ") for name, text in OPTIONS.items())


solve.__doc__ = f"""Integrates a scene, as `rigidae solve` does, and returns a Run.

    run = rigidae.solve("problems/heavy_top.toml", coordinates="quaternion",
                        equations="euler", scheme="ggl", rtol=1e-10)

    scene    a rigidae.Scene, a scene file's path, or a scene dict
    record   "steps": every IDA step (run.steps) and the output grid (run.grid);
             "grid": the output grid only; "none": neither (run.summary only)
    out      a folder: also write the files `rigidae solve` writes there, as
             the scene's output.record and step_format say (default: steps.csv,
             trajectory.csv, events.csv, summary.json). None (default): no files.
    options  the CLI's scene overrides, by the same names ('-' as '_'); flags
             take True. Checked with the CLI's messages (InputError).

    A multibody scene (schema_version 2) gives a MultibodyRun: per-body and
    per-joint arrays (run.body("top")["q"], run.joint("pivot")["force"]);
    out= then writes steps.csv, trajectory.csv and events.csv (summary.json:
    the CLI's).

    Raises SolverError (the message, and .run with the records up to the
    failure) when the integrator fails, Interrupted (.run) on Ctrl-C, and
    InputError for bad input. The GIL is released while it integrates.

    Options:
{_options_doc()}
"""
solve.__signature__ = inspect.Signature(
    [inspect.Parameter("scene", inspect.Parameter.POSITIONAL_OR_KEYWORD),
     inspect.Parameter("record", inspect.Parameter.KEYWORD_ONLY, default="steps"),
     inspect.Parameter("out", inspect.Parameter.KEYWORD_ONLY, default=None)]
    + [inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=None) for name in OPTIONS])


def compare(scene, *, only=None, skip=None, repeat=3, reference=None, reference_rtol=None, out=None,
            progress=None, as_dataframe=None, **options):
    """Every applicable coordinates x equations x scheme combination on one
    scene against one reference, as `rigidae compare`; returns compare.csv's
    table (one row per combination; a failed one is a row with its message).

    only, skip      patterns (a list or a comma-separated string): 'quaternion/*/ggl'
                    globs the whole name, a bare word ('ggl', 'linear') matches a part
    repeat          wall time is the median of this many runs (default 3)
    reference       'auto' (default: the scene's choice), 'exact' or 'tight'
    reference_rtol  tolerance of a tight reference (default rtol/100 in [1e-13, 1e-12])
    out             folder for compare.csv, compare.txt, compare.md and every run's
                    files; None: a temporary folder, deleted afterwards
    progress        called with one line per finished run (e.g. print)
    as_dataframe    None: a DataFrame if pandas is importable, else a dict of arrays
    options         scene overrides as for solve(), except coordinates, equations, scheme

    Raises SolverError (with .table) when the reference could not be computed."""
    scene = _as_scene(scene, {})
    args = _option_args(dict(options, repeat=repeat, only=only, skip=skip, reference=reference,
                             reference_rtol=reference_rtol))
    with tempfile.TemporaryDirectory(prefix="rigidae-compare-") as tmp:
        folder = os.fspath(out) if out is not None else tmp
        try:
            raw = _core.compare(scene, args, folder, progress)
        except InputError as e:
            raise _as_keywords(e) from None
        result = _tables.read_csv(os.path.join(folder, "compare.csv"), as_dataframe)
    if not raw["reference_ok"]:
        e = SolverError(raw["reference_message"])
        e.table = result
        raise e
    return result


# --------------------------------------------------------------------------
# Studies
# --------------------------------------------------------------------------

def _study_out(spec, out):
    return os.fspath(out) if out is not None else os.path.join("out", spec.name)


def study(path, *, out=None, shard=None, run=None, collect=True, progress=None, as_dataframe=None):
    """Runs an accuracy study file (docs/studies.md), as `rigidae study`, and
    returns its results.csv table (one row per run: errors, work, timings).

    out       the study folder (default out/STUDY_NAME, as the CLI); complete
              runs there are never redone, so an interrupted study resumes
    shard     "i/N": only runs k with k % N == i (then nothing is collected, None returned)
    run       one run's id (see rigidae.load_study(path).run_ids())
    collect   merge the run folders into results.csv and best.txt afterwards
    progress  called as progress(done, skipped, failed, total, last_run_id)
    Figures: `/usr/bin/python3 tools/plot_study.py OUT` as the CLI draws them."""
    spec = _core.load_study(os.fspath(path))
    folder = _study_out(spec, out)
    _core.run_study(spec, folder, shard, run, progress)
    if shard is not None or run is not None or not collect:
        return None
    _core.collect_study(spec, folder)
    return read_study(folder, as_dataframe)


def load_study(path):
    """A study file, checked (InputError with FILE:LINE:COL); .run_ids() lists its runs."""
    return _core.load_study(os.fspath(path))


def collect_study(path, out=None):
    """Merges a study's complete run folders into OUT/results.csv and the
    best-per-target table; returns (best table text, ids of runs missing)."""
    spec = _core.load_study(os.fspath(path))
    return _core.collect_study(spec, _study_out(spec, out))


def read_study(out, as_dataframe=None):
    """A collected study's OUT/results.csv as a table (DataFrame or dict of arrays)."""
    return _tables.read_csv(os.path.join(os.fspath(out), "results.csv"), as_dataframe)


# --------------------------------------------------------------------------
# References
# --------------------------------------------------------------------------

def exact_solution(scene, times):
    """The closed-form solution of a scene (a torque-free body, or a symmetric
    Lagrange top) at the given times, as a structured array with the columns
    t, qw, qx, qy, qz, omega_x, omega_y, omega_z (the quaternion continuous in
    time). InputError says why when the scene has no closed form."""
    scene = _as_scene(scene, {})
    times = np.atleast_1d(np.asarray(times, dtype=np.float64))
    raw = _core.exact_solution(scene, times.tolist())
    return _structured(raw["columns"], raw["rows"], [])


def quaternion_angle(a, b):
    """Rotation angle (rad) between orientations given as unit quaternions:
    arrays (..., 4) scalar first, or structured arrays with qw..qz columns."""
    def q(x):
        if getattr(x, "dtype", None) is not None and x.dtype.names:
            return np.stack([x["qw"], x["qx"], x["qy"], x["qz"]], axis=-1)
        return np.asarray(x, dtype=np.float64)

    a, b = q(a), q(b)
    # The quaternions (sign aligned) are 4-vectors half the rotation angle
    # apart: |a - b| = 2 sin(angle/4), accurate for small angles, unlike acos.
    sign = np.where(np.sum(a * b, axis=-1) >= 0, 1.0, -1.0)
    diff = np.linalg.norm(a - sign[..., None] * b, axis=-1)
    return 4.0 * np.arcsin(np.clip(diff / 2.0, 0.0, 1.0))
