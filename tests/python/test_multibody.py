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
PARTICLE_PENDULUM = str(SOURCE / "problems" / "particle_pendulum.toml")


@pytest.mark.parametrize("scene,options", [
    (DOUBLE_PENDULUM, dict(t_end=0.5)),
    (HEAVY_TOP_ABSOLUTE, dict(t_end=0.2, coordinates="euler", scheme="index2")),
    # The ODE integrators run mechanisms from Python as from the CLI.
    (DOUBLE_PENDULUM, dict(t_end=0.5, integrator="cvode-adams", scheme="projection")),
    (HEAVY_TOP_ABSOLUTE, dict(t_end=0.2, integrator="arkode-erk", scheme="index1", rtol=1e-4, atol=1e-4)),
    # A run the accuracy check warns about (the plain ODE's energy drift).
    (PARTICLE_PENDULUM, dict(t_end=10.0, integrator="cvode-adams", scheme="index1", rtol=1e-6, atol=1e-6)),
], ids=["double_pendulum", "heavy_top_absolute/euler/index2", "double_pendulum/cvode-adams",
        "heavy_top_absolute/arkode-erk/index1/loose", "particle_pendulum/cvode-adams/index1/warned"])
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
    assert run.summary["integrator"] == cli["integrator"]
    # The accuracy check's warnings and the verdict's, as the CLI's summary.json lists them.
    assert [w["message"] for w in run.summary["warnings"]] == [w["message"] for w in cli["warnings"]]
    # The verdict too (the module names the CLI's option where it has no closed form).
    py_verdict, cli_verdict = dict(run.summary["error_estimate"]), dict(cli["error_estimate"])
    assert py_verdict.pop("not_estimated").startswith(cli_verdict.pop("not_estimated")[:40])
    assert py_verdict == cli_verdict
    if scene == PARTICLE_PENDULUM:
        # The energy drift, and the closed form's verdict (the simple pendulum): 7.7e-4 m off at rtol 1e-6.
        assert [w["quantity"] for w in run.summary["warnings"]] == ["energy", "position_error"]
        assert run.summary["error_estimate"]["source"] == "closed form"

    _, header, rows = read_csv(tmp_path / "cli" / "trajectory.csv")
    assert list(run.grid.dtype.names) == header
    table = np.array([[float(x) for x in r] for r in rows])
    assert table.shape == (len(run.grid), len(header))
    for i, name in enumerate(header):
        np.testing.assert_array_equal(run.grid[name], table[:, i], err_msg=name)
    # The per-body and per-joint views are the same columns.
    for b in run.bodies:
        np.testing.assert_array_equal(run.body(b)["x"][:, 2], table[:, header.index(f"{b}.z")])
        if f"{b}.qw" in header:  # a particle has no rotation columns
            np.testing.assert_array_equal(run.body(b)["q"][:, 0], table[:, header.index(f"{b}.qw")])
        else:
            assert "q" not in run.body(b)
    for j in run.joints:
        np.testing.assert_array_equal(run.joint(j)["force"][:, 2], table[:, header.index(f"{j}.force_z")])
        # Its residuals and coordinates (JOINT.angle, ...) under their column names.
        scalars = {k: v for k, v in run.joint(j).items() if k not in ("t", "force", "torque")}
        assert {"residual_position", "residual_velocity"} <= set(scalars)
        for key, values in scalars.items():
            np.testing.assert_array_equal(values, table[:, header.index(f"{j}.{key}")], err_msg=f"{j}.{key}")

    _, step_header, step_rows = read_csv(tmp_path / "cli" / "steps.csv")
    steps = np.array([[float(x) for x in r] for r in step_rows])
    assert len(run.steps) == len(steps)
    # Every column of steps.csv, the per-step multipliers and reactions too.
    assert list(run.steps.dtype.names) == step_header
    for i, name in enumerate(step_header):
        np.testing.assert_array_equal(run.steps[name], steps[:, i], err_msg=name)
    for j in run.joints:
        np.testing.assert_array_equal(run.joint_steps(j)["force"][:, 2], steps[:, step_header.index(f"{j}.force_z")])
    assert run.summary["multipliers_error_controlled"] == cli["multipliers_error_controlled"] is False
    assert run.summary["multipliers_error_note"] == cli["multipliers_error_note"]


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
    # summary.json is written, and it is the run's summary.
    written = read_summary(tmp_path / "py")
    assert run.summary == written
    assert written["status"] == "success" and written["counters"]["steps"] == run.counters["steps"]
    _, header, rows = read_csv(tmp_path / "py" / "trajectory.csv")
    assert header == list(run.grid.dtype.names)
    assert len(rows) == len(run.grid)
    np.testing.assert_array_equal(np.array([float(r[-1]) for r in rows]), run.grid[header[-1]])


def test_per_step_reactions_obey_newton_on_the_lower_bar():
    """The elbow's reaction on the lower bar at every step is m (a - g) of the
    bar's centre of mass (the only other force on it is gravity). a comes from
    the output grid's velocities by central differences, on a grid fine
    enough (1e-4 s) that their O(dt^2) error is small; the per-step rows that
    fall between two grid points are compared with the difference quotient
    there, so the check is independent of how the reactions are computed."""
    run = rigidae.solve(DOUBLE_PENDULUM, t_end=0.05, output_step=1e-4, rtol=1e-11, atol=1e-11)
    lower_mass = 0.8
    g = np.array([0.0, 0.0, -9.81])
    t = run.grid["t"]
    v = run.body("lower")["v"]
    a = (v[2:] - v[:-2]) / (t[2:] - t[:-2])[:, None]  # at t[1:-1]
    elbow = run.joint_steps("elbow")
    checked = 0
    for k, tk in enumerate(elbow["t"]):
        if not (t[1] <= tk <= t[-2]):
            continue
        ak = np.array([np.interp(tk, t[1:-1], a[:, c]) for c in range(3)])
        expected = lower_mass * (ak - g)
        assert np.allclose(elbow["force"][k], expected, rtol=0, atol=1e-4 * np.linalg.norm(expected)), tk
        checked += 1
    assert checked > 10


def test_exact_solution_of_a_mechanism_is_an_error():
    with pytest.raises(rigidae.InputError, match="bodies and joints"):
        rigidae.exact_solution(DOUBLE_PENDULUM, [0.0, 0.1])
