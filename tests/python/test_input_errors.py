"""Bad input from Python: scene dicts are checked by the scene loader with
its messages, positioned by key path; options by the CLI's option parser."""
import copy
import re

import pytest

import rigidae
from conftest import HEAVY_TOP, SOURCE, run_cli

BASE = rigidae.read_scene_dict(HEAVY_TOP)


def cli_detail(stderr):
    """The CLI's message without its FILE:LINE:COL."""
    return re.sub(r"^.*?:\d+:\d+: error: ", "", stderr.strip())


def test_dict_scene_solves_like_the_file():
    a = rigidae.solve(BASE, record="none")
    b = rigidae.solve(HEAVY_TOP, record="none")
    assert a.summary["counters"] == b.summary["counters"]
    assert a.final["q_WB"] == b.final["q_WB"]
    assert a.summary["configuration"]["body"] == b.summary["configuration"]["body"]


def test_misspelt_key_is_named_with_the_loaders_message():
    d = copy.deepcopy(BASE)
    d["body"]["mas"] = d["body"].pop("mass")
    with pytest.raises(rigidae.InputError) as e:
        rigidae.scene_from_dict(d)
    err = e.value
    assert isinstance(err, ValueError)
    assert err.key == ("body", "mas")
    assert err.suggestion == "mass"
    assert str(err).startswith("scene['body']['mas']: error: unknown key 'mas' in [body]; did you mean 'mass'?")
    # The same words as the CLI on the same mistake in a file.
    code, _, stderr = run_cli("solve", SOURCE / "tests" / "bad_scenes" / "unknown_key_typo.toml")
    assert code == 2
    assert cli_detail(stderr) == err.detail.replace("scene['body']['mas']: error: ", "")


@pytest.mark.parametrize("edit, key, words", [
    (lambda d: d["initial"].__setitem__("quaternion", [1.0, 0.0, 0.0]), ("initial", "quaternion"),
     "must have exactly 4 numbers"),
    (lambda d: d["body"].__setitem__("mass", "heavy"), ("body", "mass"), "must be a number, not a string"),
    (lambda d: d["formulation"].__setitem__("scheme", "ggll"), ("formulation", "scheme"), 'did you mean "ggl"?'),
    (lambda d: d.__setitem__("bodyy", {"mass": 1.0}), ("bodyy",), "did you mean 'body'?"),
    (lambda d: d["body"].pop("mass"), ("body",), "missing required key 'mass' in [body]"),
    (lambda d: d["time"].__setitem__("end", float("nan")), ("time", "end"), "finite"),
])
def test_bad_values_are_positioned_by_key(edit, key, words):
    d = copy.deepcopy(BASE)
    edit(d)
    with pytest.raises(rigidae.InputError) as e:
        rigidae.solve(d)
    assert e.value.key == key
    assert words in str(e.value)


def test_value_without_toml_form():
    d = copy.deepcopy(BASE)
    d["body"]["mass"] = None
    with pytest.raises(rigidae.InputError, match=r"scene\['body'\]\['mass'\]"):
        rigidae.scene_from_dict(d)


def test_options_are_checked_by_the_cli_parser():
    code, _, stderr = run_cli("solve", HEAVY_TOP, "--rtol", "2")
    assert code == 2
    with pytest.raises(rigidae.InputError) as e:
        rigidae.solve(HEAVY_TOP, rtol=2)
    assert str(e.value) in stderr
    assert e.value.option == "rtol"
    # A misspelt keyword in the words of a Python call (the CLI names its option).
    code, _, stderr = run_cli("solve", HEAVY_TOP, "--rtoll", "1e-6")
    assert code == 2 and "did you mean '--rtol'" in stderr
    with pytest.raises(rigidae.InputError, match=r"unknown keyword argument rtoll= for rigidae.solve\(\); "
                                                 r"did you mean rtol=\?") as e:
        rigidae.solve(HEAVY_TOP, rtoll=1e-6)
    assert e.value.option == "rtoll" and e.value.suggestion == "rtol"
    with pytest.raises(rigidae.InputError, match=r"for rigidae.compare\(\); did you mean rtol=\?"):
        rigidae.compare(HEAVY_TOP, rtoll=1e-6)
    # A flag's keyword is documented as True/False, not by its scene key's values.
    assert "no_chart_switching=True as the flag; default False" in rigidae.OPTIONS["no_chart_switching"]
    assert "[threshold|every_step" not in rigidae.OPTIONS["project_every_step"]
    with pytest.raises(rigidae.InputError, match="'dense'"):
        rigidae.solve(HEAVY_TOP, linear_solver="lu")
    with pytest.raises(rigidae.InputError, match="takes True or False"):
        rigidae.solve(HEAVY_TOP, no_chart_switching="yes")


def test_every_cli_scene_option_is_a_keyword():
    code, out, _ = run_cli("solve", "--help")
    assert code == 0
    cli_options = set(re.findall(r"^\s+(?:-[a-z], )?--([a-z][a-z-]+)", out, re.M))
    # The command's own: out= and record= in Python; --error-estimate is a second run, not a setting;
    # figures, the viewer's page and ParaView files: CLI only.
    own = {"out", "quiet", "help", "record", "error-estimate", "plot", "view", "vtk"}
    assert {o.replace("-", "_") for o in cli_options - own} == set(rigidae.OPTIONS)
    doc = rigidae.solve.__doc__
    for name in rigidae.OPTIONS:
        assert f"    {name}= (--{name.replace('_', '-')}" in doc


def test_options_apply_as_on_the_command_line():
    run = rigidae.solve(HEAVY_TOP, t_end=0.25, output_step=0.05, record="grid", max_order=3,
                        no_chart_switching=True, coordinates="quaternion")
    assert run.grid["t"][-1] == 0.25 and len(run.grid) == 6
    assert run.summary["configuration"]["solver"]["max_order"] == 3


def test_file_errors_keep_file_line_column():
    with pytest.raises(rigidae.InputError) as e:
        rigidae.load_scene(SOURCE / "tests" / "bad_scenes" / "unknown_key_typo.toml")
    assert e.value.line == 6 and e.value.column == 1 and e.value.suggestion == "mass"
