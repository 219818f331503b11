#!/usr/bin/python3
"""CTest `install.pip`: `pip install .` into a fresh venv made from Debian's
python3, with no index and no build isolation (nothing is downloaded), then
`import rigidae` in the venv solves problems/heavy_top.toml.

RIGIDAE_BUILD_DIR=BUILD_DIR is passed to setup.py: the extension is built by
this build folder's CMake (already up to date after the build, so the cost is
pip's own) rather than from scratch; see README "Install" for both ways.

Usage: check_pip_install.py BUILD_DIR SOURCE_DIR
"""
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

build, source = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve()
work = build / "pip_install_test"
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
venv = work / "venv"
started = time.monotonic()


def run(*cmd, env=None, cwd=None):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=env, cwd=cwd)
    if p.returncode != 0:
        sys.exit(f"FAILED ({p.returncode}): {' '.join(map(str, cmd))}\n{p.stdout}\n{p.stderr}")
    return p


run("/usr/bin/python3", "-m", "venv", "--system-site-packages", venv)
env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
env.update(RIGIDAE_BUILD_DIR=str(build), PIP_DISABLE_PIP_VERSION_CHECK="1", PYTHONDONTWRITEBYTECODE="1")
run(venv / "bin" / "python", "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps", "-q", source,
    env=env)
print(f"pip install: {time.monotonic() - started:.1f} s")

code = f"""
import math, rigidae
assert rigidae.__file__.startswith({str(venv)!r}), rigidae.__file__
run = rigidae.solve({str(source / 'problems' / 'heavy_top.toml')!r}, t_end=0.5)
s = run.summary
assert s['status'] == 'success', s['status']
assert s['final']['t'] == 0.5, s['final']['t']
assert math.isfinite(s['final']['energy']) and abs(s['final']['energy_rel_error']) < 1e-4, s['final']
assert set(s['build']) == {{'commit', 'dirty', 'date'}}, s['build']
print(rigidae.__version__, rigidae.__file__, s['counters']['steps'], s['final']['energy'])
"""
out = run(venv / "bin" / "python", "-c", code, env=env, cwd=work).stdout
print(out, end="")
print(f"total: {time.monotonic() - started:.1f} s")
