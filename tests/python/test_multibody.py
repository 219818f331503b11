"""rigidae.solve on multibody scenes (schema_version 2): the module's
per-body and per-joint arrays equal the CLI's trajectory.csv value for value
(the CSV holds the shortest text that reads back to the same double), the
counters equal summary.json's, and the heavy top's pivot reaction at t = 0
is the literature's 450.28 N (Bruls, Cardona & Arnold 2012)."""
import numpy as np
import pytest

import rigidae
from conftest import SOURCE, read_csv, read_summary, run_cli

DOUBLE_PENDULUM = str(SOURCE / "problems" / "double_pendulum.toml")
HEAVY_TOP_ABSOLUTE = str(SOURCE / "problems" / "heavy_top_absolute.toml")


@pytest.mark.parametrize("scene,options", [
    (DOUBLE_PENDULUM, dict(t_end=0.5)),
    (HEAVY_TOP_ABSOLUTE, dict(t_end=0.2, coordinates="euler", scheme="index2")),
], ids=["double_pendulum", "heavy_top_absolute/euler/index2"])
def test_multibody_module_equals_cli(scene, options, tmp_path):
    args = []
    for k, v in options.items():
        args += ["--" + k.replace("_", "-"), str(v)]
    code, _, err = run_cli("solve", scene, "--out", tmp_path / "cli", "--quiet", *args)
    assert code == 0, err
    cli = read_summary(tmp_path / "cli")
    run = rigidae.solve(scene, **options)
    assert isinstance(run, rigidae.MultibodyRun)
    assert run.ok
    for k, v in run.counters.items():
        assert v == cli["counters"][k], k
    assert run.summary["linear_solver"] == cli["linear_solver"]

    _, header, rows = read_csv(tmp_path / "cli" / "trajectory.csv")
    assert list(run.grid.dtype.names) == header
    table = np.array([[float(x) for x in r] for r in rows])
    assert table.shape == (len(run.grid), len(header))
    for i, name in enumerate(header):
        np.testing.assert_array_equal(run.grid[name], table[:, i], err_msg=name)
    # The per-body and per-joint views are the same columns.
    for b in run.bodies:
        np.testing.assert_array_equal(run.body(b)["q"][:, 0], table[:, header.index(f"{b}.qw")])
    for j in run.joints:
        np.testing.assert_array_equal(run.joint(j)["force"][:, 2], table[:, header.index(f"{j}.force_z")])

    _, step_header, step_rows = read_csv(tmp_path / "cli" / "steps.csv")
    steps = np.array([[float(x) for x in r] for r in step_rows])
    assert len(run.steps) == len(steps)
    for i, name in enumerate(step_header[:6]):
        np.testing.assert_array_equal(run.steps[name], steps[:, i], err_msg=name)


def test_heavy_top_pivot_reaction_at_start():
    run = rigidae.solve(HEAVY_TOP_ABSOLUTE, t_end=0.05, record="grid")
    force = run.joint("pivot")["force"]
    # m (a_c - g) = (0, -319.526, -317.262) N, |F| = 450.28 N in the literature.
    assert np.linalg.norm(force[0]) == pytest.approx(450.28, rel=1e-4)
    assert force[0] == pytest.approx([0.0, -319.526, -317.262], abs=2e-2)
    with pytest.raises(KeyError, match="pivot"):
        run.joint("pivt")


def test_multibody_out_writes_the_cli_files(tmp_path):
    run = rigidae.solve(DOUBLE_PENDULUM, t_end=0.2, out=tmp_path / "py")
    _, header, rows = read_csv(tmp_path / "py" / "trajectory.csv")
    assert header == list(run.grid.dtype.names)
    assert len(rows) == len(run.grid)
    np.testing.assert_array_equal(np.array([float(r[-1]) for r in rows]), run.grid[header[-1]])
