"""rigidae solve --vtk: a ParaView collection (.pvd) of .vtp files, one per
output time; the corners of a box drawn on the four-bar's coupler, read back
from the XML, are where the trajectory's pose at that time puts them (the
transform computed here from the quaternion by Rodrigues' formula)."""
import csv
import math
import xml.etree.ElementTree as ET

import numpy as np

from conftest import SOURCE, run_cli

FOUR_BAR = SOURCE / "problems" / "four_bar.toml"
# A box on the coupler, shifted along the bar and turned a quarter turn about x.
BOX_POSITION = np.array([0.05, 0.0, 0.0])
BOX_SIZE = np.array([0.5, 0.03, 0.02])
BOX_QUATERNION = [math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0]


def rotation(q):
    """Rodrigues: R = I + sin(a) K + (1 - cos(a)) K^2 for the axis-angle of the unit quaternion q."""
    w, v = q[0], np.array(q[1:])
    s = np.linalg.norm(v)
    if s == 0:
        return np.eye(3)
    angle, k = 2 * math.atan2(s, w), v / s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def array(piece, path, name):
    for a in piece.find(path).iter("DataArray"):
        if a.get("Name") == name:
            return np.array(a.text.split(), dtype=float)
    raise KeyError(name)


def test_vtk_box_corners_follow_the_trajectory(tmp_path):
    text = FOUR_BAR.read_text()
    anchor = 'inertia_principal = [0.0001625, 0.0313, 0.0313625]  # 0.5 x 0.03 x 0.02 m bar\n'
    visual = (f'visual = {{ shape = "box", size = {list(BOX_SIZE)}, position = {list(BOX_POSITION)}, '
              f'quaternion = {BOX_QUATERNION} }}\n')
    scene = tmp_path / "four_bar_box.toml"
    scene.write_text(text.replace(anchor, anchor + visual))
    out = tmp_path / "run"
    code, _, stderr = run_cli("solve", scene, "--quiet", "--record", "grid", "--t-end", "1", "--out", out, "--vtk")
    assert code == 0, stderr

    collection = ET.parse(out / "vtk" / "run.pvd").getroot().find("Collection")
    datasets = collection.findall("DataSet")
    with open(out / "trajectory.csv") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, rows = rows[0], [[float(v) for v in r] for r in rows[1:]]
    assert len(datasets) == len(rows) == 101  # one file per output time
    k = 37
    assert float(datasets[k].get("timestep")) == rows[k][0]
    piece = ET.parse(out / "vtk" / datasets[k].get("file")).getroot().find("PolyData/Piece")
    points = array(piece, "Points", "Points").reshape(-1, 3)
    body = array(piece, "CellData", "body").astype(int)
    kind = array(piece, "CellData", "kind").astype(int)
    connectivity = array(piece, "Polys", "connectivity").astype(int).reshape(-1, 3)
    n_verts = int(piece.get("NumberOfVerts"))
    # Cells: the vertices first (joints, then centres of mass), then the triangles.
    triangles = connectivity[(body[n_verts:] == 1) & (kind[n_verts:] == 0)]
    assert len(triangles) == 12  # a box: two triangles per face
    got = np.unique(points[np.unique(triangles)], axis=0)
    assert len(got) == 8

    col = {name: i for i, name in enumerate(header)}
    x = np.array([rows[k][col[f"coupler.{c}"]] for c in "xyz"])
    R_WB = rotation([rows[k][col[f"coupler.q{c}"]] for c in "wxyz"])
    R_BV = rotation(BOX_QUATERNION)
    corners = [x + R_WB @ (BOX_POSITION + R_BV @ (np.array(s) * BOX_SIZE / 2))
               for s in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3)]
    for c in corners:
        assert np.min(np.linalg.norm(got - c, axis=1)) < 1e-12
    # The coupler's centre of mass (a vertex of kind 2) is the trajectory's.
    vert_ids = array(piece, "Verts", "connectivity").astype(int)
    com = points[vert_ids[(body[:n_verts] == 1) & (kind[:n_verts] == 2)][0]]
    assert np.allclose(com, x, atol=1e-15)
