"""The accuracy verdict's targets on the CI subset of the corpus
(tools/accuracy_corpus.py --preset ci; the full corpus: docs/accuracy_check.md).

The truth is independent of the verdict: the closed form (single bodies)
and a tight reference in quaternion/euler/ggl cross-checked in linear
coordinates (mechanisms), compared with each run's output grid in Python.
"""
import csv
import math
import os
import subprocess
import sys

from conftest import CLI, SOURCE



def test_warned_when_far_off_and_quiet_when_near(tmp_path):
    out = tmp_path / "corpus"
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "accuracy_corpus.py"), "--preset", "ci", "--out",
                        str(out), "--rigidae", CLI, "--jobs", "2", "--check"], capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr[-3000:]
    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 102
    ok = [r for r in rows if r["status"] == "success"]
    assert len(ok) == len(rows), [r for r in rows if r["status"] != "success"]
    far = [r for r in ok if float(r["off"]) > 1e3 * float(r["rtol"])]
    near = [r for r in ok if float(r["off"]) <= 1e2 * float(r["rtol"])]
    # Enough runs on either side for the rates to mean something, mechanisms among them.
    assert len(far) >= 40 and len(near) >= 10
    assert any(r["scene"] == "four_bar.toml" for r in near)
    assert any(r["scene"] == "double_pendulum.toml" for r in far)
    far_warned = sum(r["warned"] == "True" for r in far)
    near_warned = sum(r["warned"] == "True" for r in near)
    assert far_warned >= 0.95 * len(far), [(r["scene"], r["combination"], r["rtol"], r["off"]) for r in far
                                           if r["warned"] != "True"]
    assert near_warned <= 0.01 * len(near), [(r["scene"], r["combination"], r["rtol"], r["off"]) for r in near
                                             if r["warned"] == "True"]
    # Mechanisms are judged by their companions, whose cost is recorded.
    for r in ok:
        if r["scene"] in ("four_bar.toml", "double_pendulum.toml"):
            assert r["estimate_source"] == "companion"
            assert math.isfinite(float(r["companion_wall_s"]))
        else:
            assert r["estimate_source"] == "closed form"
    assert (out / "corpus.md").read_text().count("Targets") == 1
