#!/usr/bin/python3
"""Bodies and joints of problems/bricard.toml: the threefold-symmetric
orthogonal Bricard 6R loop (six links a, DH twists alternating +-90 deg, no
offsets; Baker 1980), closed at theta_odd = THETA by Gauss-Newton on the
other five angles. Prints the [[bodies]] and [[joints]] tables and, on
stderr, the closure error and the rank of the six hinge screws (5: one
degree of freedom).

Usage: /usr/bin/python3 tools/make_bricard.py [THETA]   (default 0.7 rad)
"""
import sys

import numpy as np

A = 0.5
TWISTS = [np.pi / 2, -np.pi / 2] * 3


def dh(theta, alpha):
    c, s, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[c, -s * ca, s * sa, A * c], [s, c * ca, -c * sa, A * s], [0, sa, ca, 0], [0, 0, 0, 1.0]])


def frames(th):
    out = [np.eye(4)]
    for t, al in zip(th, TWISTS):
        out.append(out[-1] @ dh(t, al))
    return out


def miss(th):
    return (frames(th)[-1] - np.eye(4))[:3, :].ravel()


def close(theta):
    th = np.array([theta, 2.0, theta, 2.0, theta, 2.0])
    for _ in range(100):
        r = miss(th)
        J = np.zeros((r.size, 5))
        for k in range(5):
            e = np.zeros(6)
            e[k + 1] = 1e-7
            J[:, k] = (miss(th + e) - r) / 1e-7
        th[1:] += np.linalg.lstsq(J, -r, rcond=None)[0]
        if np.abs(r).max() < 1e-15:
            break
    return np.mod(th + np.pi, 2 * np.pi) - np.pi


def main():
    theta = float(sys.argv[1]) if len(sys.argv) > 1 else 0.7
    th = close(theta)
    F = frames(th)
    screws = np.array([np.concatenate([f[:3, 2], np.cross(f[:3, 3], f[:3, 2])]) for f in F[:6]])
    sv = np.linalg.svd(screws)[1]
    print(f"# closure error {np.abs(F[6] - np.eye(4)).max():.2g}, angles {th}, screw rank "
          f"{int((sv > 1e-9 * sv[0]).sum())}", file=sys.stderr)
    m, b, c = 1.0, 0.03, 0.02
    inertia = [m * (b * b + c * c) / 12, m * (A * A + c * c) / 12, m * (A * A + b * b) / 12]
    vec = lambda v: "[" + ", ".join(repr(float(x) + 0.0) for x in v) + "]"
    for i in range(1, 6):
        R = F[i + 1][:3, :3]
        print(f'[[bodies]]\nname = "link{i}"\nmass = {m}\ninertia_principal = {vec(inertia)}  '
              f'# 0.5 x 0.03 x 0.02 m bar along body x\nposition = {vec((F[i][:3, 3] + F[i + 1][:3, 3]) / 2)}\n'
              f'matrix = [{vec(R[0])},\n          {vec(R[1])},\n          {vec(R[2])}]\n')
    names = ["ground"] + [f"link{i}" for i in range(1, 6)]
    for i in range(6):
        print(f'[[joints]]\nname = "H{i}"\ntype = "revolute"\nbodies = ["{names[i - 1]}", "{names[i]}"]\n'
              f'point = {vec(F[i][:3, 3])}\naxis = {vec(F[i][:3, 2])}\n')


if __name__ == "__main__":
    main()
