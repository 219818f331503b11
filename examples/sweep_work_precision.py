"""A parameter sweep rigidae's study files have no axis for: the heavy top's
initial spin, for two formulations over a range of tolerances, measured
against the closed form; a work-precision figure (steps against error).

    PYTHONPATH=build/python /usr/bin/python3 examples/sweep_work_precision.py

Writes out/examples/work_precision.png.
"""
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import rigidae

base = rigidae.read_scene_dict("problems/heavy_top.toml")
fig, ax = plt.subplots(figsize=(7, 5))
for spin, marker in ((50.0, "o"), (150.0, "s")):
    scene = dict(base, initial=dict(base["initial"], angular_velocity=[0.0, spin, -4.61538]))
    for coordinates, equations in (("quaternion", "euler"), ("quaternion", "lagrange")):
        steps, errors = [], []
        for rtol in 10.0 ** -np.arange(5, 11):
            run = rigidae.solve(scene, coordinates=coordinates, equations=equations, rtol=rtol, atol=rtol,
                                record="grid")
            exact = rigidae.exact_solution(run.scene, run.grid["t"])
            steps.append(run.counters["steps"])
            errors.append(rigidae.quaternion_angle(run.grid, exact).max())
        ax.loglog(errors, steps, marker=marker, label=f"spin {spin:g} rad/s, {coordinates}/{equations}")
ax.set_xlabel("max orientation error over the grid, rad")
ax.set_ylabel("IDA steps")
ax.legend()
os.makedirs("out/examples", exist_ok=True)
fig.savefig("out/examples/work_precision.png", dpi=120)
print("figure: out/examples/work_precision.png")
