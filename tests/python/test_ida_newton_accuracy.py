"""bench/ida_newton_accuracy.py: its references are right (the particle pendulum's closed values
against a numerical integration of the pendulum equation; the crank-slider's closed form against
a default run), and docs/benchmarks.md's accuracy-sweep table agrees with the committed JSON lines."""
import json
import math
import re
import sys

import pytest

from conftest import CLI, SOURCE

sys.path.insert(0, str(SOURCE / "bench"))
import ida_newton_accuracy as acc  # noqa: E402


def test_particle_pendulum_reference_matches_the_pendulum_equation():
    # theta'' = -(g/L) sin(theta) from theta = pi/2 at rest, RK4 over one
    # period in steps of T/8/400: the bob (L sin theta, 0, -L cos theta) at
    # every T/8 against the closed values (g = 9.81, L = 1; theta from the
    # downward vertical, positive towards +x).
    g, period = 9.81, 2.3678419475762374
    n_sub = 400
    h = period / 8 / n_sub

    def f(th, w):
        return w, -g * math.sin(th)

    th, w = math.pi / 2, 0.0
    for j in range(9):
        x, z = math.sin(th), -math.cos(th)
        ex = acc.exact_particle(j)
        assert abs(x - ex[0]) < 1e-9 and abs(z - ex[2]) < 1e-9 and ex[1] == 0.0, (j, x, z, ex)
        for _ in range(n_sub):
            k1 = f(th, w)
            k2 = f(th + h / 2 * k1[0], w + h / 2 * k1[1])
            k3 = f(th + h / 2 * k2[0], w + h / 2 * k2[1])
            k4 = f(th + h * k3[0], w + h * k3[1])
            th += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])


def test_crank_slider_default_run_is_within_its_tolerance_of_the_closed_form(tmp_path):
    summary, rows = acc.run(CLI, "crank_slider_driven", str(tmp_path / "run"))
    assert summary["status"] == "success"
    worst, end = acc.errors("crank_slider_driven", rows, None)
    assert len(rows) == 101
    # rtol = atol = 1e-8 on a 0.44 m slider position; measured 2.9e-10 m
    assert 0 < worst < 1e-8 and end <= worst


def test_docs_sweep_table_agrees_with_the_committed_results():
    lines = [json.loads(x) for x in open(SOURCE / "bench" / "results" / "ida_newton_accuracy.jsonl") if x.strip()]
    doc = (SOURCE / "docs" / "benchmarks.md").read_text()
    section = doc[doc.index("### The accuracy sweep"):doc.index("### The first count")]
    settings = list(dict.fromkeys(r["setting"] for r in lines))
    assert len(settings) >= 10
    for st in settings:
        rs = [r for r in lines if r["setting"] == st]
        fails = sum(r["newton_conv_fails"] for r in rs)
        residuals = sum(r["residual_evals"] for r in rs)
        row = next((ln for ln in section.splitlines() if ln.startswith(f"| {st} |")), None)
        assert row is not None, st
        cells = [c.strip().replace("*", "") for c in row.split("|")[1:-1]]
        assert int(re.match(r"[\d,]+", cells[1]).group(0).replace(",", "")) == fails, (st, cells[1])
        assert int(cells[2].replace(",", "")) == residuals, (st, cells[2])
        p = next(r for r in rs if r["scene"] == "pendulum_1000")
        assert cells[5] == f"{p['max_error_on_grid_m']:.2e} / {p['error_at_end_m']:.2e}", st


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
