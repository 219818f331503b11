"""rigidae view of a single body (schema 1, the heavy top): drawn as its
inertia ellipsoid about the fixed point, the picture in headless Chromium
changes as it precesses (helpers: test_view.py)."""
import json
import re

import numpy as np
import pytest

from conftest import HEAVY_TOP
from test_view import CHROMIUM, drawn_fraction, screenshot, solve_and_view


@pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed (tools/build.sh installs it)")
def test_heavy_top_page_single_body(tmp_path):
    page, html = solve_and_view(HEAVY_TOP, tmp_path / "run", "--t-end", "1")
    data = json.loads(re.search(r'id="motion">(.*?)</script>', html, re.S).group(1).replace("<\\/", "</"))
    body = data["geometry"]["bodies"][0]
    # No visual in the scene: the inertia ellipsoid of a thin disk, J = (0.234375, 0.46875, 0.234375)
    # kg m^2, m = 15 kg: a^2 = 5 (J2 + J3 - J1) / (2 m), c likewise, b^2 = 5 (J1 + J3 - J2) / (2 m) = 0,
    # raised to 5 % of the largest.
    assert body["inertia_ellipsoid"]
    semi = sorted(body["visuals"][0]["semi_axes"])
    a = (5 * 0.46875 / 30) ** 0.5
    assert semi == pytest.approx([0.05 * a, a, a], rel=1e-9)
    assert body["visuals"][0]["position"] == [0.0, 1.0, 0.0]  # at the centre of mass
    a0 = screenshot(page, 0.0, tmp_path / "t0.png")
    a1 = screenshot(page, 0.8, tmp_path / "t1.png")
    assert drawn_fraction(a0) > 0.01
    assert float((np.abs(a0 - a1).sum(axis=2) > 60).mean()) > 0.01
