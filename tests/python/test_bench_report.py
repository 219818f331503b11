"""bench/report.py on the committed results: the work-precision figures of issue 13 are written
(PNG and PDF, one per scene), the doc links them, a second run changes nothing, and every row of
the "Targets of issue 13" table agrees with a selection made here straight from the JSON lines
(fastest successful setting at or below the target error, ratio = rigidae wall / RKF78 wall)."""
import json
import math
import re
import shutil
import statistics
import subprocess
import sys

import pytest

from conftest import SOURCE

SCENES = ("heavy_top", "free_body", "lagrange_top")
TARGETS = (1e-6, 1e-9)


def read_jsonl(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def fastest(rows, target):
    good = [r for r in rows if r.get("status", "success") == "success" and r.get("error_rad") is not None
            and r["error_rad"] <= target]
    return min(good, key=lambda r: r["wall_s"]) if good else None


def seconds(cell):
    """'40.2 ms' -> 0.0402; '2.41e+03 ms' -> 2.41."""
    m = re.fullmatch(r"([0-9.e+-]+) ms", cell.strip())
    assert m, cell
    return float(m.group(1)) * 1e-3


def run_report(doc, figures):
    p = subprocess.run([sys.executable, str(SOURCE / "bench" / "report.py"), "--doc", str(doc),
                        "--figures", str(figures)], capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    doc = out / "benchmarks.md"
    shutil.copy(SOURCE / "docs" / "benchmarks.md", doc)
    run_report(doc, out / "figures")
    return out, doc


def targets_table(text):
    """The rows of the targets table as lists of cells."""
    part = text[text.index("### Targets of issue 13"):]
    lines = [line for line in part.splitlines() if line.startswith("| ")]
    header = lines[0]
    rows = []
    for line in lines[1:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        if not cells[0] in SCENES:
            break
        rows.append(cells)
    return header, rows


def test_report_writes_a_work_precision_figure_per_scene_and_links_it(report):
    out, doc = report
    text = doc.read_text()
    for scene in SCENES:
        for ext, magic in (("png", b"\x89PNG\r\n\x1a\n"), ("pdf", b"%PDF-")):
            path = out / "figures" / f"workprecision_{scene}.{ext}"
            assert path.is_file(), path
            assert path.stat().st_size > 20000, path  # an empty matplotlib page is ~1-2 kB
            with open(path, "rb") as f:
                assert f.read(len(magic)) == magic
            assert f"(figures/workprecision_{scene}.{ext})" in text


def test_report_is_idempotent(report):
    out, doc = report
    first = doc.read_bytes()
    figures = {p.name: p.read_bytes() for p in (out / "figures").iterdir()}
    run_report(doc, out / "figures")
    assert doc.read_bytes() == first
    assert {p.name: p.read_bytes() for p in (out / "figures").iterdir()} == figures


def test_targets_table_agrees_with_the_results(report):
    _, doc = report
    header, rows = targets_table(doc.read_text())
    cols = [c.strip() for c in header.strip("|").split("|")]
    col = {name: cols.index(name) for name in ("scene", "error ≤", "best rigidae setting (steps)", "wall",
                                               "RKF78 (steps)", "rigidae / RKF78", "within 3x of RKF78",
                                               "peer / rigidae", "30x faster than it")}
    rkf_wall_col = cols.index("wall", col["wall"] + 1)
    ode = read_jsonl(SOURCE / "bench" / "results" / "ode.jsonl")
    peers = read_jsonl(SOURCE / "bench" / "peers" / "results.jsonl")
    assert [(r[col["scene"]], r[col["error ≤"]]) for r in rows] == [
        (s, f"{t:.0e} rad") for s in SCENES for t in TARGETS]
    for cells in rows:
        scene, target = cells[col["scene"]], float(cells[col["error ≤"]].split()[0])
        rig = fastest([r for r in ode if r.get("scene") == scene and r.get("peer") == "rigidae"], target)
        rkf = fastest([r for r in ode if r.get("scene") == scene and r.get("peer") == "odeint"], target)
        assert rig and rkf, (scene, target)  # every scene reaches both targets in the committed run
        assert cells[col["best rigidae setting (steps)"]] == \
            f"{rig['method']} rtol {rig['setting']:.0e} ({rig['steps']:,})"
        assert cells[col["RKF78 (steps)"]] == f"tol {rkf['setting']:.0e} ({rkf['steps']:,})"
        wall, rkf_wall = seconds(cells[col["wall"]]), seconds(cells[rkf_wall_col])
        assert wall == pytest.approx(rig["wall_s"], rel=5e-3)
        assert rkf_wall == pytest.approx(rkf["wall_s"], rel=5e-3)
        ratio = float(cells[col["rigidae / RKF78"]])
        assert ratio == pytest.approx(rig["wall_s"] / rkf["wall_s"], rel=5e-3)
        assert ratio == pytest.approx(wall / rkf_wall, rel=1e-2)  # the printed columns agree too
        assert cells[col["within 3x of RKF78"]] == ("met" if rig["wall_s"] <= 3 * rkf["wall_s"] else "**missed**")
        slow = fastest([r for r in peers if r.get("scene", "heavy_top") == scene
                        and r["peer"] in ("simbody", "mujoco", "scipy")], target)
        if slow is None:
            assert cells[col["peer / rigidae"]] == "–"
            continue
        speedup = float(cells[col["peer / rigidae"]].rstrip("x"))
        assert speedup == pytest.approx(slow["wall_s"] / rig["wall_s"], rel=5e-3)
        expected = ("met" if speedup >= 30 else "**missed**") if target == 1e-6 else "–"
        assert cells[col["30x faster than it"]] == expected
        assert math.isfinite(speedup)


# ---- the mechanism benchmarks' tables in the generated part -------------------------------------

BEGIN = "<!-- BEGIN generated by bench/report.py: do not edit by hand -->"
END = "<!-- END generated by bench/report.py -->"
RESULTS = SOURCE / "bench" / "results"


def generated_section(text, heading):
    """The generated part's section under '### heading' (up to the next ### heading)."""
    part = text[text.index(BEGIN):text.index(END)]
    start = part.index("\n### " + heading)
    end = part.find("\n### ", start + 1)
    return part[start:end if end >= 0 else len(part)]


def table_rows(section):
    """Every table row of a section as a list of stripped cells (header and rule lines left out)."""
    rows = []
    for line in section.splitlines():
        if line.startswith("|") and not set(line) <= set("|-: "):
            rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return rows


def row_starting(rows, *cells):
    found = [r for r in rows if r[:len(cells)] == list(cells)]
    assert len(found) == 1, (cells, found)
    return found[0]


def loglog_slope(points):
    """The least-squares slope of log y over log x, by the standard library (not chain_report's own code)."""
    return statistics.linear_regression([math.log(x) for x, _ in points], [math.log(y) for _, y in points]).slope


def test_chain_table_slopes_and_figure_come_from_chain_jsonl(report):
    out, doc = report
    section = generated_section(doc.read_text(), "The N-link chain on IDA")
    rows = table_rows(section)
    chain = read_jsonl(RESULTS / "chain.jsonl")
    assert len(chain) >= 3
    for r in chain:
        cells = row_starting(rows, str(r["links"]), f"{r['linear_solver']} ({r['solver_setting']})")
        assert cells[2] == f"{r['unknowns']:,}" and cells[5] == str(r["steps"])
        assert float(cells[9]) == pytest.approx(r["instructions_per_step"] / 1e6, rel=5e-3)
        assert float(cells[8]) == pytest.approx(r["cpu_ms_per_step"], rel=5e-3)
    big = [r for r in chain if r["links"] >= 10]
    ins = loglog_slope([(r["links"], r["instructions_per_step"]) for r in big])
    cpu = loglog_slope([(r["links"], r["cpu_ms_per_step"]) for r in big])
    m = re.search(r"CPU (-?[0-9.]+), instructions (-?[0-9.]+)", section)
    assert m, section
    assert float(m.group(1)) == pytest.approx(cpu, abs=0.006)
    assert float(m.group(2)) == pytest.approx(ins, abs=0.006)
    figure = out / "figures" / "benchmarks_chain.png"
    assert figure.is_file() and figure.stat().st_size > 20000
    with open(figure, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert "(figures/benchmarks_chain.png)" in section


def test_dense_klu_table_comes_from_its_jsonl(report):
    _, doc = report
    rows = table_rows(generated_section(doc.read_text(), "The N-link chain: dense LU or KLU"))
    lines = read_jsonl(RESULTS / "chain_dense_klu.jsonl")
    sizes = sorted({r["links"] for r in lines})
    assert [r[0] for r in rows[1:]] == [str(n) for n in sizes]
    for n in sizes:
        dense = next(r for r in lines if r["links"] == n and r["solver_setting"] == "dense")
        klu = next(r for r in lines if r["links"] == n and r["solver_setting"] == "klu")
        cells = row_starting(rows, str(n))
        assert float(cells[4]) == pytest.approx(klu["instructions_per_step"] / dense["instructions_per_step"], abs=0.006)


def test_long_run_table_comes_from_long_run_jsonl(report):
    _, doc = report
    rows = table_rows(generated_section(doc.read_text(), "Long runs: the recorded runs"))
    runs = [r for r in read_jsonl(RESULTS / "long_run.jsonl") if r.get("kind") == "long_run"]
    assert {r["run"] for r in runs} >= {"pivot-1e-12"}
    for r in runs:
        cells = row_starting(rows, r["run"], f"{r['steps']:,}", f"{r['rhs']:,}")
        assert float(cells[3]) == pytest.approx(r["end_m"], rel=0.05)  # the bob's distance at the end
        assert float(cells[4]) == pytest.approx(r["worst_m"], rel=0.05)
        assert float(cells[6]) == pytest.approx(r["cpu_s_median"], abs=6e-4)


def test_heavy_top_rkf78_table_comes_from_its_jsonl(report):
    _, doc = report
    rows = table_rows(generated_section(doc.read_text(), "Heavy top, ARKODE against RKF78"))
    lines = read_jsonl(RESULTS / "heavy_top_rkf78.jsonl")
    runs = [r for r in lines if r.get("error_rad") is not None]
    for target in TARGETS:
        rkf = fastest([r for r in runs if r["peer"] == "odeint"], target)
        rig = fastest([r for r in runs if r["peer"] == "rigidae"], target)
        cells = row_starting(rows, f"{target:g}", "odeint RKF78")
        assert cells[2:4] == [f"{rkf['setting']:g}", f"{rkf['steps']:,}"]
        cells = row_starting(rows, f"{target:g}", rig["method"])
        assert cells[2:4] == [f"{rig['setting']:g}", f"{rig['steps']:,}"]
        assert float(cells[6]) == pytest.approx(rig["wall_s"] / rkf["wall_s"], abs=0.006)


def test_ida_newton_tables_come_from_their_jsonl(report):
    _, doc = report
    text = doc.read_text()
    rows = table_rows(generated_section(text, "IDA's Newton convergence failures: the default runs"))
    fails = read_jsonl(RESULTS / "ida_newton_failures.jsonl")
    total = row_starting(rows, "**total**")
    assert total[1:5] == [f"{sum(r[k] for r in fails):,}"
                          for k in ("steps", "newton_conv_fails", "residual_evals", "jacobian_evals")]
    rows = table_rows(generated_section(text, "IDA's Newton settings: the accuracy sweep"))
    sweep = read_jsonl(RESULTS / "ida_newton_accuracy.jsonl")
    settings = list(dict.fromkeys(r["setting"] for r in sweep))
    assert [r[0] for r in rows[1:]] == settings
    for st in settings:
        rs = [r for r in sweep if r["setting"] == st]
        cells = row_starting(rows, st)
        assert cells[1].split()[0] == f"{sum(r['newton_conv_fails'] for r in rs):,}"


def test_default_integrator_tables_come_from_its_jsonl(report):
    _, doc = report
    section = generated_section(doc.read_text(), "Defaults chosen by measurement: the tables")
    records = read_jsonl(RESULTS / "default_integrator.jsonl")
    assert f"{len(records)} settings" in section
    rows = table_rows(section)
    for scene in dict.fromkeys(r["scene"] for r in records):
        base = next(r for r in records if r["scene"] == scene and r["default"] and r["status"] == "success")
        # the first table's row: the default run's error on the grid, its steps
        cells = next(r for r in rows if r[0] == scene and len(r) == 7)
        error, steps = cells[2].split(" / ")[:2]
        assert float(error.split()[0]) == pytest.approx(base["error"], rel=5e-3)
        assert steps == f"{base['steps']:,}"
    # each rule table has one row per scene, and its cheapest column is one of the integrators (or none)
    rule = [r for r in rows if len(r) == 8 and r[0] != "scene"]
    assert len(rule) == 2 * len(set(r["scene"] for r in records))
    assert {r[6] for r in rule} <= {"ida", "arkode-erk", "cvode-adams", "cvode-bdf", "none"}


def test_absent_results_files_are_named_not_fatal(tmp_path):
    sys.path.insert(0, str(SOURCE / "bench"))
    import report as bench_report
    empty = tmp_path / "results"
    empty.mkdir()
    text = bench_report.mechanisms_part(str(empty), str(tmp_path / "figures"), "figures")
    for name in ("heavy_top_rkf78.jsonl", "default_integrator.jsonl", "long_run.jsonl", "ida_newton_failures.jsonl",
                 "ida_newton_accuracy.jsonl", "chain.jsonl", "chain_dense_klu.jsonl"):
        assert f"`bench/results/{name}` is absent" in text, name
    assert not (tmp_path / "figures" / "benchmarks_chain.png").exists()
    assert "|" not in text  # no table without its file


def test_committed_doc_is_what_report_writes(report):
    # The fixture regenerated a copy of docs/benchmarks.md from the committed results: the committed
    # doc must already read so, i.e. no table in it is stale against its results file.
    _, doc = report
    assert doc.read_text() == (SOURCE / "docs" / "benchmarks.md").read_text()
