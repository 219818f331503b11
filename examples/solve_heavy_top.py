"""Solve the heavy top once and draw what the run recorded.

    PYTHONPATH=build/python /usr/bin/python3 examples/solve_heavy_top.py

Writes out/examples/heavy_top.png: the orientation error against the closed
form, the constraint drift and the energy error over time.
"""
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import rigidae

scene = rigidae.load_scene("problems/heavy_top.toml")
run = rigidae.solve(scene, coordinates="quaternion", equations="euler", scheme="ggl", rtol=1e-10, atol=1e-10)
print(run)
print("steps", run.counters["steps"], "final q_WB", run.final["q_WB"])

exact = rigidae.exact_solution(scene, run.grid["t"])
error = rigidae.quaternion_angle(run.grid, exact)

fig, ax = plt.subplots(3, 1, sharex=True, figsize=(7, 7))
ax[0].semilogy(run.grid["t"], error + 1e-17)
ax[0].set_ylabel("orientation error, rad")
ax[1].semilogy(run.steps["t"], run.steps["drift_position"] + 1e-17)
ax[1].set_ylabel("|q.q - 1|")
ax[2].plot(run.steps["t"], run.steps["energy_rel_error"])
ax[2].set_ylabel("(H - H0)/|H0|")
ax[2].set_xlabel("t, s")
fig.suptitle(f"heavy top, {run.summary['representation']}, {run.summary['scheme']}")
os.makedirs("out/examples", exist_ok=True)
fig.savefig("out/examples/heavy_top.png", dpi=120)
print("figure: out/examples/heavy_top.png")
