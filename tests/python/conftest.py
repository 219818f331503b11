"""Shared helpers of the Python module's tests: the rigidae CLI (built next
to the module; CTest passes its path) and the source tree."""
import csv
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

SOURCE = Path(os.environ.get("RIGIDAE_SOURCE_DIR", Path(__file__).resolve().parents[2]))
CLI = os.environ.get("RIGIDAE_CLI", str(SOURCE / "build" / "rigidae"))
HEAVY_TOP = str(SOURCE / "problems" / "heavy_top.toml")


def run_cli(*args):
    """(exit code, stdout, stderr) of the rigidae binary."""
    p = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


def read_csv(path):
    """(units comment, header, rows as lists of strings) of a rigidae CSV file."""
    with open(path, newline="") as f:
        units = f.readline().rstrip("\n")
        rows = list(csv.reader(f))
    return units, rows[0], rows[1:]


def read_summary(folder):
    with open(Path(folder) / "summary.json") as f:
        return json.load(f)


@pytest.fixture
def tmp_out(tmp_path):
    return tmp_path
