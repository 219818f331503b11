#!/usr/bin/python3
"""Writes one self-contained HTML page that plays one or more runs in a
browser: `rigidae view RUN_DIR` calls it with the scene's geometry (JSON)
and three.js's module build, which are inlined so that the page opens
offline from file:// (docs/viewer.md).

Usage: view_run.py --geometry G.json --three three.module.min.js --out PAGE.html
                   [--frames N] [--runs a,b] RUN_DIR...
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_motion  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DIGITS = 6  # significant digits kept per number: 1e-6 of the scene is far below a pixel


def compact(x):
    return float(f"{x:.{DIGITS}g}")


def run_frames(geometry, run_dir, budget):
    header, rows = run_motion.read_trajectory(run_dir)
    poses = run_motion.Poses(geometry, header)
    keep = run_motion.thin(len(rows), budget)
    times, frames, forces = [], [], []
    with_force = [j for j in range(len(geometry["joints"])) if poses.joints[j] is not None]
    for i in keep:
        row = rows[i]
        times.append(compact(poses.time(row)))
        f = []
        for k in range(len(geometry["bodies"])):
            x, R = poses.pose(row, k)
            q = quaternion_of(R)
            f.extend(compact(v) for v in x + q)
        frames.append(f)
        if with_force:
            forces.append([compact(v) for j in with_force for v in poses.force(row, j)])
    return {"name": os.path.basename(os.path.normpath(run_dir)), "times": times, "frames": frames,
            "force_joints": with_force, "forces": forces, "rows": len(rows)}


def quaternion_of(R):
    """(w, x, y, z) of a rotation matrix (Shepperd's method: the largest of the four first)."""
    import math
    tr = R[0][0] + R[1][1] + R[2][2]
    if tr > 0:
        s = 2 * math.sqrt(tr + 1)
        return [s / 4, (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s]
    i = max(range(3), key=lambda k: R[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2 * math.sqrt(1 + R[i][i] - R[j][j] - R[k][k])
    q = [0.0] * 4
    q[0] = (R[k][j] - R[j][k]) / s
    q[1 + i] = s / 4
    q[1 + j] = (R[j][i] + R[i][j]) / s
    q[1 + k] = (R[k][i] + R[i][k]) / s
    return q


def page(geometry, runs, three_js):
    with open(os.path.join(HERE, "viewer", "viewer.html"), encoding="utf-8") as f:
        template = f.read()
    with open(os.path.join(HERE, "viewer", "viewer.js"), encoding="utf-8") as f:
        viewer_js = f.read()
    # The sources sit in <script type="text/plain"> elements: nothing in them
    # may end or escape the element.
    for name, text in (("three.js", three_js), ("viewer.js", viewer_js)):
        low = text.lower()
        if "</script" in low or "<!--" in low:
            raise SystemExit(f"{name} holds '</script' or '<!--' and cannot be inlined as it is")
    data = json.dumps({"geometry": geometry, "runs": runs}, separators=(",", ":")).replace("</", "<\\/")
    title = geometry.get("scene") or "run"
    # The title first, everywhere in the template (before anything is inlined).
    out = template.replace("@TITLE@", title.replace("&", "&amp;").replace("<", "&lt;"))
    parts = {"@MOTION@": data, "@THREE@": three_js, "@VIEWER@": viewer_js}
    # One pass per marker, each marker present once in the template.
    for marker, text in parts.items():
        before, sep, after = out.partition(marker)
        if not sep:
            raise SystemExit(f"viewer.html lacks {marker}")
        out = before + text + after
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--geometry", required=True)
    ap.add_argument("--three", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--frames", type=int, default=2000)
    ap.add_argument("--runs", dest="only", default="")
    a = ap.parse_args()
    if a.frames < 2:
        raise SystemExit(f"--frames {a.frames}: give at least 2")
    geometry = run_motion.load_geometry(a.geometry)
    dirs = a.runs
    if a.only:
        wanted = [w for w in a.only.split(",") if w]
        names = {os.path.basename(os.path.normpath(d)): d for d in dirs}
        missing = [w for w in wanted if w not in names]
        if missing:
            raise SystemExit(f"--runs: no run folder {', '.join(missing)} (there are: {', '.join(sorted(names))})")
        dirs = [names[w] for w in wanted]
    runs = [run_frames(geometry, d, a.frames) for d in dirs]
    with open(a.three, encoding="utf-8") as f:
        three_js = f.read()
    html = page(geometry, runs, three_js)
    tmp = a.out + ".part"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(html)
    os.replace(tmp, a.out)
    frames = sum(len(r["times"]) for r in runs)
    print(f"view: {a.out} ({len(html) / 1e6:.2f} MB: {len(runs)} run(s), {frames} frames; three.js "
          f"{len(three_js) / 1e6:.2f} MB)")


if __name__ == "__main__":
    main()
