"""Every stop keeps what was computed and says why (docs/robustness.md,
"Exit codes" and "Solver failures and interruptions"): real signals sent to
the real CLI (GNU timeout's TERM to the process and then to its group), the
step-size floor, --t-end against output.times, compare's per-run time limit
and failed reference, a study's leftovers of killed runs, an output folder
that cannot be written, and a full device.

Exit codes under test: 0 success, 1 a run failed, stalled, timed out or was
interrupted, or output was lost (what was computed is kept), 2 bad input
(nothing run)."""
import csv
import json
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from pathlib import Path

import pytest

from conftest import CLI, HEAVY_TOP, SOURCE, read_summary, run_cli

FREE_BODY = str(SOURCE / "problems" / "free_body.toml")
DOUBLE_PENDULUM = str(SOURCE / "problems" / "double_pendulum.toml")


def wait_for(path, seconds=30):
    deadline = time.monotonic() + seconds
    while not Path(path).exists():
        assert time.monotonic() < deadline, f"{path} never appeared"
        time.sleep(0.01)


def rows_of(csv_path):
    """Rows of a CSV the CLI wrote ('#' lines skipped), each checked whole:
    as many cells as the header, every cell but a chart name a finite number."""
    with open(csv_path, newline="") as f:
        lines = [l for l in f.read().split("\n")]
    assert lines[-1] == "", "the file must end with a complete line"
    body = [l for l in lines[:-1] if not l.startswith("#")]
    header = body[0].split(",")
    rows = []
    for line in body[1:]:
        cells = line.split(",")
        assert len(cells) == len(header), f"incomplete row: {line!r}"
        row = {}
        for name, cell in zip(header, cells):
            if name == "chart":
                continue
            x = float(cell)
            assert math.isfinite(x)
            row[name] = x
        rows.append(row)
    return rows


def check_interrupted(out, signal_name):
    s = read_summary(out)
    assert s["status"] == "interrupted"
    assert f"interrupted by {signal_name}" in s["message"]
    assert "t = " in s["message"] and "step size" in s["message"]
    steps = rows_of(out / "steps.csv")
    assert len(steps) == s["counters"]["steps"] > 0  # every step taken, whole
    assert all(b["t"] > a["t"] for a, b in zip(steps, steps[1:]))
    assert steps[-1]["t"] <= s["t_reached"] < 1e6
    grid = rows_of(out / "trajectory.csv")
    assert grid and grid[-1]["t"] <= s["t_reached"]
    return s


def test_gnu_timeout_term_stops_a_single_body_run_and_keeps_it(tmp_path):
    # GNU timeout sends TERM to rigidae and then to its whole process group:
    # rigidae gets TERM twice within microseconds, while it writes its files.
    p = subprocess.run(["timeout", "--preserve-status", "-s", "TERM", "0.7", CLI, "solve", HEAVY_TOP,
                        "--t-end", "1e6", "--output-step", "1", "--out", tmp_path],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 1, p.stderr
    check_interrupted(tmp_path, "SIGTERM")
    assert "rigidae: error: interrupted by SIGTERM" in p.stderr


def test_plain_gnu_timeout_reports_124_and_the_run_is_kept(tmp_path):
    p = subprocess.run(["timeout", "0.7", CLI, "solve", HEAVY_TOP, "--t-end", "1e6", "--output-step", "1",
                        "--out", tmp_path], capture_output=True, text=True, timeout=60)
    assert p.returncode == 124  # timeout's own code; rigidae's run is whole on disk
    check_interrupted(tmp_path, "SIGTERM")


@pytest.mark.parametrize("sig,name", [(signal.SIGTERM, "SIGTERM"), (signal.SIGINT, "SIGINT")])
def test_a_repeated_signal_during_the_flush_is_ignored(tmp_path, sig, name):
    p = subprocess.Popen([CLI, "solve", HEAVY_TOP, "--t-end", "1e6", "--output-step", "1", "--out", tmp_path],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(tmp_path / "steps.csv")
    time.sleep(0.3)
    p.send_signal(sig)
    p.send_signal(sig)  # before the fix this one killed rigidae mid-flush
    time.sleep(0.002)
    try:
        p.send_signal(sig)
    except ProcessLookupError:
        pass
    _, err = p.communicate(timeout=60)
    assert p.returncode == 1, err
    check_interrupted(tmp_path, name)


def test_term_stops_a_multibody_run_and_keeps_it(tmp_path):
    p = subprocess.Popen([CLI, "solve", DOUBLE_PENDULUM, "--t-end", "1e6", "--output-step", "10", "--out",
                          tmp_path], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(tmp_path / "steps.csv")
    time.sleep(0.5)
    p.send_signal(signal.SIGTERM)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 1, err
    s = read_summary(tmp_path)
    assert s["status"] == "interrupted" and "SIGTERM" in s["message"]
    assert 0 < s["t_reached"] < 1e6
    steps = rows_of(tmp_path / "steps.csv")
    assert len(steps) == s["counters"]["steps"] > 0
    assert steps[-1]["t"] <= s["t_reached"]


def test_term_stops_compare_after_the_running_combination(tmp_path):
    p = subprocess.Popen([CLI, "compare", FREE_BODY, "--t-end", "1e6", "--output-step", "1000", "--only",
                          "quaternion/*/ggl", "--repeat", "1", "--out", tmp_path],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(tmp_path / "quaternion-lagrange-ggl" / "steps.csv")
    time.sleep(0.5)
    p.send_signal(signal.SIGTERM)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 1, err
    assert "compare stopped: interrupted by SIGTERM after 1 of 2 combinations" in err
    with open(tmp_path / "compare.csv", newline="") as f:
        rows = list(csv.DictReader(l for l in f if not l.startswith("#")))
    assert [r["status"] for r in rows] == ["interrupted"]
    assert read_summary(tmp_path / "quaternion-lagrange-ggl")["status"] == "interrupted"
    assert not (tmp_path / "quaternion-euler-ggl").exists()


# --- --t-end against output.times ------------------------------------------

def scene_with_times(tmp_path, times):
    text = Path(HEAVY_TOP).read_text().replace("output_step = 0.01\n", "")  # the even grid or the times
    path = tmp_path / "timed.toml"
    path.write_text(text + "\n[output]\ntimes = [" + ", ".join(map(str, times)) + "]\n")
    line = len(text.split("\n")) + 2  # the 'times' line
    return path, line


def test_t_end_clips_output_times_beyond_it_with_a_note(tmp_path):
    scene, line = scene_with_times(tmp_path, [0.25, 0.5, 1.0, 1.5])
    code, _, err = run_cli("solve", scene, "--t-end", "0.75", "--quiet", "--out", tmp_path / "out")
    assert code == 0, err
    assert f"{scene}:{line}:" in err and "note: --t-end 0.75 s leaves out 2 of the 4 output times" in err
    grid = rows_of(tmp_path / "out" / "trajectory.csv")
    assert [r["t"] for r in grid] == [0.25, 0.5]
    assert read_summary(tmp_path / "out")["t_reached"] == 0.75


def test_t_end_before_every_output_time_is_refused_at_output_times(tmp_path):
    scene, line = scene_with_times(tmp_path, [0.5, 1.0])
    code, _, err = run_cli("solve", scene, "--t-end", "0.2", "--out", tmp_path / "out")
    assert code == 2, err
    assert err.startswith(f"{scene}:{line}:")
    assert "error: 'output.times' = [0.5, 1] s has no time left inside [time.start, --t-end] = [0, 0.2] s" in err
    assert "at least 0.5 s" in err
    assert "internal error" not in err
    assert not (tmp_path / "out").exists()


# --- the step-size floor ------------------------------------------------------

# The heavy top at atol 1e-20: without the floor it is stuck near t = 1.4e-10 s
# at steps of 1e-27 s, and reaches max_steps after minutes (300,000 steps in 10 s).
STALL = ["--rtol", "1e-14", "--atol", "1e-20"]


def test_a_collapsed_step_size_fails_fast_with_time_step_floor_and_formulation(tmp_path):
    start = time.monotonic()
    code, _, err = run_cli("solve", HEAVY_TOP, *STALL, "--quiet", "--out", tmp_path)
    assert time.monotonic() - start < 60
    assert code == 1, err
    s = read_summary(tmp_path)
    m = s["message"]
    assert s["status"] == "failed"
    assert m.startswith("step size collapsed (ida): 20 or more steps in a row below the floor at t = ")
    assert "< floor 2e-12 s (solver.min_step_fraction = 1e-12 x max(|end - start|, |t|) = 2 s)" in m
    assert f"Formulation: {s['representation']} with scheme {s['scheme']}." in m
    assert s["t_reached"] < 1e-9
    assert s["counters"]["steps"] < 10000  # not max_steps = 1e7
    assert len(rows_of(tmp_path / "steps.csv")) == s["counters"]["steps"]


def test_the_ode_driver_has_the_floor_too(tmp_path):
    # CVODE-Adams with projection restarts at order 1 after each projection
    # and creeps at ~6e-12 s here; a floor of 1e-9 x 2 s stops it.
    code, _, err = run_cli("solve", HEAVY_TOP, "--integrator", "cvode-adams", "--scheme", "projection", *STALL,
                           "--min-step-fraction", "1e-9", "--quiet", "--out", tmp_path)
    assert code == 1, err
    s = read_summary(tmp_path)
    assert s["message"].startswith("step size collapsed (cvode-adams): 20 or more steps in a row below the floor")
    assert "< floor 2e-09 s" in s["message"] and "with scheme projection." in s["message"]
    assert s["counters"]["steps"] < 10000


def test_a_tiny_first_step_that_grows_is_not_a_stall(tmp_path):
    # 1e-20 s is 1e-8 of the floor: IDA doubles its step for about 27 steps
    # before it passes the floor, all of them below it, and then runs normally.
    code, _, err = run_cli("solve", HEAVY_TOP, "--initial-step", "1e-20", "--quiet", "--out", tmp_path)
    assert code == 0, err
    assert read_summary(tmp_path)["status"] == "success"


def test_the_floor_is_a_setting_and_zero_turns_it_off(tmp_path):
    code, _, err = run_cli("solve", HEAVY_TOP, *STALL, "--min-step-fraction", "0", "--max-steps", "3000",
                           "--quiet", "--out", tmp_path)
    assert code == 1
    s = read_summary(tmp_path)
    assert "too much work" in s["message"] and s["t_reached"] < 1e-9  # crept on until max_steps
    code, out, _ = run_cli("solve", "--help")
    assert "--min-step-fraction" in out and "[0 <= X <= 1e-06; default 1e-12;" in out


# --- compare --------------------------------------------------------------

def compare_rows(folder):
    with open(folder / "compare.csv", newline="") as f:
        return list(csv.DictReader(l for l in f if not l.startswith("#")))


def test_compare_run_timeout_makes_a_row_with_its_reason(tmp_path):
    code, _, err = run_cli("compare", FREE_BODY, "--t-end", "1e5", "--output-step", "100", "--only",
                           "quaternion/lagrange/ggl", "--repeat", "1", "--run-timeout", "0.5", "--quiet",
                           "--out", tmp_path)
    assert code == 0, err  # a failed row is a result; the reference stood
    [row] = compare_rows(tmp_path)
    assert row["status"] == "failed"
    assert row["message"].startswith("timed out: the wall-time limit of 0.5 s per run (compare --run-timeout)")
    s = read_summary(tmp_path / "quaternion-lagrange-ggl")
    assert 0 < s["t_reached"] < 1e5 and s["wall_time_s"] < 5


def test_compare_states_the_time_limit_of_each_combination(tmp_path):
    # The default: max(300 s, 10 x the reference's wall time), stated with the reference's time.
    code, out, err = run_cli("compare", DOUBLE_PENDULUM, "--t-end", "0.05", "--only", "quaternion/euler/ggl",
                             "--repeat", "1", "--no-error-estimate", "--out", tmp_path / "a")
    assert code == 0, err
    text = (tmp_path / "a" / "compare.txt").read_text()
    assert text in out
    m = re.search(r"^time limit per combination: (\S+) s \(default max\(300 s, 10 x the reference's (\S+) s\); "
                  r"--run-timeout S sets it\)$", text, re.M)
    assert m, text
    limit, reference_wall = float(m.group(1)), float(m.group(2))
    assert 0 < reference_wall < 30  # a tight reference of 0.05 s of the pendulum takes well under a second
    assert limit == max(300.0, 10 * reference_wall)
    # Given: named as given; 0: none.
    for given, line in (("12.5", "time limit per combination: 12.5 s (--run-timeout)"),
                        ("0", "time limit per combination: none (--run-timeout 0)")):
        code, _, err = run_cli("compare", FREE_BODY, "--t-end", "0.1", "--only", "quaternion/euler/ggl", "--repeat",
                               "1", "--run-timeout", given, "--quiet", "--out", tmp_path / given)
        assert code == 0, err
        assert line in (tmp_path / given / "compare.txt").read_text().splitlines()


def test_compare_stops_with_exit_1_when_its_reference_fails(tmp_path):
    code, _, err = run_cli("compare", HEAVY_TOP, "--reference", "tight", "--max-steps", "30", "--only", "quaternion/*/ggl", "--repeat", "1",
                           "--quiet", "--out", tmp_path / "a")
    assert code == 1
    assert "compare stopped: the reference failed" in err
    assert compare_rows(tmp_path / "a") == []
    assert not (tmp_path / "a" / "quaternion-lagrange-ggl").exists()
    # --keep-going runs them anyway; the exit code still says the reference failed.
    code, _, err = run_cli("compare", HEAVY_TOP, "--reference", "tight", "--max-steps", "30", "--only", "quaternion/*/ggl", "--repeat", "1",
                           "--keep-going", "--quiet", "--out", tmp_path / "b")
    assert code == 1
    assert len(compare_rows(tmp_path / "b")) == 2


def test_the_index_2_3_hint_is_only_for_runs_without_error_test_suppression(tmp_path):
    # Every shipped scheme leaves its multipliers out of the error test, so
    # the hint fits none of them.
    code, _, err = run_cli("solve", HEAVY_TOP, "--coordinates", "linear", "--equations", "lagrange", "--scheme",
                           "index2", "--rtol", "1e-13", "--atol", "1e-13", "--initial-step", "1e-13", "--out",
                           tmp_path)
    assert code == 1
    m = read_summary(tmp_path)["message"]
    assert "IDA_CONV_FAIL" in m and "iteration matrix is singular" in m
    assert "index-2/3" not in m


# --- study ----------------------------------------------------------------

def small_study(tmp_path, scene=FREE_BODY):
    path = tmp_path / "small.study.toml"
    path.write_text(f"""schema_version = 1
name = "small"
scenes = ["{scene}"]
reference = "exact"
targets = [1e-3]

[grid]
combinations = ["quaternion/lagrange/ggl"]
rtol = [1e-6]
atol = "rtol"

[timing]
warmups = 0
repeats = 1
""")
    return path


def dead_pid():
    p = subprocess.Popen(["true"])
    p.wait()
    return p.pid


def test_study_resume_removes_temporary_folders_of_killed_runs(tmp_path):
    study = small_study(tmp_path)
    out = tmp_path / "out"
    code, listing, err = run_cli("study", "list", study, "--out", out)
    assert code == 0, err
    run_id = listing.split("--run ")[1].split()[0].strip("'")
    host = socket.gethostname()
    final = out / "runs" / run_id  # ids hold slashes: SCENE/COMBINATION/TOLERANCES
    final.parent.mkdir(parents=True, exist_ok=True)
    dead = final.parent / f".{final.name}.tmp-{host}-{dead_pid()}"
    alive = final.parent / f".{final.name}.tmp-{host}-{os.getpid()}"  # a worker still writing: left alone
    other = final.parent / f".{final.name}.tmp-otherhost-{dead_pid()}"  # unknown: left alone
    for d in (dead, alive, other):
        d.mkdir()
        (d / "summary.json").write_text("{}")
    code, _, err = run_cli("study", "run", study, "--run", run_id, "--out", out, "--quiet")
    assert code == 0, err
    assert not dead.exists()
    assert f"removed {dead}" in err
    assert alive.exists() and other.exists()
    assert (final / "run.json").exists()


def reachable_by_everyone(folder):
    """True when every ancestor of folder lets other users pass (o+x)."""
    folder = Path(folder).resolve()
    return all(os.stat(p).st_mode & 0o001 for p in [folder, *folder.parents])


@pytest.fixture
def nobody_dir():
    """A folder that the unprivileged user 'nobody' can read but not write
    (tests run as root, for whom permission bits do not apply). It must lie
    where nobody can reach it: a checkout inside a private folder (mktemp -d
    is mode 700) is not, so the CLI and the scenes are copied in as well."""
    if os.geteuid() != 0:
        pytest.skip("needs root to run as nobody")
    places = [p for p in (tempfile.gettempdir(), "/tmp", "/var/tmp") if os.path.isdir(p) and reachable_by_everyone(p)]
    if not places:
        pytest.skip("no temporary folder that the user nobody can reach")
    base = Path(tempfile.mkdtemp(prefix="rigidae-ro-", dir=places[0]))
    os.chmod(base, 0o755)
    (base / "bin").mkdir()
    shutil.copy2(CLI, base / "bin" / "rigidae")
    for scene in (HEAVY_TOP, FREE_BODY, str(SOURCE / "problems" / "arm6.urdf")):
        shutil.copy2(scene, base / Path(scene).name)
    yield base
    for d, _, _ in os.walk(base):
        os.chmod(d, 0o755)
    shutil.rmtree(base)


def run_as_nobody(base, *args):
    p = subprocess.run([str(base / "bin" / "rigidae"), *map(str, args)], capture_output=True, text=True,
                       timeout=300, user=65534, group=65534, extra_groups=[])
    return p.returncode, p.stdout, p.stderr


def test_an_unwritable_output_folder_is_exit_2_for_every_command(nobody_dir):
    heavy_top = nobody_dir / Path(HEAVY_TOP).name
    free_body = nobody_dir / Path(FREE_BODY).name
    study = small_study(nobody_dir, free_body)
    out = nobody_dir / "out"
    code, _, err = run_cli("study", study, "--out", out, "--quiet", "--no-plot")
    assert code == 0, err
    code, _, err = run_cli("solve", heavy_top, "--t-end", "0.01", "--record", "grid", "--quiet", "--out", out / "run")
    assert code == 0, err
    for d, _, _ in os.walk(nobody_dir):
        os.chmod(d, 0o555)
    results = {
        "solve": run_as_nobody(nobody_dir, "solve", heavy_top, "--t-end", "0.01", "--out", out / "solve"),
        "solve into the folder": run_as_nobody(nobody_dir, "solve", heavy_top, "--t-end", "0.01", "--out", out),
        "compare": run_as_nobody(nobody_dir, "compare", free_body, "--t-end", "0.1", "--only",
                                 "quaternion/lagrange/ggl", "--out", out),
        "study run": run_as_nobody(nobody_dir, "study", "run", study, "--shard", "0/1", "--out", out / "again"),
        "study collect": run_as_nobody(nobody_dir, "study", "collect", study, "--out", out, "--no-plot"),
        # The drawing commands and export write into a folder too (a traceback and exit 1 before).
        "view": run_as_nobody(nobody_dir, "view", out / "run", "--scene", heavy_top),
        "vtk": run_as_nobody(nobody_dir, "vtk", out / "run", "--scene", heavy_top, "--out", out / "vtk"),
        "animate": run_as_nobody(nobody_dir, "animate", out / "run", "--scene", heavy_top, "--out", out / "a.gif"),
        "export": run_as_nobody(nobody_dir, "export", "--mjcf", nobody_dir / "arm6.urdf", "-o", out / "arm6.xml"),
    }
    for what, (code, _, err) in results.items():
        assert code == 2, f"{what}: exit {code}: {err}"
        assert "internal error" not in err, what
        assert "Permission denied" in err, what


def test_a_full_device_names_the_step_file_not_the_summary(tmp_path):
    # steps.csv is a link to /dev/full: every write to it fails with ENOSPC,
    # as on a full disk, while summary.json can still be written.
    (tmp_path / "steps.csv").symlink_to("/dev/full")
    code, _, err = run_cli("solve", HEAVY_TOP, "--out", tmp_path)
    assert code == 1
    assert f"{tmp_path / 'steps.csv'}: " in err and "No space left on device" in err
    s = read_summary(tmp_path)
    assert s["status"] == "failed"
    assert "output lost: " + str(tmp_path / "steps.csv") in s["message"]


def test_a_full_device_under_a_mechanism_keeps_a_summary_naming_the_step_file(tmp_path):
    (tmp_path / "steps.csv").symlink_to("/dev/full")
    code, _, err = run_cli("solve", DOUBLE_PENDULUM, "--out", tmp_path)
    assert code == 1
    assert f"{tmp_path / 'steps.csv'}: " in err and "No space left on device" in err
    s = read_summary(tmp_path)
    assert s["status"] == "failed"
    assert s["message"].startswith("output lost: " + str(tmp_path / "steps.csv"))


def test_term_stops_a_study_and_leaves_no_temporary_folder(tmp_path):
    scene = tmp_path / "long_free_body.toml"
    scene.write_text(Path(FREE_BODY).read_text().replace("end = 20.0", "end = 100000.0")
                     .replace("output_step = 0.02", "output_step = 100.0"))
    study = small_study(tmp_path)
    study.write_text(study.read_text().replace(FREE_BODY, str(scene)))
    out = tmp_path / "out"
    p = subprocess.Popen([CLI, "study", "run", study, "--shard", "0/1", "--out", out, "--quiet"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 30
    while not list(out.glob("runs/**/.*.tmp-*/steps.csv")):
        assert time.monotonic() < deadline and p.poll() is None
        time.sleep(0.01)
    time.sleep(0.3)
    p.send_signal(signal.SIGTERM)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 1, err
    assert "study interrupted; complete runs are kept" in err
    assert not list(out.glob("runs/**/.*.tmp-*"))  # the run in progress leaves nothing
    assert not list(out.glob("runs/**/run.json"))
