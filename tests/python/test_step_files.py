"""steps.npy (--step-format npy): NumPy's own reader gives back the numbers
of steps.csv exactly, under the CSV's column names; the row count in the
header is right after a run that fails midway and after a write that the
system refuses."""
import resource
import signal

import numpy as np
import pytest

from conftest import CLI, HEAVY_TOP, SOURCE, read_csv, read_summary, run_cli

DOUBLE_PENDULUM = str(SOURCE / "problems" / "double_pendulum.toml")


def solve(scene, out, *args):
    code, stdout, stderr = run_cli("solve", scene, "--quiet", "--out", out, *args)
    return code, stdout + stderr


def csv_table(path):
    """(header, float rows) of a rigidae CSV; text cells (the chart) as bytes."""
    _, header, rows = read_csv(path)
    return header, rows


def check_npy_equals_csv(npy_path, csv_path):
    steps = np.load(npy_path)
    header, rows = csv_table(csv_path)
    assert list(steps.dtype.names) == header
    assert len(steps) == len(rows)
    for k, name in enumerate(header):
        column = steps[name]
        if column.dtype.kind == "S":
            assert [c.decode() for c in column] == [r[k] for r in rows]
        else:
            # The CSV holds the shortest text that reads back to the same double: equal, bit for bit.
            assert np.array_equal(column, np.array([float(r[k]) for r in rows]).astype(column.dtype))
    return steps


@pytest.mark.parametrize("scene,formulation", [
    (HEAVY_TOP, []),
    (HEAVY_TOP, ["--coordinates", "euler"]),  # the chart column: a string field
    (DOUBLE_PENDULUM, []),                    # multibody
])
def test_npy_equals_csv(tmp_path, scene, formulation):
    a, b = tmp_path / "csv", tmp_path / "npy"
    code, out = solve(scene, a, "--t-end", "0.5", *formulation)
    assert code == 0, out
    code, out = solve(scene, b, "--t-end", "0.5", "--step-format", "npy", *formulation)
    assert code == 0, out
    assert not (b / "steps.csv").exists() and not (a / "steps.npy").exists()
    steps = check_npy_equals_csv(b / "steps.npy", a / "steps.csv")
    # The trajectory is the same file whatever the step format.
    assert (a / "trajectory.csv").read_bytes() == (b / "trajectory.csv").read_bytes()
    assert np.all(np.diff(steps["t"]) > 0)
    # pandas (where installed: python3-pandas) takes the record array as it is, columns by name.
    try:
        import pandas as pd
    except ImportError:
        return
    frame = pd.DataFrame(steps)
    assert list(frame.columns) == list(steps.dtype.names)
    assert np.array_equal(frame["t"].to_numpy(), steps["t"])


def test_npy_row_count_after_a_failed_run(tmp_path):
    """A run stopped by max_steps: the header counts the rows written, the same rows as the CSV's."""
    a, b = tmp_path / "csv", tmp_path / "npy"
    code, out = solve(HEAVY_TOP, a, "--max-steps", "137")
    assert code == 1, out
    code, out = solve(HEAVY_TOP, b, "--max-steps", "137", "--step-format", "npy")
    assert code == 1, out
    steps = check_npy_equals_csv(b / "steps.npy", a / "steps.csv")
    assert 100 <= len(steps) <= 137
    assert read_summary(b)["status"] == "failed"


def limit_file_size(limit_bytes):
    def apply():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # the write fails with EFBIG instead of killing
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))
    return apply


def test_npy_row_count_after_a_refused_write(tmp_path):
    """A file-size limit stops the writes midway: the file keeps the whole rows before it,
    its header counts exactly those, and they are the first rows of an unlimited run."""
    import subprocess
    full, cut = tmp_path / "full", tmp_path / "cut"
    code, out = solve(HEAVY_TOP, full, "--step-format", "npy")
    assert code == 0, out
    limit = 64 * 1024
    p = subprocess.run([CLI, "solve", HEAVY_TOP, "--quiet", "--step-format", "npy", "--out", str(cut)],
                       capture_output=True, text=True, preexec_fn=limit_file_size(limit), timeout=300)
    assert p.returncode == 1, p.stdout + p.stderr
    assert "steps.npy" in p.stderr and "File too large" in p.stderr
    steps = np.load(cut / "steps.npy")
    reference = np.load(full / "steps.npy")
    row = steps.dtype.itemsize
    assert (cut / "steps.npy").stat().st_size <= limit
    assert len(steps) >= (limit - 1024) // row - 1  # nearly every byte under the limit holds rows
    assert np.array_equal(steps, reference[: len(steps)])
    # No partial row is left after the last whole one.
    header = (cut / "steps.npy").stat().st_size - len(steps) * row
    assert header % 64 == 0
