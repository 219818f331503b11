"""Error against time for a multibody compare (schema-2 scenes): compare keeps the tight reference's
per-body grid as reference.csv, and tools/plot_compare.py draws each run's worst-body orientation and
centre-of-mass error from it. The figure's data at the final time must be what compare.csv reports,
recomputed here independently (rotation matrices instead of quaternions) from the files, and the
error must fall when the tolerance does."""
import csv
import json
import math
import sys

import numpy as np
import pytest

from conftest import SOURCE, read_csv, run_cli

sys.path.insert(0, str(SOURCE / "tools"))
import plot_compare  # noqa: E402

DOUBLE_PENDULUM = SOURCE / "problems" / "double_pendulum.toml"
FOUR_BAR = SOURCE / "problems" / "four_bar.toml"
BODY_COLUMNS = ("qw", "qx", "qy", "qz", "wx", "wy", "wz", "x", "y", "z")


@pytest.fixture(scope="module")
def compare_dir(tmp_path_factory):
    """Every IDA combination (36) of the double pendulum for 0.3 s, with --plot (a pattern without
    @INTEGRATOR selects IDA rows: the ODE integrators' rows are left out, as the figures' run names
    below carry no integrator)."""
    out = tmp_path_factory.mktemp("mbcmp") / "double_pendulum"
    code, _, err = run_cli("compare", DOUBLE_PENDULUM, "--t-end", "0.3", "--repeat", "1", "--out", out, "--plot",
                           "--only", "*/*/*", "--quiet")
    assert code == 0, err
    return out


def columns(path):
    """{name: float array} of a rigidae CSV (units line first)."""
    with open(path, newline="") as f:
        f.readline()
        reader = csv.reader(f)
        names = next(reader)
        rows = np.array([[float(x) for x in r] for r in reader if len(r) == len(names)])
    return {n: rows[:, k] for k, n in enumerate(names)}


def compare_rows(folder):
    _, header, rows = read_csv(folder / "compare.csv")
    return [dict(zip(header, r)) for r in rows]


def rotation(q):
    """Rotation matrices (N x 3 x 3) from unit quaternions (N x 4, scalar first), written out here."""
    q = q / np.linalg.norm(q, axis=1)[:, None]
    w, x, y, z = q.T
    R = np.empty((q.shape[0], 3, 3))
    R[:, 0] = np.stack([w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)], 1)
    R[:, 1] = np.stack([2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)], 1)
    R[:, 2] = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z], 1)
    return R


def worst_errors(run, ref, bodies):
    """Per grid point the largest rotation angle and centre-of-mass distance over the bodies:
    |R - R_ref|_F = 2 sqrt(2) sin(angle / 2), accurate for small angles."""
    n = min(run["t"].size, ref["t"].size)
    assert np.array_equal(run["t"][:n], ref["t"][:n])
    angle, dist = np.zeros(n), np.zeros(n)
    for b in bodies:
        R = rotation(np.stack([run[f"{b}.{c}"][:n] for c in ("qw", "qx", "qy", "qz")], 1))
        Rr = rotation(np.stack([ref[f"{b}.{c}"][:n] for c in ("qw", "qx", "qy", "qz")], 1))
        s = np.linalg.norm(R - Rr, axis=(1, 2)) / (2 * math.sqrt(2))
        angle = np.maximum(angle, 2 * np.arcsin(np.clip(s, 0, 1)))
        x = np.stack([run[f"{b}.{c}"][:n] for c in "xyz"], 1)
        xr = np.stack([ref[f"{b}.{c}"][:n] for c in "xyz"], 1)
        dist = np.maximum(dist, np.linalg.norm(x - xr, axis=1))
    return angle, dist


def figure_data(folder, run_dir):
    """The series the error figures draw for one run (plot_compare's own loading)."""
    ref, _ = plot_compare.read_reference(str(folder))
    assert ref is not None and ref["multibody"]
    return plot_compare.load_series((str(folder / run_dir), 1000, ref, None))


def test_reference_csv_is_the_tight_run_per_body(compare_dir):
    """reference.csv: t, then per body BODY.qw..qz, wx..wz, x..z, the same numbers as the tight run's
    own trajectory.csv (reference/), starting at the scene's pose. The angular velocities go through
    the body frame (the grid rigidae reads every run into holds omega_B, record/trajectory_csv.hpp)
    and back: equal to the last few ulps, the rest bit for bit."""
    _, header, _ = read_csv(compare_dir / "reference.csv")
    assert header == ["t"] + [f"{b}.{c}" for b in ("upper", "lower") for c in BODY_COLUMNS]
    ref = columns(compare_dir / "reference.csv")
    tight = columns(compare_dir / "reference" / "trajectory.csv")
    for name in header:
        if name.split(".")[-1] in ("wx", "wy", "wz"):
            scale = max(1.0, float(np.max(np.abs(tight[name]))))
            assert np.max(np.abs(ref[name] - tight[name])) <= 8 * np.finfo(float).eps * scale, name
        else:
            assert np.array_equal(ref[name], tight[name]), name
    assert ref["t"][-1] == pytest.approx(0.3)
    # double_pendulum.toml: upper's centre of mass at (0.25, 0, 0), lower's at (0.5, 0.2, 0), unrotated
    assert [ref["upper.x"][0], ref["upper.y"][0], ref["lower.x"][0], ref["lower.y"][0]] == [0.25, 0, 0.5, 0.2]
    assert [ref["lower.qw"][0], ref["lower.qx"][0]] == [1, 0]
    with open(compare_dir / "reference.csv") as f:
        assert "reference: quaternion/euler/ggl at rtol 1e-12" in f.readline()


def test_figure_data_is_the_compare_error_at_the_end(compare_dir):
    """For every run: the error figures' last point and maximum equal compare.csv's error_final_rad,
    error_max_rad, error_position_final_m and error_position_max_m, and an independent recomputation
    from trajectory.csv and reference.csv gives the same numbers."""
    ref = columns(compare_dir / "reference.csv")
    rows = compare_rows(compare_dir)
    assert len(rows) == 36
    for r in rows:
        assert r["status"] == "success", r["combination"]
        data = figure_data(compare_dir, r["run_dir"])
        angle, dist = worst_errors(columns(compare_dir / r["run_dir"] / "trajectory.csv"), ref, ("upper", "lower"))
        assert angle[0] < 1e-12 and dist[0] < 1e-12
        for key, mine, final, peak in (("error", angle, "error_final_rad", "error_max_rad"),
                                       ("error_position", dist, "error_position_final_m", "error_position_max_m")):
            t_last, e_last = data["last"][key]
            assert t_last == pytest.approx(0.3)
            assert e_last == pytest.approx(float(r[final]), rel=1e-5), (r["combination"], key)
            assert mine[-1] == pytest.approx(float(r[final]), rel=1e-5, abs=1e-13), (r["combination"], key)
            assert data["stats"][key]["max"] == pytest.approx(float(r[peak]), rel=1e-5), (r["combination"], key)
            assert mine.max() == pytest.approx(float(r[peak]), rel=1e-5, abs=1e-13), (r["combination"], key)
            # the decimated line keeps the peak and the last point
            t, y = data["series"][key]["max"]
            assert y.max() == data["stats"][key]["max"] and y[-1] == e_last


def test_error_figures_are_written_and_identical_runs_named(compare_dir):
    """error.png and error_position.png (and PDFs), six panels of six schemes; runs named identical in
    identical_runs.json have the same steps and errors in compare.csv."""
    for name in ("error", "error_position"):
        for ext in ("png", "pdf"):
            path = compare_dir / "figures" / f"{name}.{ext}"
            assert path.stat().st_size > 5000, path
    with open(compare_dir / "figures" / "identical_runs.json") as f:
        pairs = json.load(f)["pairs"]
    by_name = {r["combination"]: r for r in compare_rows(compare_dir)}
    identical = [p for p in pairs if p["until"] is None]
    assert identical, "projection is index1 until a projection happens: some pair is expected"
    for p in identical:
        a, b = by_name[p["run"]], by_name[p["same_as"]]
        for key in ("steps", "error_final_rad", "error_position_final_m", "residual_evals"):
            assert a[key] == b[key], (p, key)
    for p in pairs:  # "until" pairs part: their step counts or errors differ
        if p["until"] is not None:
            a, b = by_name[p["run"]], by_name[p["same_as"]]
            assert (a["steps"], a["error_final_rad"]) != (b["steps"], b["error_final_rad"]), p


def test_error_falls_when_the_tolerance_falls(tmp_path):
    """The four-bar linkage (a closed loop) at rtol = atol 1e-5 and 1e-8: each run's largest error over
    time, as the figure draws it, falls by more than 100 (measured 375 to 13000 over 1 s)."""
    only = "quaternion/euler/ggl,linear/lagrange/index2,euler/lagrange/baumgarte"
    peaks = {}
    for tol in ("1e-5", "1e-8"):
        out = tmp_path / f"four_bar_{tol}"
        code, _, err = run_cli("compare", FOUR_BAR, "--t-end", "1", "--rtol", tol, "--atol", tol, "--only", only,
                               "--repeat", "1", "--out", out, "--quiet")
        assert code == 0, err
        for r in compare_rows(out):
            data = figure_data(out, r["run_dir"])
            peaks[(tol, r["combination"])] = (data["stats"]["error"]["max"], data["stats"]["error_position"]["max"])
    for combination in only.split(","):
        loose, tight = peaks[("1e-5", combination)], peaks[("1e-8", combination)]
        for k in range(2):
            assert tight[k] < loose[k] / 100, (combination, loose, tight)
            assert tight[k] > 0
