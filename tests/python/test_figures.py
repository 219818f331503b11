"""The figures of compare --plot, solve --plot and tools/plot_study.py: every file written and
non-empty, and identical runs detected (and only those)."""
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import HEAVY_TOP, SOURCE, read_csv, run_cli

sys.path.insert(0, str(SOURCE / "tools"))
import identical_runs  # noqa: E402
import plot_compare  # noqa: E402

COMPARE_FIGURES = ["error", "drift_position", "drift_velocity", "multipliers", "energy_error", "momentum_error",
                   "step_size", "order", "axis_trace", "summary"]


@pytest.fixture(scope="module")
def compare_dir(tmp_path_factory):
    """A short compare of the Euler-form quaternion runs with --plot (a few seconds)."""
    out = tmp_path_factory.mktemp("cmp") / "heavy_top"
    code, _, err = run_cli("compare", HEAVY_TOP, "--only", "quaternion/euler/*", "--repeat", "1", "--t-end", "0.1",
                           "--out", out, "--plot", "--quiet")
    assert code == 0, err
    return out


def test_compare_plot_writes_every_figure_as_png_and_pdf(compare_dir):
    for name in COMPARE_FIGURES:
        for ext in ("png", "pdf"):
            path = compare_dir / "figures" / f"{name}.{ext}"
            assert path.is_file(), path
            assert path.stat().st_size > 5000, path  # an empty matplotlib page is ~1-2 kB
    with open(compare_dir / "figures" / "error.png", "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    with open(compare_dir / "figures" / "error.pdf", "rb") as f:
        assert f.read(5) == b"%PDF-"


def test_compare_keeps_the_reference_on_the_output_grid(compare_dir):
    """reference.csv is the closed form: at t = 0 the scene's initial state, and every run's trajectory.csv
    is on the same grid; the error the figures draw at the end is compare.csv's error_final_rad."""
    _, header, rows = read_csv(compare_dir / "reference.csv")
    assert header == ["t", "qw", "qx", "qy", "qz", "omega_x", "omega_y", "omega_z"]
    ref = np.array(rows, dtype=float)
    assert np.allclose(ref[0, 1:5], [1, 0, 0, 0], atol=1e-14)
    assert np.allclose(ref[0, 5:8], [0, 150, -4.61538], atol=1e-12)
    _, cheader, crows = read_csv(compare_dir / "compare.csv")
    grid_ref = plot_compare.read_grid(str(compare_dir / "reference.csv"))
    for row in crows:
        r = dict(zip(cheader, row))
        grid = plot_compare.read_grid(str(compare_dir / r["run_dir"] / "trajectory.csv"))
        assert np.array_equal(grid["t"], grid_ref["t"])
        _, angle = plot_compare.grid_error(grid, grid_ref)
        assert angle[0] < 1e-12
        assert math.isclose(angle[-1], float(r["error_final_rad"]), rel_tol=1e-3, abs_tol=1e-12)


def test_quaternion_angle_is_the_rotation_angle():
    for angle in (1e-9, 0.3, 2.0, 3.0):
        axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
        p = np.r_[math.cos(angle / 2), math.sin(angle / 2) * axis][None, :]
        r = np.array([[1.0, 0, 0, 0]])
        assert abs(plot_compare.quaternion_angle(p, r)[0] - angle) < 4e-16 * max(1, angle)
        # the same relative rotation seen from another frame: left-multiplying both keeps the angle
        c = np.r_[math.cos(0.4), math.sin(0.4) * np.array([1.0, 0, 0])]
        mul = lambda a, b: np.r_[a[0] * b[0] - a[1:] @ b[1:], a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:])]
        assert abs(plot_compare.quaternion_angle(mul(c, p[0])[None], mul(c, r[0])[None])[0] - angle) < 1e-14


def test_identical_runs_are_labelled_and_different_ones_are_not(compare_dir):
    """In the Euler form index3 and ggl assemble the same rows (README, 'Choosing a scheme'): their step
    histories are equal bit for bit. index2 is another DAE: it must not be called the same as anything."""
    pairs = json.loads((compare_dir / "figures" / "identical_runs.json").read_text())["pairs"]
    by_run = {p["run"]: p for p in pairs}
    assert by_run["quaternion/euler/index3"]["same_as"] == "quaternion/euler/ggl"
    assert by_run["quaternion/euler/index3"]["until"] is None
    assert "quaternion/euler/index2" not in by_run
    assert "quaternion/euler/ggl" not in by_run  # the one drawn
    assert "quaternion/euler/baumgarte" not in by_run
    # The detection agrees with the files themselves (their rows: the units
    # line names the scheme in its note on multipliers).
    def rows(name):
        return [l for l in (compare_dir / name / "steps.csv").read_bytes().splitlines() if not l.startswith(b"#")]
    a, b, c = rows("quaternion-euler-index3"), rows("quaternion-euler-ggl"), rows("quaternion-euler-index2")
    assert len(a) > 100 and a == b and a != c


def test_same_until_a_projection(tmp_path):
    """projection is index1 until its first projection: forced at every step, the histories part at the
    first step that is projected, and the detection says 'until' with the time of the last shared step."""
    out = tmp_path / "p"
    code, _, err = run_cli("compare", HEAVY_TOP, "--only", "linear/euler/index1,linear/euler/projection",
                           "--repeat", "1", "--t-end", "0.05", "--out", out, "--keep-steps", "--quiet")
    assert code == 0, err
    runs = [(n, str(out / n), ("linear", "euler")) for n in ("linear-euler-index1", "linear-euler-projection")]
    same = identical_runs.find_identical(runs)
    steps_i = np.genfromtxt(out / "linear-euler-index1" / "steps.csv", delimiter=",", names=True, skip_header=1)
    steps_p = np.genfromtxt(out / "linear-euler-projection" / "steps.csv", delimiter=",", names=True, skip_header=1)
    n = min(len(steps_i), len(steps_p))
    differ = np.flatnonzero((steps_i["t"][:n] != steps_p["t"][:n]) | (steps_i["qw"][:n] != steps_p["qw"][:n]))
    summary = json.loads((out / "linear-euler-projection" / "summary.json").read_text())
    if summary["counters"]["projections"] == 0:
        assert same["linear-euler-projection"]["until"] is None
    else:
        assert differ.size > 0
        rel = same.get("linear-euler-projection")
        if differ[0] >= identical_runs.MIN_SHARED_STEPS:
            assert rel["same_as"] == "linear-euler-index1"
            assert rel["until"] == steps_i["t"][differ[0] - 1]
        else:
            assert rel is None


def test_solve_plot_draws_the_error_against_the_closed_form(tmp_path):
    out = tmp_path / "run"
    code, _, err = run_cli("solve", HEAVY_TOP, "--t-end", "0.1", "--out", out, "--plot", "--quiet")
    assert code == 0, err
    for ext in ("png", "pdf"):
        assert (out / "figures" / f"run.{ext}").stat().st_size > 5000
    grid = plot_compare.read_grid(str(out / "trajectory.csv"))
    ref = plot_compare.read_grid(str(out / "reference.csv"))
    _, angle = plot_compare.grid_error(grid, ref)
    # README: the default quaternion/euler/ggl at rtol 1e-8 is ~1e-5 rad off after 2 s; after 0.1 s far less
    assert 0 < angle[-1] < 1e-5


def test_study_figures_are_faceted_and_name_identical_schemes(tmp_path):
    """The committed heavy-top study: three figures per scene, and the identical-scheme rule finds index3 = ggl
    in the Euler forms (equal counters at every tolerance) and nothing in the Lagrange forms."""
    study = SOURCE / "docs" / "studies" / "heavy_top"
    # three of the nine tolerances are enough to draw (and quicker)
    lines = (study / "results.csv").read_text().splitlines(keepends=True)
    small = tmp_path / "study"
    small.mkdir()
    keep = [l for l in lines[2:] if ",0.0001,0.0001," in l or ",1e-07,1e-07," in l or ",1e-10,1e-10," in l]
    combinations = {l.split(",")[2] for l in lines[2:] if l.strip()}  # every combination, each integrator's
    assert len(keep) == 3 * len(combinations) and len(combinations) >= 26
    (small / "results.csv").write_text("".join(lines[:2] + keep))
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "plot_study.py"), str(small), "--figures",
                        str(tmp_path), "--quiet"], capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    for name in ("work_precision", "error_vs_evals", "error_vs_rtol"):
        for ext in ("png", "pdf"):
            assert (tmp_path / f"heavy_top_{name}.{ext}").stat().st_size > 5000
    import plot_study
    rows = plot_study.read_results(study / "results.csv")
    same = plot_study.identical_schemes(rows, "orientation_error_final_rad")
    assert same.get(("quaternion", "euler", "index3", "ida")) == "ggl"
    assert same.get(("linear", "euler", "index3", "ida")) == "ggl"
    assert not any(e == "lagrange" for (_, e, _, _) in same)


def test_study_figures_draw_each_integrator_as_its_own_line_with_error_on_x(tmp_path, monkeypatch):
    """IDA's and ARKODE's runs of one scheme are two lines (never one zig-zag), told apart by
    line style in the same colour, and a work-precision panel has the error on x and the wall
    time on y (SciML's orientation)."""
    import plot_study
    import plot_compare as pc
    rows = []
    for integ, times in (("ida", (0.01, 0.02, 0.04)), ("arkode-erk", (0.002, 0.003, 0.005))):
        for rtol, err, wall in zip(("1e-4", "1e-6", "1e-8"), (1e-3, 1e-5, 1e-7), times):
            rows.append(dict(scene="s", coordinates="quaternion", equations="euler", scheme="projection",
                             integrator=integ, rtol=rtol, atol=rtol, status="success", wall_min_s=str(wall),
                             orientation_error_final_rad=str(err), steps="10", residual_evals="20",
                             jacobian_residual_evals="0"))
    kept = []
    monkeypatch.setattr(pc, "save", lambda fig, path: kept.append(fig))
    plot_study.draw(rows, "s", "orientation_error_final_rad", lambda r: float(r["wall_min_s"]), "wall time  (s)",
                    "wall time against error", str(tmp_path / "wp.png"))
    ax = kept[0].axes[0]
    lines = [l for l in ax.get_lines() if len(l.get_xdata()) == 3]
    assert len(lines) == 2
    assert lines[0].get_color() == lines[1].get_color()
    assert lines[0].get_linestyle() != lines[1].get_linestyle()
    by_time = sorted(lines, key=lambda l: max(l.get_ydata()))
    assert sorted(by_time[0].get_ydata()) == [0.002, 0.003, 0.005]  # ARKODE's wall times on y
    assert sorted(by_time[1].get_xdata()) == [1e-7, 1e-5, 1e-3]  # the errors on x
    assert "error" in ax.get_xlabel() and "wall time" in ax.get_ylabel()


def test_solve_plot_of_a_multibody_scene(tmp_path):
    """A mechanism has no closed form: no reference.csv, and the page draws what steps.csv has."""
    out = tmp_path / "mb"
    code, _, err = run_cli("solve", SOURCE / "problems" / "four_bar.toml", "--t-end", "0.1", "--out", out, "--plot",
                           "--quiet")
    assert code == 0, err
    assert not (out / "reference.csv").exists()
    assert (out / "figures" / "run.png").stat().st_size > 5000
    assert "warning" not in err


def test_sphere_view_sees_a_circle_face_on_enough():
    """A body axis turning in the x-z plane (a spin about y) must not be drawn edge-on: the view direction
    keeps a component along the circle's normal y."""
    u = np.linspace(0, 4.0, 200)
    xyz = np.stack([np.cos(u), np.zeros_like(u), np.sin(u)], 1)
    elev, azim = plot_compare.sphere_view(xyz)
    v = np.array([np.cos(np.radians(elev)) * np.cos(np.radians(azim)),
                  np.cos(np.radians(elev)) * np.sin(np.radians(azim)), np.sin(np.radians(elev))])
    assert abs(v[1]) > 0.5


def test_long_subtitles_and_panel_notes_stay_on_the_page(tmp_path, monkeypatch):
    """matplotlib does not clip a figure's text: a subtitle or an identical-run note longer than
    the page ran off it (one-panel compare figures, the studies' right-hand panels). Every text
    drawn must lie inside the figure."""
    kept = []
    monkeypatch.setattr(plot_compare, "save", lambda fig, path: kept.append(fig))
    fig, axes = plot_compare.new_figure(1, 1)
    ax = axes[0, 0]
    ax.plot([0, 1], [1e-8, 1e-4])
    note = "projection (arkode-erk:fehlberg78) = index1 (arkode-erk:fehlberg78) (same counts and errors; drawn once)"
    plot_compare.panel_title(ax, "quaternion / euler", ["linear/euler/index3 (cvode-bdf) failed at t = 0.25 s: " + note],
                             [note, note.replace("projection", "baumgarte")])
    subtitle = ("rtol 1e-8, atol 1e-8; 12 runs\nangle between each run's orientation and the reference (exact: "
                "Lagrange top) at every output time; largest value per time bin; values below 1e-10 (incl. exact "
                "zeros) drawn at 1e-10")
    plot_compare.finish_figure(fig, "heavy_top: orientation error against time", subtitle, [], str(tmp_path / "x.png"))
    [fig] = kept
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    texts = [t for t in fig.texts + ax.texts + [ax.title] if t.get_text()]
    assert len(texts) >= 6  # title, subtitle, the wrapped notes, the panel label
    for t in texts:
        box = t.get_window_extent(renderer)
        assert page.x0 - 0.5 <= box.x0 and box.x1 <= page.x1 + 0.5, (t.get_text(), box, page)
        assert page.y0 - 0.5 <= box.y0 and box.y1 <= page.y1 + 0.5, (t.get_text(), box, page)
    # Wrapped, not dropped: every word of the notes is drawn.
    drawn = " ".join(t.get_text() for t in ax.texts)
    assert drawn.count("drawn once") == 3
