"""summary.json's provenance (build: embedded at build time; run: this
process's command line and time), `-q` for `--quiet`, and tools/'s scripts
executable with the right interpreter line."""
import os
import re
import shutil
import subprocess

import pytest

from conftest import CLI, HEAVY_TOP, SOURCE, read_summary

DATE = re.compile(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ$")


def git(*args):
    if not shutil.which("git"):
        return None
    p = subprocess.run(["git", "-C", str(SOURCE), *args], capture_output=True, text=True)
    return p.stdout.strip() if p.returncode == 0 else None


def solve(out, *args, env=None):
    p = subprocess.run([CLI, "solve", *map(str, args), "--out", str(out)], capture_output=True, text=True, env=env,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    return p


@pytest.mark.parametrize("scene", [HEAVY_TOP, str(SOURCE / "problems" / "double_pendulum.toml")],
                         ids=["single_body", "multibody"])
def test_summary_records_the_build_and_the_run(scene, tmp_path):
    # No git on PATH: the commit must come from the build, not from running git now.
    p = solve(tmp_path / "run", scene, "--t-end", "0.05", "-q", env=dict(os.environ, PATH="/nonexistent"))
    assert p.stdout == ""  # -q is --quiet: nothing printed on success
    s = read_summary(tmp_path / "run")
    assert set(s["build"]) == {"commit", "dirty", "date"}
    assert DATE.match(s["build"]["date"]) and DATE.match(s["run"]["date"])
    assert s["build"]["date"] <= s["run"]["date"]
    assert isinstance(s["build"]["dirty"], bool)
    head = git("rev-parse", "HEAD")
    if head:
        assert re.fullmatch(r"[0-9a-f]{40}", s["build"]["commit"])
        # The build's commit is HEAD unless a commit was made after the last build.
        assert s["build"]["commit"] == head or git("merge-base", "--is-ancestor", s["build"]["commit"], head) == ""
    assert s["run"]["command_line"] == (f"{CLI} solve {scene} --t-end 0.05 -q --out {tmp_path / 'run'}")


def test_command_line_words_are_quoted_for_a_shell(tmp_path):
    out = tmp_path / "with space"
    solve(out, HEAVY_TOP, "--t-end", "0.05", "--quiet")
    line = read_summary(out)["run"]["command_line"]
    assert line.endswith(f" --quiet --out '{out}'")


def test_q_is_in_the_help_and_takes_no_value():
    p = subprocess.run([CLI, "solve", "--help"], capture_output=True, text=True)
    assert "  -q, --quiet" in p.stdout
    p = subprocess.run([CLI, "solve", HEAVY_TOP, "-q=1"], capture_output=True, text=True)
    assert p.returncode == 2 and "option -q takes no value" in p.stderr


def test_every_tool_is_executable_with_debian_interpreters():
    tools = sorted((SOURCE / "tools").iterdir())
    assert any(t.suffix == ".py" for t in tools) and any(t.suffix == ".sh" for t in tools)
    for t in tools:
        if t.suffix not in (".py", ".sh"):
            continue
        assert os.access(t, os.X_OK), f"{t.name}: chmod +x"
        first = t.read_text().split("\n", 1)[0]
        want = "#!/usr/bin/python3" if t.suffix == ".py" else "#!/usr/bin/env bash"
        assert first == want, f"{t.name}: first line {first!r}, want {want!r}"
    # What a checkout gets: the modes git records.
    listed = git("ls-files", "-s", "tools")
    if listed:
        for line in listed.splitlines():
            mode, path = line.split()[0], line.split("\t")[1]
            if path.endswith((".py", ".sh")):
                assert mode == "100755", f"{path}: git update-index --chmod=+x"


def test_python_multibody_run_records_the_build_and_the_run():
    # A MultibodyRun has no summary.json: its summary carries the same blocks, from the same build.
    import rigidae
    run = rigidae.solve(str(SOURCE / "problems" / "double_pendulum.toml"), t_end=0.01, record="none")
    s = run.summary
    assert set(s["build"]) == {"commit", "dirty", "date"}
    assert DATE.match(s["build"]["date"]) and DATE.match(s["run"]["date"])
    assert s["build"]["date"] <= s["run"]["date"]
    assert "python" in s["run"]["command_line"]
