#!/usr/bin/python3
"""Writes an N-link chain scene (schema_version 2) to a file.

    /usr/bin/python3 tools/make_chain.py N [--joint spherical|revolute] [--out FILE]
        [--length 0.1] [--mass 0.1] [--spin 1.0] [--end 1.0] [--output-step 0.01]

The chain starts horizontal along +x: link k (k = 1..N) is a square bar of
length L and side L/10, centre of mass at ((k - 1/2) L, 0, 0), body axes =
space axes. Joint j1 holds link1 to the ground at the origin; joint jk joins
link(k-1) and link(k) at ((k - 1) L, 0, 0).
  revolute:  every hinge axis is space y: a planar chain, released from rest.
  spherical: the whole chain starts turning rigidly about the vertical at
             --spin rad/s (every joint's velocity condition holds: the links
             share one angular velocity and each centre moves at w x r), so
             it falls and swings in 3D.
Gravity -9.81 m/s^2 along z. About 340 bytes per link: the file stays
under the loader's scene size limit (64 MiB) up to about 190,000 links.
"""
import argparse
import pathlib
import sys


def number(x: float) -> str:
    """Shortest text that reads back as the same double."""
    return repr(float(x))


def vec(v) -> str:
    return "[" + ", ".join(number(x) for x in v) + "]"


def chain(n: int, joint: str, length: float, mass: float, spin: float, end: float, output_step: float) -> str:
    side = length / 10.0
    # A bar along x: J_x = m (s^2 + s^2) / 12, J_y = J_z = m (L^2 + s^2) / 12.
    j_axis = mass * 2.0 * side * side / 12.0
    j_cross = mass * (length * length + side * side) / 12.0
    w = spin if joint == "spherical" else 0.0
    out = [
        f"# A chain of {n} links and {joint} joints, written by tools/make_chain.py",
        f"# ({n} {joint} --length {length} --mass {mass}"
        + (f" --spin {spin}" if joint == "spherical" else "") + f" --end {end}).",
        "# Starts horizontal along +x"
        + (f", turning rigidly about the vertical at {spin} rad/s." if w else ", at rest."),
        "# What makes it interesting: the cost per step must grow linearly with the",
        "# number of links (sparse iteration matrix, KLU above a measured size).",
        "",
        "schema_version = 2",
        f'name = "chain_{n}{"" if joint == "spherical" else "_revolute"}"',
        f'description = "{n}-link chain of {joint} joints (tools/make_chain.py)"',
        "",
    ]
    for k in range(1, n + 1):
        x = (k - 0.5) * length
        out += [
            "[[bodies]]",
            f'name = "link{k}"',
            f"mass = {number(mass)}",
            f"inertia_principal = {vec([j_axis, j_cross, j_cross])}",
            f"position = {vec([x, 0.0, 0.0])}",
        ]
        if w:
            # Rigid turn about z through the origin: v = w e_z x (x, 0, 0) = (0, w x, 0).
            out += [f"velocity = {vec([0.0, w * x, 0.0])}", f"angular_velocity = {vec([0.0, 0.0, w])}"]
        out.append("")
    for k in range(1, n + 1):
        out += [
            "[[joints]]",
            f'name = "j{k}"',
            f'type = "{joint}"',
            f'bodies = ["{"ground" if k == 1 else f"link{k - 1}"}", "link{k}"]',
            f"point = {vec([(k - 1) * length, 0.0, 0.0])}",
        ]
        if joint == "revolute":
            out.append("axis = [0.0, 1.0, 0.0]")
        out.append("")
    out += [
        "[gravity]",
        "acceleration = [0.0, 0.0, -9.81]",
        "",
        "[time]",
        f"end = {number(end)}",
        f"output_step = {number(output_step)}",
        "",
        "[formulation]",
        'coordinates = "quaternion"',
        'equations = "euler"',
        'scheme = "ggl"',
        "",
        "[solver]",
        "rtol = 1e-8",
        "atol = 1e-8",
        "",
    ]
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("links", type=int, help="number of links N (1 to 100000)")
    ap.add_argument("--joint", choices=["spherical", "revolute"], default="spherical")
    ap.add_argument("--length", type=float, default=0.1, help="link length, m")
    ap.add_argument("--mass", type=float, default=0.1, help="link mass, kg")
    ap.add_argument("--spin", type=float, default=1.0, help="initial turn about the vertical, rad/s (spherical)")
    ap.add_argument("--end", type=float, default=1.0, help="end time, s")
    ap.add_argument("--output-step", type=float, default=0.01, help="output step, s")
    ap.add_argument("--out", help="file to write (default: problems/chain_N.toml)")
    args = ap.parse_args()
    if not 1 <= args.links <= 100000:
        sys.exit("make_chain.py: N must be from 1 to 100000")
    if not (args.length > 0 and args.mass > 0 and args.end > 0 and args.output_step > 0):
        sys.exit("make_chain.py: --length, --mass, --end and --output-step must be > 0")
    out = pathlib.Path(args.out or pathlib.Path(__file__).resolve().parent.parent / "problems" / f"chain_{args.links}.toml")
    out.write_text(chain(args.links, args.joint, args.length, args.mass, args.spin, args.end, args.output_step))
    size = out.stat().st_size
    print(f"{out}: {args.links} links, {args.joint} joints, {size} bytes")
    if size > 64 << 20:
        print(f"make_chain.py: warning: {out} is larger than the 64 MiB (67108864 bytes) a scene file may have; "
              "rigidae will refuse it", file=sys.stderr)


if __name__ == "__main__":
    main()
