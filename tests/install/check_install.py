#!/usr/bin/python3
"""CTest `install`: cmake --install into a prefix under the build folder, then
  1. the installed files are where README "Install" says;
  2. a project outside the tree (tests/install/consumer) finds the package with
     find_package(rigidae) and CMAKE_PREFIX_PATH, builds against
     rigidae::rigidae_core, solves problems/heavy_top.toml to t = 0.5 s and
     prints numbers that are checked;
  3. the installed CLI, after the prefix is moved elsewhere and with a bogus
     RIGIDAE_TOOLS_DIR, runs its plot script from PREFIX/share/rigidae/tools
     and draws the figures; summary.json records the build and the run.

Usage: check_install.py BUILD_DIR SOURCE_DIR CMAKE GENERATOR [CMAKE_ARG...]
(the CMAKE_ARGs are added to the consumer's configure command)
"""
import json
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

build, source, cmake, generator = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3], sys.argv[4]
consumer_args = sys.argv[5:]
work = build / "install_test"
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
prefix, moved = work / "prefix", work / "moved" / "prefix"
heavy_top = source / "problems" / "heavy_top.toml"
started = time.monotonic()


def run(*cmd, env=None, cwd=None):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=env, cwd=cwd)
    if p.returncode != 0:
        sys.exit(f"FAILED ({p.returncode}): {' '.join(map(str, cmd))}\n{p.stdout}\n{p.stderr}")
    return p


def check(ok, what):
    if not ok:
        sys.exit(f"FAILED: {what}")


# 1. cmake --install and the layout.
run(cmake, "--install", build, "--prefix", prefix)
libdir = next(d for d in ("lib", "lib64") if (prefix / d / "librigidae_core.a").exists())
for rel in ("bin/rigidae", f"{libdir}/librigidae_core.a", "include/rigidae/app/solve.hpp",
            "include/rigidae/io/scene_loader.hpp", f"{libdir}/cmake/rigidae/rigidaeConfig.cmake",
            f"{libdir}/cmake/rigidae/rigidaeConfigVersion.cmake", f"{libdir}/cmake/rigidae/rigidaeTargets.cmake",
            "share/rigidae/tools/plot_solve.py", "share/rigidae/tools/plot_compare.py",
            "share/rigidae/tools/plot_study.py", "share/rigidae/tools/view_run.py",
            "share/rigidae/tools/viewer/viewer.js", "share/rigidae/three/three.module.min.js"):
    check((prefix / rel).is_file(), f"{rel} installed")
for rel in ("bin/rigidae", "share/rigidae/tools/plot_solve.py"):
    check(os.access(prefix / rel, os.X_OK), f"{rel} executable")
# No path of the source tree is compiled into the installed CLI for its scripts.
check(str(source / "tools").encode() not in (prefix / "bin" / "rigidae").read_bytes(),
      "the installed CLI holds no path to the source tree's tools/")
print(f"install: {time.monotonic() - started:.1f} s")

# 2. The consumer project: configure, build, run.
consumer = work / "consumer"
configure = [cmake, "-S", source / "tests" / "install" / "consumer", "-B", consumer, "-G", generator,
             "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}", *consumer_args]
if shutil.which("ccache"):
    configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
out = run(*configure).stdout
check(f"rigidae 0.1" in out and str(prefix / "bin" / "rigidae") in out, "find_package(rigidae) and its variables:\n" + out)
run(cmake, "--build", consumer)
print(f"consumer built: {time.monotonic() - started:.1f} s")
out = run(consumer / "consumer", heavy_top, work / "consumer_run", 0.5).stdout
values = dict(line.split(" ", 1) for line in out.splitlines())
check(values.get("status") == "success", "consumer: status success\n" + out)
check(float(values["t_reached"]) == 0.5, "consumer: t_reached 0.5\n" + out)
check(int(values["steps"]) > 10, "consumer: steps\n" + out)
energy = float(values["energy"])
check(math.isfinite(energy) and energy != 0.0, "consumer: finite energy\n" + out)
check(abs(float(values["energy_rel_error"])) < 1e-4, "consumer: energy conserved\n" + out)
summary = json.loads((work / "consumer_run" / "summary.json").read_text())
check(summary["final"]["t"] == 0.5 and summary["final"]["energy"] == energy, "consumer: summary.json")
print(out, end="")

# 3. The installed CLI, moved, with a bogus RIGIDAE_TOOLS_DIR: --plot uses the installed scripts.
moved.parent.mkdir()
prefix.rename(moved)
env = dict(os.environ, RIGIDAE_TOOLS_DIR=str(work / "no-such-folder"), RIGIDAE_SHOW_PLOT_SCRIPT="1")
p = run(moved / "bin" / "rigidae", "solve", heavy_top, "--t-end", "0.2", "--plot", "-q", "--out", work / "cli_run",
        env=env, cwd=work)
script = moved / "share" / "rigidae" / "tools" / "plot_solve.py"
check(f"rigidae: plot script {script}\n" in p.stderr, "the installed plot script ran:\n" + p.stderr)
check((work / "cli_run" / "figures" / "run.png").is_file(), "figures/run.png drawn:\n" + p.stderr)
summary = json.loads((work / "cli_run" / "summary.json").read_text())
check(summary["final"]["t"] == 0.2, "CLI: t_end")
check(set(summary["build"]) == {"commit", "dirty", "date"} and set(summary["run"]) == {"command_line", "date"},
      "summary.json build and run")
check(summary["run"]["command_line"].startswith(f"{moved / 'bin' / 'rigidae'} solve ") and
      summary["run"]["command_line"].endswith(" --plot -q --out " + str(work / "cli_run")),
      "summary.json run.command_line: " + summary["run"]["command_line"])
print(f"installed CLI --plot: {script}")
# rigidae view from the moved prefix: its tools and three.js (share/rigidae/three), nothing of the build tree.
p = run(moved / "bin" / "rigidae", "view", work / "cli_run", "--out", work / "cli_run" / "page.html", env=env, cwd=work)
check(f"rigidae: tool script {moved / 'share' / 'rigidae' / 'tools' / 'view_run.py'}\n" in p.stderr,
      "the installed view script ran:\n" + p.stderr)
page = (work / "cli_run" / "page.html").read_text()
three = (moved / "share" / "rigidae" / "three" / "three.module.min.js").read_text()
check(three in page, "the page inlines the installed three.js")
# The CLI alone, without its share/ folder: a clear warning naming where it looked; the run still succeeds.
lonely = work / "lonely" / "bin"
lonely.mkdir(parents=True)
shutil.copy2(moved / "bin" / "rigidae", lonely / "rigidae")
env.pop("RIGIDAE_TOOLS_DIR")
p = run(lonely / "rigidae", "solve", heavy_top, "--t-end", "0.05", "--plot", "-q", "--out", work / "lonely_run",
        env=env, cwd=work)
check(f"figures skipped: plot_solve.py not found in {lonely.parent / 'share' / 'rigidae' / 'tools'}" in p.stderr
      and "RIGIDAE_TOOLS_DIR" in p.stderr, "the missing scripts' warning:\n" + p.stderr)
check((work / "lonely_run" / "summary.json").is_file(), "the run without scripts is written")
print(f"total: {time.monotonic() - started:.1f} s")
