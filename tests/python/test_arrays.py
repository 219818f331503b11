"""The arrays have the documented columns, dtypes and units."""
import numpy as np
import pytest

import rigidae
from conftest import HEAVY_TOP, read_csv, run_cli


@pytest.mark.parametrize("coordinates", ["quaternion", "euler"])
def test_columns_dtypes_units(coordinates, tmp_path):
    run = rigidae.solve(HEAVY_TOP, coordinates=coordinates, equations="lagrange", t_end=0.2)
    code, _, err = run_cli("solve", HEAVY_TOP, "--coordinates", coordinates, "--equations", "lagrange",
                           "--t-end", "0.2", "--out", tmp_path, "--quiet")
    assert code == 0, err
    units, header, _ = read_csv(tmp_path / "steps.csv")
    assert list(run.steps.dtype.names) == header
    observed = ["qw", "qx", "qy", "qz", "omega_x", "omega_y", "omega_z", "drift_position", "drift_velocity"]
    tail = ["energy", "energy_rel_error", "vertical_momentum", "vertical_momentum_rel_error"]
    names = [c for c in header if c.startswith(("lambda_", "mu_"))]
    assert header[:12] == ["t", "h", "order"] + observed
    assert header[12 + len(names):12 + len(names) + 4] == tail
    assert list(run.grid.dtype.names) == read_csv(tmp_path / "trajectory.csv")[1]
    assert list(run.grid.dtype.names) == [c for c in header if c not in ("h", "order")]
    for c in header:
        expected = {"order": np.dtype(np.int64), "chart": np.dtype("<U3")}.get(c, np.dtype(np.float64))
        assert run.steps.dtype[c] == expected, c
        # Every unit UNITS states is the one the CSV's first line states.
        assert rigidae.UNITS[c] != "?", c
    assert ("chart" in header) == (coordinates == "euler")
    if coordinates == "euler":
        assert set(run.steps["chart"]) <= {"xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy",
                                          "zxz", "zyz"}
    for unit, columns in (("J", "lambda_"), ("1/s", "mu_"), ("rad/s", "omega_")):
        if any(c.startswith(columns) for c in header):
            assert f"{columns}* {unit}" in units
    # The grid: start and end exactly, the scene's step between.
    assert run.grid["t"][0] == 0.0 and run.grid["t"][-1] == 0.2
    assert np.allclose(np.diff(run.grid["t"]), 0.01)
    # Unit quaternions, and the energy error relative to the start.
    q = np.stack([run.steps[c] for c in ("qw", "qx", "qy", "qz")], axis=1)
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-6)
    assert run.steps["order"].min() >= 1 and run.steps["order"].max() <= 5


def test_record_modes():
    full = rigidae.solve(HEAVY_TOP, t_end=0.2)
    grid = rigidae.solve(HEAVY_TOP, t_end=0.2, record="grid")
    none = rigidae.solve(HEAVY_TOP, t_end=0.2, record="none")
    assert grid.steps is None and none.steps is None and none.grid is None
    assert np.array_equal(grid.grid, full.grid)
    # Recording does not change the run.
    assert full.summary["counters"] == grid.summary["counters"] == none.summary["counters"]
    assert full.summary["maxima"] == none.summary["maxima"]
    assert full.final["q_WB"] == none.final["q_WB"]
    with pytest.raises(rigidae.InputError, match="record='all'"):
        rigidae.solve(HEAVY_TOP, record="all")
