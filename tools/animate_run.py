#!/usr/bin/python3
"""Draws a run with matplotlib for papers and slides (`rigidae animate
RUN_DIR`; docs/viewer.md): an animation, GIF (Pillow) or MP4 (Debian's
ffmpeg), with --frames frames evenly spread over the output grid, and a
strobe picture OUT_strobe.png with --strobe poses overlaid, the earlier
ones fainter. The bodies are their `visual` shapes (else their inertia
ellipsoids, shape_mesh.py), the joints dots, the centres of mass' paths
lines; the view looks along the axis the motion spans least.

Usage: animate_run.py --geometry G.json --out FILE.gif|FILE.mp4
                      [--frames N] [--fps F] [--strobe K] RUN_DIR
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_motion  # noqa: E402
import shape_mesh  # noqa: E402

import matplotlib  # noqa: E402
import numpy as np  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import animation  # noqa: E402
from matplotlib.colors import to_rgb  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

COLOURS = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1", "#ff9da7", "#9c755f"]


LIGHT = np.array([0.3, -0.6, 0.75]) / np.linalg.norm([0.3, -0.6, 0.75])


def shaded(polys, colour):
    """The colour of each triangle, darker as its normal turns from the light
    (both faces lit alike: matplotlib does not know which side faces the view)."""
    n = np.cross(polys[:, 1] - polys[:, 0], polys[:, 2] - polys[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    light = 0.45 + 0.55 * np.abs(n @ LIGHT)
    return np.clip(np.array(to_rgb(colour))[None, :] * light[:, None], 0, 1)


class Drawing:
    def __init__(self, geometry, header, rows):
        self.g = geometry
        self.poses = run_motion.Poses(geometry, header)
        self.rows = rows
        self.meshes = [shape_mesh.body_mesh(b, segments=12) for b in geometry["bodies"]]
        # The centres of mass over the whole run: the axes' limits and the view.
        self.paths = [[run_motion.to_space(*self.poses.pose(r, k), b["center_of_mass"]) for r in rows]
                      for k, b in enumerate(geometry["bodies"])]
        pts = [p for path in self.paths for p in path]
        ext = geometry.get("extent", 1.0)
        lo = [min(p[i] for p in pts) - 0.5 * ext for i in range(3)]
        hi = [max(p[i] for p in pts) + 0.5 * ext for i in range(3)]
        half = 0.5 * max(h - l for l, h in zip(lo, hi))
        self.centre = [0.5 * (l + h) for l, h in zip(lo, hi)]
        self.half = half
        spans = [h - l for l, h in zip(lo, hi)]
        depth = min(range(3), key=lambda i: spans[i])
        self.view = {0: (15, 180 - 15), 1: (15, -90 + 15), 2: (60, -60)}[depth]

    def new_axes(self, fig):
        ax = fig.add_subplot(projection="3d")
        ax.view_init(elev=self.view[0], azim=self.view[1])
        for i, set_lim in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
            set_lim(self.centre[i] - self.half, self.centre[i] + self.half)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_zlabel("z (m)")
        return ax

    def draw_pose(self, ax, i, alpha=1.0, trails=True):
        """Draws row i: shapes, joint points, and the paths up to it."""
        row = self.rows[i]
        poses = [self.poses.pose(row, k) for k in range(len(self.meshes))]
        for k, (verts, tris) in enumerate(self.meshes):
            x, R = poses[k]
            space = [run_motion.to_space(x, R, p) for p in verts]
            polys = np.array([[space[a] for a in t] for t in tris])
            ax.add_collection3d(Poly3DCollection(polys, facecolors=shaded(polys, COLOURS[k % len(COLOURS)]),
                                                 edgecolor="none", alpha=alpha))
            if trails:
                path = self.paths[k][: i + 1]
                ax.plot([p[0] for p in path], [p[1] for p in path], [p[2] for p in path],
                        color=COLOURS[k % len(COLOURS)], lw=0.8)
        for j in self.g["joints"]:
            b = j["body"]
            p = run_motion.to_space(*poses[b], j["point"]) if b >= 0 else j["point"]
            ax.scatter([p[0]], [p[1]], [p[2]], color="#333333", s=10, alpha=alpha, depthshade=False)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--geometry", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--fps", type=float, default=20.0)
    ap.add_argument("--strobe", type=int, default=8)
    a = ap.parse_args()
    if len(a.runs) != 1:
        raise SystemExit(f"animate draws one run: give the folder of one run (of {len(a.runs)} in this folder)")
    ext = os.path.splitext(a.out)[1].lower()
    if ext not in (".gif", ".mp4"):
        raise SystemExit(f"--out {a.out}: the animation is a .gif or an .mp4")
    if a.frames < 2 or a.strobe < 1 or not a.fps > 0:
        raise SystemExit("--frames must be at least 2, --strobe at least 1 and --fps positive")
    geometry = run_motion.load_geometry(a.geometry)
    header, rows = run_motion.read_trajectory(a.runs[0])
    d = Drawing(geometry, header, rows)
    name = geometry.get("scene", "run")

    keep = run_motion.thin(len(rows), a.frames)
    fig = plt.figure(figsize=(6.4, 4.8), dpi=100)

    def frame(n):
        fig.clf()
        ax = d.new_axes(fig)
        i = keep[n]
        d.draw_pose(ax, i)
        ax.set_title(f"{name}   t = {d.poses.time(rows[i]):.3f} s", fontsize=10)

    anim = animation.FuncAnimation(fig, frame, frames=len(keep))
    writer = animation.PillowWriter(fps=a.fps) if ext == ".gif" else animation.FFMpegWriter(fps=a.fps, codec="libx264",
                                                                                             extra_args=["-pix_fmt", "yuv420p"])
    tmp = a.out + ".part" + ext
    anim.save(tmp, writer=writer)
    os.replace(tmp, a.out)
    plt.close(fig)

    strobe = os.path.splitext(a.out)[0] + "_strobe.png"
    fig = plt.figure(figsize=(6.4, 4.8), dpi=150)
    ax = d.new_axes(fig)
    poses = run_motion.thin(len(rows), a.strobe)
    for n, i in enumerate(poses):
        d.draw_pose(ax, i, alpha=0.25 + 0.75 * (n + 1) / len(poses), trails=(n == len(poses) - 1))
    t = [d.poses.time(rows[i]) for i in poses]
    ax.set_title(f"{name}: {len(poses)} poses, t = {t[0]:.3g} to {t[-1]:.3g} s", fontsize=10)
    fig.savefig(strobe)
    plt.close(fig)
    print(f"animate: {a.out} ({len(keep)} frames at {a.fps:g} fps), {strobe} ({len(poses)} poses)")


if __name__ == "__main__":
    main()
