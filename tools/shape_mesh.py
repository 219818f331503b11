#!/usr/bin/python3
"""Triangle meshes of the `visual` shapes of a scene (and of the default
inertia ellipsoid), in the body frame: for the ParaView files (vtk_run.py)
and the animations (animate_run.py). The browser viewer builds the same
shapes with three.js.

A shape in its own frame V (docs/scene_format.md, "visual"): a box centred
at the origin with edge lengths `size`; a sphere of `radius`; an ellipsoid
of `semi_axes`; a cylinder and a capsule along z_V, centred, `length` the
cylinder's (the capsule adds hemispheres of `radius`). Its points in the
body frame: x_B = position + R_BV x_V, R_BV from `quaternion` (w, x, y, z).
Round shapes are surfaces of revolution about z_V: a profile (r, z) turned
through `segments` angles; a profile point with r = 0 is a pole.
"""
import math

from run_motion import apply, quaternion_matrix


def _lathe(profile, segments):
    verts, tris, rings = [], [], []
    for r, z in profile:
        if r == 0.0:
            rings.append([len(verts)])
            verts.append([0.0, 0.0, z])
        else:
            start = len(verts)
            for s in range(segments):
                a = 2 * math.pi * s / segments
                verts.append([r * math.cos(a), r * math.sin(a), z])
            rings.append(list(range(start, start + segments)))
    for lower, upper in zip(rings, rings[1:]):
        if len(lower) == 1 and len(upper) == 1:
            continue
        for s in range(segments):
            s1 = (s + 1) % segments
            if len(lower) == 1:
                tris.append([lower[0], upper[s1], upper[s]])
            elif len(upper) == 1:
                tris.append([lower[s], lower[s1], upper[0]])
            else:
                tris.append([lower[s], lower[s1], upper[s1]])
                tris.append([lower[s], upper[s1], upper[s]])
    return verts, tris


def _sphere_profile(radius, rings, z_shift=0.0, lower=True, upper=True):
    pts = []
    for i in range(rings + 1):
        theta = math.pi * i / rings  # from the south pole
        if (theta < math.pi / 2 and not lower) or (theta > math.pi / 2 and not upper):
            continue
        r = radius * math.sin(theta) if 0 < i < rings else 0.0
        pts.append((r, -radius * math.cos(theta) + z_shift))
    return pts


def shape_in_own_frame(v, segments=16):
    """(vertices, triangles) of shape v in its own frame V."""
    kind = v["shape"]
    if kind == "box":
        hx, hy, hz = (0.5 * s for s in v["size"])
        verts = [[sx * hx, sy * hy, sz * hz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
        # Corners: index = 4 (x > 0) + 2 (y > 0) + (z > 0); two triangles per face.
        faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
        tris = [t for a, b, c, d in faces for t in ([a, b, c], [a, c, d])]
        return verts, tris
    rings = max(4, segments // 2)
    if kind in ("sphere", "ellipsoid"):
        verts, tris = _lathe(_sphere_profile(1.0 if kind == "ellipsoid" else v["radius"], rings), segments)
        if kind == "ellipsoid":
            a = v["semi_axes"]
            verts = [[p[0] * a[0], p[1] * a[1], p[2] * a[2]] for p in verts]
        return verts, tris
    r, h = v["radius"], 0.5 * v["length"]
    if kind == "cylinder":
        return _lathe([(0.0, -h), (r, -h), (r, h), (0.0, h)], segments)
    if kind == "capsule":
        profile = _sphere_profile(r, rings, -h, upper=False) + _sphere_profile(r, rings, h, lower=False)
        return _lathe(profile, segments)
    raise ValueError(f"unknown shape {kind!r}")


def shape_in_body_frame(v, segments=16):
    """(vertices, triangles) of shape v in the body frame."""
    verts, tris = shape_in_own_frame(v, segments)
    R = quaternion_matrix(v["quaternion"])
    p = v["position"]
    return [[p[i] + q for i, q in enumerate(apply(R, x))] for x in verts], tris


def body_mesh(body, segments=16):
    """All of a body's shapes as one mesh in its body frame."""
    verts, tris = [], []
    for v in body["visuals"]:
        vv, tt = shape_in_body_frame(v, segments)
        tris.extend([[i + len(verts) for i in t] for t in tt])
        verts.extend(vv)
    return verts, tris
