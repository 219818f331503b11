"""compare, study and the closed-form references from Python."""
import numpy as np
import pytest

import rigidae
from rigidae import _scene_dict
from conftest import HEAVY_TOP, SOURCE, read_csv, run_cli


def columns(table):
    return list(table.columns) if hasattr(table, "columns") else list(table)


def column(table, name):
    return np.asarray(table[name])


def test_compare_table_is_compare_csv(tmp_path):
    opts = dict(only="quaternion/euler/*", skip="projection,index3", repeat=1, t_end=0.3)
    table = rigidae.compare(HEAVY_TOP, out=tmp_path / "py", **opts)
    code, _, err = run_cli("compare", HEAVY_TOP, "--only", opts["only"], "--skip", opts["skip"], "--repeat", "1",
                           "--t-end", "0.3", "--out", tmp_path / "cli", "--quiet")
    assert code == 0, err
    _, header, rows = read_csv(tmp_path / "cli" / "compare.csv")
    assert columns(table) == header
    assert list(column(table, "combination")) == [r[0] for r in rows] == [
        "quaternion/euler/index2", "quaternion/euler/index1", "quaternion/euler/baumgarte", "quaternion/euler/ggl"]
    assert list(column(table, "steps")) == [int(r[header.index("steps")]) for r in rows]
    assert column(table, "steps").dtype == np.int64
    assert np.array_equal(column(table, "error_final_rad"), [float(r[header.index("error_final_rad")]) for r in rows])
    # Without out, nothing is left behind and the table is the same.
    again = rigidae.compare(HEAVY_TOP, as_dataframe=False, **opts)
    assert list(again["steps"]) == list(column(table, "steps"))
    with pytest.raises(rigidae.InputError, match="does not apply to compare"):
        rigidae.compare(HEAVY_TOP, scheme="ggl")


def test_exact_solution_against_a_tight_run():
    run = rigidae.solve(HEAVY_TOP, coordinates="quaternion", equations="euler", scheme="ggl", rtol=1e-11,
                        atol=1e-11, record="grid")
    exact = rigidae.exact_solution(HEAVY_TOP, run.grid["t"])
    assert list(exact.dtype.names) == ["t", "qw", "qx", "qy", "qz", "omega_x", "omega_y", "omega_z"]
    # At the start: the scene's initial state.
    assert np.allclose([exact[c][0] for c in ("qw", "qx", "qy", "qz")], [1, 0, 0, 0], atol=1e-14)
    assert np.allclose([exact[c][0] for c in ("omega_x", "omega_y", "omega_z")], [0, 150, -4.61538], atol=1e-12)
    angle = rigidae.quaternion_angle(run.grid, exact)
    # README: quaternion/euler/ggl at rtol 1e-10 is 3.5e-7 rad from the reference at 2 s; 1e-11 is tighter.
    assert angle.max() < 1e-6
    assert np.abs(run.grid["omega_y"] - exact["omega_y"]).max() < 1e-4
    # An asymmetric heavy top has no closed form; the message says why.
    asymmetric = rigidae.read_scene_dict(HEAVY_TOP)
    asymmetric["body"]["inertia_principal"] = [0.2, 0.46875, 0.3]
    with pytest.raises(rigidae.InputError, match="no closed-form solution: .+"):
        rigidae.exact_solution(asymmetric, [0.0])


def test_quaternion_angle_is_the_rotation_angle():
    for angle in (1e-9, 0.3, 2.0, np.pi):
        q = [np.cos(angle / 2), 0.0, np.sin(angle / 2), 0.0]
        assert abs(rigidae.quaternion_angle(np.array([1.0, 0, 0, 0]), np.array(q)) - angle) < 1e-15 * max(1, angle) * 4
        assert abs(rigidae.quaternion_angle(np.array(q), -np.array(q))) == 0.0


STUDY = """schema_version = 1
name = "tiny"
scenes = ["{scene}"]
reference = "exact"
[grid]
combinations = ["quaternion/euler/ggl", "euler/euler/any"]
rtol = [1e-6, 1e-8]
atol = "rtol"
[timing]
warmups = 0
repeats = 1
"""


def test_study_results_table(tmp_path):
    scene = rigidae.read_scene_dict(HEAVY_TOP)
    scene["time"]["end"] = 0.3
    scene_file = tmp_path / "top.toml"
    scene_file.write_text(_scene_dict.to_toml(scene)[0])
    study_file = tmp_path / "tiny.toml"
    study_file.write_text(STUDY.format(scene=scene_file))
    seen = []
    table = rigidae.study(study_file, out=tmp_path / "out", progress=lambda *p: seen.append(p))
    assert len(column(table, "combination")) == 4 and seen[-1][0] == seen[-1][3] == 4
    assert set(column(table, "status")) == {"success"}
    err = column(table, "orientation_error_final_rad")
    rtol = column(table, "rtol")
    # Tighter tolerance, smaller error, per combination.
    for combo in set(column(table, "combination")):
        pick = column(table, "combination") == combo
        e, r = err[pick], rtol[pick]
        assert e[np.argmin(r)] < e[np.argmax(r)]
    # The CLI collects the same folder into the same results.csv.
    assert columns(rigidae.read_study(tmp_path / "out")) == read_csv(tmp_path / "out" / "results.csv")[1]
    code, _, errtext = run_cli("study", "collect", study_file, "--out", tmp_path / "out", "--no-plot", "--quiet")
    assert code == 0, errtext
    again = rigidae.read_study(tmp_path / "out", as_dataframe=False)
    assert list(again["steps"]) == list(column(table, "steps"))

