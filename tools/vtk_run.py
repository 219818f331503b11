#!/usr/bin/python3
"""Writes a run as ParaView files: OUT/run.pvd, a collection with one
OUT/frame_NNNNN.vtp (VTK XML PolyData) per output time (`rigidae vtk
RUN_DIR`, `rigidae solve --vtk`; docs/viewer.md).

Each .vtp holds, in space coordinates at that time: every body's shapes as
triangles (shape_mesh.py), then as vertices each joint's point and each
body's centre of mass. Cell data `body` is the body's index (for a joint, of
the body its point is in) and `kind` is 0 for a shape's triangle, 1 for a
joint point, 2 for a centre of mass. Open run.pvd in ParaView and colour by
`body`; the time steps are the run's output times.

Usage: vtk_run.py --geometry G.json --out DIR [--frames N] RUN_DIR
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_motion  # noqa: E402
import shape_mesh  # noqa: E402


def data_array(name, kind, values, components=1):
    comp = f' NumberOfComponents="{components}"' if components != 1 else ""
    text = " ".join(repr(v) if isinstance(v, float) else str(v) for v in values)
    return f'<DataArray type="{kind}" Name="{name}"{comp} format="ascii">{text}</DataArray>\n'


def frame_vtp(geometry, meshes, poses, row):
    points, polys, verts, poly_body, vert_body, vert_kind = [], [], [], [], [], []
    body_poses = [poses.pose(row, k) for k in range(len(geometry["bodies"]))]
    for k, (vs, ts) in enumerate(meshes):
        x, R = body_poses[k]
        base = len(points)
        points.extend(run_motion.to_space(x, R, p) for p in vs)
        polys.extend([base + i for i in t] for t in ts)
        poly_body.extend([k] * len(ts))
    for j in geometry["joints"]:
        b = j["body"]
        p = run_motion.to_space(*body_poses[b], j["point"]) if b >= 0 else list(j["point"])
        verts.append(len(points))
        points.append(p)
        vert_body.append(b)
        vert_kind.append(1)
    for k, body in enumerate(geometry["bodies"]):
        verts.append(len(points))
        points.append(run_motion.to_space(*body_poses[k], body["center_of_mass"]))
        vert_body.append(k)
        vert_kind.append(2)
    flat = [c for p in points for c in p]
    out = ['<?xml version="1.0"?>\n',
           '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">\n<PolyData>\n',
           f'<Piece NumberOfPoints="{len(points)}" NumberOfVerts="{len(verts)}" NumberOfLines="0" '
           f'NumberOfStrips="0" NumberOfPolys="{len(polys)}">\n',
           "<Points>\n", data_array("Points", "Float64", flat, 3), "</Points>\n",
           "<Verts>\n", data_array("connectivity", "Int64", verts),
           data_array("offsets", "Int64", list(range(1, len(verts) + 1))), "</Verts>\n",
           "<Polys>\n", data_array("connectivity", "Int64", [i for t in polys for i in t]),
           data_array("offsets", "Int64", [3 * (i + 1) for i in range(len(polys))]), "</Polys>\n",
           # VTK orders a PolyData's cells: vertices, lines, polygons, strips.
           '<CellData Scalars="body">\n', data_array("body", "Int32", vert_body + poly_body),
           data_array("kind", "Int32", vert_kind + [0] * len(polys)), "</CellData>\n",
           "</Piece>\n</PolyData>\n</VTKFile>\n"]
    return "".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--geometry", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--frames", type=int, default=0)
    a = ap.parse_args()
    if len(a.runs) != 1:
        raise SystemExit(f"vtk writes one run: give the folder of one run (of {len(a.runs)} in this folder)")
    geometry = run_motion.load_geometry(a.geometry)
    header, rows = run_motion.read_trajectory(a.runs[0])
    poses = run_motion.Poses(geometry, header)
    meshes = [shape_mesh.body_mesh(b) for b in geometry["bodies"]]
    os.makedirs(a.out, exist_ok=True)
    entries = []
    keep = run_motion.thin(len(rows), a.frames)
    for n, i in enumerate(keep):
        name = f"frame_{n:05d}.vtp"
        with open(os.path.join(a.out, name), "w", encoding="utf-8") as f:
            f.write(frame_vtp(geometry, meshes, poses, rows[i]))
        entries.append(f'<DataSet timestep="{poses.time(rows[i])!r}" group="" part="0" file="{name}"/>\n')
    with open(os.path.join(a.out, "run.pvd"), "w", encoding="utf-8") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
                "<Collection>\n" + "".join(entries) + "</Collection>\n</VTKFile>\n")
    print(f"vtk: {os.path.join(a.out, 'run.pvd')} ({len(keep)} frames)")


if __name__ == "__main__":
    main()
