"""A solver failure raises SolverError with the CLI's message and keeps the
records up to the failure, as the CLI keeps its files."""
import numpy as np
import pytest

import rigidae
from conftest import SOURCE, read_csv, read_summary, run_cli

GIMBAL = SOURCE / "tests" / "failure_scenes" / "gimbal_lock.toml"


def test_failure_raises_and_keeps_the_records(tmp_path):
    code, _, stderr = run_cli("solve", GIMBAL, "--out", tmp_path, "--quiet")
    assert code == 1
    cli = read_summary(tmp_path)
    assert cli["status"] == "failed"

    with pytest.raises(rigidae.SolverError) as e:
        rigidae.solve(GIMBAL)
    err = e.value
    assert err.message == cli["message"] and err.message in stderr
    run = err.run
    assert run.status == "failed" and not run.ok
    assert run.summary["counters"] == cli["counters"]
    assert run.final["t"] == cli["final"]["t"] < 1.0
    # Every step up to the failure, as steps.csv has them.
    _, header, rows = read_csv(tmp_path / "steps.csv")
    assert len(run.steps) == len(rows) > 0
    assert np.array_equal(run.steps["t"], [float(r[0]) for r in rows])
    assert run.steps["t"][-1] == float(rows[-1][0]) == cli["final"]["t"]
    # The grid stops before the end.
    assert run.grid["t"][-1] <= run.final["t"]


def test_too_few_steps_is_a_failure_with_records():
    with pytest.raises(rigidae.SolverError, match="max|steps") as e:
        rigidae.solve(SOURCE / "problems" / "heavy_top.toml", max_steps=50)
    assert len(e.value.run.steps) == 50
    assert np.all(np.diff(e.value.run.steps["t"]) > 0)
