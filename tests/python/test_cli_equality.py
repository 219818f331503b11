"""The module's runs equal the CLI's on the same scene: the same counters,
the same final state, and the same records value for value (the CSV files
hold the shortest text that reads back to the same double, so a row read
back must equal the array's row exactly)."""
import numpy as np
import pytest

import rigidae
from conftest import HEAVY_TOP, read_csv, read_summary, run_cli

# Quaternions with the default scheme, Euler angles with chart switches,
# linear coordinates in the Lagrange form with multipliers, projection restarts.
COMBINATIONS = [
    dict(coordinates="quaternion", equations="euler", scheme="ggl"),
    dict(coordinates="euler", equations="euler", scheme="ggl"),
    dict(coordinates="linear", equations="lagrange", scheme="index2", t_end=0.5),
    dict(coordinates="quaternion", equations="lagrange", scheme="projection", rtol=1e-7, atol=1e-7, t_end=0.5),
]


def cli_args(options):
    args = []
    for k, v in options.items():
        args += ["--" + k.replace("_", "-"), str(v)]
    return args


def as_float(rows, columns, name):
    i = columns.index(name)
    return np.array([float(r[i]) for r in rows])


@pytest.mark.parametrize("options", COMBINATIONS, ids=lambda o: "/".join(str(v) for v in o.values()))
def test_module_equals_cli(options, tmp_path):
    code, _, err = run_cli("solve", HEAVY_TOP, "--out", tmp_path / "cli", "--quiet", *cli_args(options))
    assert code == 0, err
    cli = read_summary(tmp_path / "cli")
    run = rigidae.solve(HEAVY_TOP, **options)

    assert run.summary["counters"] == cli["counters"]
    assert run.summary["chart_switch_count"] == cli["chart_switch_count"]
    for key in ("q_WB", "omega_B"):
        assert np.allclose(run.final[key], cli["final"][key], rtol=0, atol=1e-14)
    for key in ("t", "energy", "drift_position", "drift_velocity"):
        assert abs(run.final[key] - cli["final"][key]) <= 1e-14 * max(1.0, abs(cli["final"][key]))
    # Everything else in the summary but the wall time.
    py = dict(run.summary)
    py.pop("wall_time_s"), cli.pop("wall_time_s")
    assert py.pop("run")["command_line"] != cli.pop("run")["command_line"]  # this process, the CLI's
    # The build record is each binary's: equal when both were built together, not after a commit
    # that rebuilt only the module (tests/install/check_pip_install.py rebuilds it).
    assert set(py.pop("build")) == set(cli.pop("build")) == {"commit", "dirty", "date"}
    # The command's own addition: the error against the closed form on the
    # output grid (the heavy top has one), from trajectory.csv and reference.csv.
    assert cli.pop("closed_form_error")["final_orientation_rad"] < 1e-3
    # The verdict judged from the closed form (app/error_estimate.hpp), its
    # warnings after the invariants': the module's, from the grid it keeps
    # in memory, is the command's.
    verdict = cli["error_estimate"]
    assert verdict["source"] == "closed form"
    judged = [w for w in cli["warnings"] if w["quantity"] in ("orientation_error", "position_error")]
    assert len(judged) == (verdict["orientation"]["max_orientation_rad"] > verdict["limit"])
    assert py == cli

    for array, name in ((run.steps, "steps.csv"), (run.grid, "trajectory.csv")):
        _, header, rows = read_csv(tmp_path / "cli" / name)
        assert list(array.dtype.names) == header
        assert len(array) == len(rows)
        for c in header:
            if c == "chart":
                assert list(array[c]) == [r[header.index(c)] for r in rows]
            else:
                assert np.array_equal(array[c], as_float(rows, header, c)), c


def test_files_written_by_the_module_equal_the_cli_files(tmp_path):
    options = dict(coordinates="euler", equations="lagrange", t_end=1.0)
    code, _, err = run_cli("solve", HEAVY_TOP, "--out", tmp_path / "cli", "--quiet", *cli_args(options))
    assert code == 0, err
    run = rigidae.solve(HEAVY_TOP, out=tmp_path / "py", record="none", **options)
    assert run.steps is None and run.grid is None
    for name in ("steps.csv", "trajectory.csv", "events.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    py, cli = read_summary(tmp_path / "py"), read_summary(tmp_path / "cli")
    py.pop("wall_time_s"), cli.pop("wall_time_s")
    py.pop("run"), cli.pop("run")  # the command line and the time of each
    assert set(py.pop("build")) == set(cli.pop("build")) == {"commit", "dirty", "date"}  # each binary's, as above
    assert "closed_form_error" in cli  # the command's own addition, as above
    cli.pop("closed_form_error")
    verdict = cli.pop("error_estimate")
    judged = [w for w in cli["warnings"] if w["quantity"] in ("orientation_error", "position_error")]
    assert len(judged) == (verdict["orientation"]["max_orientation_rad"] > verdict["limit"])
    cli["warnings"] = cli["warnings"][:len(cli["warnings"]) - len(judged)]
    # record="none" keeps no grid in memory: the module's verdict says so.
    assert py.pop("error_estimate")["not_estimated"] == "record='none' keeps no output grid to compare"
    assert py == cli
    # The events of the chart switches, in memory as in events.csv.
    _, header, rows = read_csv(tmp_path / "cli" / "events.csv")
    assert len(run.events) == len(rows) == cli["chart_switch_count"] > 0
    assert np.array_equal(run.events["t"], as_float(rows, header, "t"))
    assert list(run.events["to"]) == [r[header.index("to")] for r in rows]


def test_no_files_unless_asked(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rigidae.solve(HEAVY_TOP, t_end=0.1)
    assert list(tmp_path.iterdir()) == []
