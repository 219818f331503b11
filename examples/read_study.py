"""Read an accuracy study's results table: the cheapest run of each
combination that reaches an error target.

    PYTHONPATH=build/python /usr/bin/python3 examples/read_study.py
        reads the shipped docs/studies/lagrange_top/results.csv
    PYTHONPATH=build/python /usr/bin/python3 examples/read_study.py studies/free_body.toml out/free_body
        runs (or resumes: complete runs are kept) that study first

With pandas the table is a DataFrame, otherwise a dict of numpy arrays.
"""
import sys

import numpy as np

import rigidae

if len(sys.argv) > 2:
    table = rigidae.study(sys.argv[1], out=sys.argv[2], progress=lambda done, skipped, failed, total, last:
                          print(f"\r[{done}/{total}] {last:60.60}", end="", file=sys.stderr))
    print(file=sys.stderr)
else:
    table = rigidae.read_study("docs/studies/lagrange_top")

target = 1e-4  # rad, orientation error at the end
c = {k: np.asarray(table[k]) for k in ("combination", "rtol", "status", "steps", "wall_median_s",
                                        "orientation_error_final_rad")}
ok = c["status"] == "success"
print(f"{ok.sum()} of {len(ok)} runs succeeded; cheapest run per combination with error <= {target:g} rad:")
for combination in sorted(set(c["combination"])):
    pick = ok & (c["combination"] == combination) & (c["orientation_error_final_rad"] <= target)
    if not pick.any():
        print(f"  {combination:32} never")
        continue
    i = np.flatnonzero(pick)[np.argmin(c["wall_median_s"][pick])]
    print(f"  {combination:32} rtol {c['rtol'][i]:.0e}: {c['steps'][i]:7d} steps, "
          f"{c['wall_median_s'][i] * 1e3:7.2f} ms, error {c['orientation_error_final_rad'][i]:.1e} rad")
