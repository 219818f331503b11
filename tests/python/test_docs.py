"""The documentation stays true to the code: README's generated tables match their records, every
scene key of the settings table is documented, the bad-input table lists every bad scene."""
import re
import subprocess
import sys

import pytest

from conftest import SOURCE

sys.path.insert(0, str(SOURCE / "tools"))
import readme_tables  # noqa: E402

README = (SOURCE / "README.md").read_text()


def test_readme_markers_parse_and_name_every_table():
    blocks = readme_tables.blocks(README)
    assert sorted(name for name, _, _ in blocks) == sorted(readme_tables.TABLES)
    lines = README.split("\n")
    for name, start, end in blocks:
        inside = lines[start:end]
        assert inside and all(line.startswith("|") for line in inside), name
        assert re.match(r"^\|(---\|)+$", inside[1]), name  # a markdown table: header, rule, rows
        assert len(inside) > 3, name


def test_readme_tables_are_what_the_records_give():
    """README.md's tables equal a rewrite from docs/measured and docs/studies (no solve is re-run)."""
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "readme_tables.py"), "--check"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def test_rewrite_is_idempotent_and_restores_an_edited_table():
    once = readme_tables.rewrite(README)
    assert readme_tables.rewrite(once) == once
    # an edited number inside a block is put back; text outside the blocks is never touched
    edited = once.replace("| quaternion/euler/index1 | success | ", "| quaternion/euler/index1 | success | 1", 1)
    assert edited != once
    assert readme_tables.rewrite(edited) == once
    outside = once.replace("## Measured tables", "## Measured tables (edited)")
    assert readme_tables.rewrite(outside) == outside


def test_compare_table_rows_are_compare_csv():
    """One row per combination of the recorded compare.csv, in its order, with its numbers."""
    rows = readme_tables.read_csv(SOURCE / "docs" / "measured" / "heavy_top_compare.csv")
    text = readme_tables.heavy_top_compare()
    body = text.split("\n")[2:]
    assert [line.split(" | ")[0].lstrip("| ") for line in body] == [r["combination"] for r in rows]
    for line, r in zip(body, rows):
        cells = [c.strip() for c in line.strip("|").split(" | ")]
        assert int(cells[2]) == int(r["steps"])
        assert int(cells[3]) == int(r["residual_evals"]) + int(r["jacobian_residual_evals"])
        assert float(cells[8]) == pytest.approx(float(r["error_final_rad"]), rel=0.051)


@pytest.mark.parametrize("broken, message", [
    ("<!-- generated: multibody -->\n| a |\n", "has no"),
    ("| a |\n<!-- end -->\n", "without"),
    ("<!-- generated: nonsense -->\n| a |\n<!-- end -->\n", "unknown table"),
    ("<!-- generated: multibody -->\n<!-- generated: study_best -->\n<!-- end -->\n<!-- end -->\n", "inside"),
])
def test_broken_markers_are_named(broken, message):
    with pytest.raises(ValueError, match=message):
        readme_tables.blocks("# title\n" + broken)


def settings_scene_keys():
    text = (SOURCE / "src" / "settings" / "table.cpp").read_text()
    keys = re.findall(r'\.scene_key\s*=\s*"([^"]+)"', text)
    assert len(keys) > 20  # the regex still finds the table's rows
    return keys


def schema1_sections():
    """{section: text} of docs/scene_format.md's schema-1 part: "" for the top level, "solver",
    "formulation.euler_angles", ..."""
    text = (SOURCE / "docs" / "scene_format.md").read_text().split("# Schema 2")[0]
    sections, name = {}, None
    for line in text.split("\n"):
        m = re.match(r"^##+ (?:`\[([a-z_.]+)\]`|(Top level))", line)
        if m:
            name = m.group(1) or ""
            sections.setdefault(name, "")
            continue
        if name is not None:
            sections[name] += line + "\n"
    return sections


def test_every_scene_key_of_the_settings_table_is_documented():
    sections = schema1_sections()
    missing = []
    for key in settings_scene_keys():
        table, _, leaf = key.rpartition(".")
        body = sections.get(table)
        if body is None or not re.search(r"^\| `" + re.escape(leaf) + r"` \|", body, re.M):
            missing.append(key)
    assert not missing, f"scene keys of src/settings/table.cpp without a row in docs/scene_format.md: {missing}"


def test_bad_input_table_lists_every_bad_scene():
    table = (SOURCE / "docs" / "bad_input.md").read_text()
    listed = re.findall(r"^\| `([^`]+)` \|", table, re.M)
    files = sorted(p.name for p in (SOURCE / "tests" / "bad_scenes").glob("*.toml"))
    assert sorted(listed) == files
    assert f"{len(files)} files of" in table.replace("\n", " ")
    assert f"lists the {len(files)} bad inputs" in README.replace("\n", " ")
