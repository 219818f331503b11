#!/usr/bin/python3
"""README.md's measured tables, generated from recorded results by one command.

Usage:
    /usr/bin/python3 tools/readme_tables.py --measure   # run the measurements (about a minute), record, rewrite
    /usr/bin/python3 tools/readme_tables.py --studies   # rerun the three studies (4.5 min on a quiet 2-core machine), their figures, rewrite
    /usr/bin/python3 tools/readme_tables.py --measure --studies   # both: every table and study figure with today's timings
    /usr/bin/python3 tools/readme_tables.py             # rewrite README.md from the recorded results
    /usr/bin/python3 tools/readme_tables.py --check     # exit 1 if README.md differs from them (CI)

Each table sits between two markers in README.md:

    <!-- generated: NAME (tools/readme_tables.py; do not edit by hand) -->
    | ... |
    <!-- end -->

and is rebuilt from a recorded file; nothing outside the markers is touched,
and rewriting its own output changes nothing. The tables:

  heavy_top_compare  `rigidae compare problems/heavy_top.toml --repeat 3`: its
                     compare.csv, kept as docs/measured/heavy_top_compare.csv
  heavy_top_six      the six coordinates x equations with scheme ggl at rtol =
                     atol = 1e-10 (tools/six_combinations.py's runs), final
                     angle to the closed form: docs/measured/heavy_top_six.csv
  multibody          the shipped multibody scenes with the default combination:
                     docs/measured/multibody.csv (steps, wall of one run)
  study_best         the fastest run meeting each error target, from the
                     committed studies docs/studies/*/results.csv

--studies reruns studies/{heavy_top,free_body,lagrange_top}.toml with today's
binary and timings, replaces docs/studies/NAME/ (results.csv, best.md) and
docs/figures/study_NAME_*.png|pdf (tools/plot_study.py), then rewrites the
tables: README's study figures and study_best come from one command.

--measure needs a Release build in ./build (bash tools/build.sh). Wall times
are single runs (compare: medians of 3) on whatever machine runs it; counts and
errors are exact and repeatable.
"""
import argparse
import csv
import io
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MEASURED = os.path.join(ROOT, "docs", "measured")
BEGIN = re.compile(r"^<!-- generated: ([a-z0-9_]+)\b.*-->\s*$")
END = "<!-- end -->"
MULTIBODY_SCENES = ["heavy_top_absolute", "double_pendulum", "four_bar", "slider_mechanism", "chain_10"]
STUDIES = [("heavy_top", "heavy top"), ("free_body", "free body"), ("lagrange_top", "Lagrange top")]
TARGETS = [1e-3, 1e-6, 1e-9]


# ----------------------------------------------------------------------------
# Reading and formatting


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def e2(x):
    """Two significant digits in the compare table's style (1.2e-05); '–' for nothing measured."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return "–"
    return "–" if math.isnan(v) else f"{v:.1e}"


def short(x):
    """1e-07 -> 1e-7."""
    s = f"{float(x):g}"
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m.group(1) == "-" else "") + m.group(2), s)


def thousands(n):
    return f"{int(n):,}"


def cell(text):
    return str(text).replace("|", "\\|")


def table(header, rows):
    out = ["| " + " | ".join(cell(h) for h in header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(cell(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


# ----------------------------------------------------------------------------
# The tables


def heavy_top_compare():
    rows = read_csv(os.path.join(MEASURED, "heavy_top_compare.csv"))
    header = ["combination", "status", "steps", "residual evals", "wall s", "max |Phi|", "max |dPhi/dt|",
              "max |dE/E|", "error at end, rad", "max error, rad", "restarts", "warnings"]
    body = []
    for r in rows:
        constrained = r["coordinates"] != "euler"
        evals = int(r["residual_evals"]) + int(r["jacobian_residual_evals"])
        warnings = re.sub(r"vertical_angular_momentum", "L_z", r.get("warnings", ""))
        body.append([r["combination"], r["status"], r["steps"], evals, f"{float(r['wall_s']):.3f}",
                     e2(r["max_drift_position"]) if constrained else "–",
                     e2(r["max_drift_velocity"]) if constrained else "–",
                     e2(r["max_abs_energy_rel_error"]), e2(r["error_final_rad"]), e2(r["error_max_rad"]),
                     r["restarts"], warnings])
    return table(header, body)


def heavy_top_six():
    rows = read_csv(os.path.join(MEASURED, "heavy_top_six.csv"))
    header = ["combination", "steps", "residual evals (incl. Jacobians)", "Jacobians", "wall s",
              "max position drift", "final angle to the closed form, rad"]
    body = [[r["combination"], r["steps"], r["residual_evals"], r["jacobian_evals"], f"{float(r['wall_s']):.2f}",
             e2(r["max_drift_position"]) if r["combination"].split("/")[0] != "euler" else "–",
             e2(r["error_final_rad"])] for r in rows]
    return table(header, body)


def multibody():
    rows = read_csv(os.path.join(MEASURED, "multibody.csv"))
    body = [[r["scene"], f"{short(r['t_end'])} s", thousands(r["steps"]), f"{float(r['wall_s']):.2f} s", r["status"]]
            for r in rows]
    return table(["scene", "t_end", "steps", "wall", "status"], body)


def study_best():
    header = ["scene"] + [f"<= 1e{round(math.log10(t))} rad" for t in TARGETS]
    body = []
    for folder, label in STUDIES:
        rows = [r for r in read_csv(os.path.join(ROOT, "docs", "studies", folder, "results.csv"))
                if r["status"] == "success" and r["orientation_error_final_rad"] not in ("", "nan")]
        line = [label]
        for target in TARGETS:
            ok = [r for r in rows if float(r["orientation_error_final_rad"]) <= target]
            if ok:
                best = min(ok, key=lambda r: float(r["wall_min_s"]))
                wall = float(best["wall_min_s"])
                wall_text = f"{wall * 1e3:.2g} ms" if wall < 0.01 else f"{wall:.2g} s"
                line.append(f"{best['combination']}, rtol {short(best['rtol'])}: {wall_text}")
            else:
                closest = min(rows, key=lambda r: float(r["orientation_error_final_rad"]))
                line.append(f"none at rtol >= {short(min(float(r['rtol']) for r in rows))} (best "
                            f"{float(closest['orientation_error_final_rad']):.1e}, {closest['combination']})")
        body.append(line)
    return table(header, body)


TABLES = {"heavy_top_compare": heavy_top_compare, "heavy_top_six": heavy_top_six, "multibody": multibody,
          "study_best": study_best}


# ----------------------------------------------------------------------------
# Markers


def blocks(text):
    """[(name, first line index inside, end line index)] of the generated blocks; ValueError on a
    begin without an end, an end without a begin, nesting or an unknown name."""
    lines = text.split("\n")
    found, open_at, name = [], None, None
    for i, line in enumerate(lines):
        m = BEGIN.match(line)
        if m:
            if open_at is not None:
                raise ValueError(f"README.md:{i + 1}: 'generated: {m.group(1)}' inside '{name}' (line {open_at})")
            if m.group(1) not in TABLES:
                raise ValueError(f"README.md:{i + 1}: unknown table '{m.group(1)}'; known: {', '.join(TABLES)}")
            open_at, name = i + 1, m.group(1)
        elif line.strip() == END:
            if open_at is None:
                raise ValueError(f"README.md:{i + 1}: '{END}' without a '<!-- generated: NAME -->' before it")
            found.append((name, open_at, i))
            open_at, name = None, None
    if open_at is not None:
        raise ValueError(f"README.md:{open_at}: 'generated: {name}' has no '{END}'")
    return found


def rewrite(text):
    """README text with every generated block rebuilt."""
    lines = text.split("\n")
    out, last = [], 0
    for name, start, end in blocks(text):
        out += lines[last:start]
        out += TABLES[name]().split("\n")
        last = end
    out += lines[last:]
    return "\n".join(out)


# ----------------------------------------------------------------------------
# Measuring (runs the CLI; minutes, not for CI)


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 1):
        sys.exit(f"readme_tables: {' '.join(cmd)} exited {p.returncode}:\n{p.stderr}")
    return p


def write_csv(path, header, rows):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)


def measure(rigidae, work):
    scene = os.path.join(ROOT, "problems", "heavy_top.toml")
    out = os.path.join(work, "compare")
    run([rigidae, "compare", scene, "--repeat", "3", "--out", out, "--quiet"])
    os.makedirs(MEASURED, exist_ok=True)
    shutil.copyfile(os.path.join(out, "compare.csv"), os.path.join(MEASURED, "heavy_top_compare.csv"))

    # the six combinations at rtol 1e-10 with ggl, their error from compare's own measurement
    six = os.path.join(work, "six")
    run([rigidae, "compare", scene, "--only", "*/*/ggl,euler/*/*", "--rtol", "1e-10", "--atol", "1e-10",
         "--repeat", "1", "--out", six, "--quiet"])
    rows = []
    for r in read_csv(os.path.join(six, "compare.csv")):
        rows.append([f"{r['coordinates']}/{r['equations']}", r["steps"],
                     int(r["residual_evals"]) + int(r["jacobian_residual_evals"]), r["jacobian_evals"], r["wall_s"],
                     r["max_drift_position"], r["error_final_rad"]])
    write_csv(os.path.join(MEASURED, "heavy_top_six.csv"),
              ["combination", "steps", "residual_evals", "jacobian_evals", "wall_s", "max_drift_position",
               "error_final_rad"], rows)

    rows = []
    for name in MULTIBODY_SCENES:
        d = os.path.join(work, name)
        run([rigidae, "solve", os.path.join(ROOT, "problems", name + ".toml"), "--out", d, "--quiet"])
        with open(os.path.join(d, "summary.json")) as f:
            s = json.load(f)
        conf = s.get("configuration") or {}  # single-body summaries; multibody ones are flat
        t_end = (conf.get("time") or {}).get("end", s.get("t_reached"))
        rows.append([name, t_end, (s.get("counters") or {}).get("steps"),
                     s.get("wall_time_s"), s.get("status")])
    write_csv(os.path.join(MEASURED, "multibody.csv"), ["scene", "t_end", "steps", "wall_s", "status"], rows)




def rerun_studies(rigidae, work):
    for name, _ in STUDIES:
        out = os.path.join(work, name)
        print(f"readme_tables: study {name} ...", flush=True)
        p = subprocess.run([rigidae, "study", os.path.join(ROOT, "studies", name + ".toml"), "--out", out,
                            "--quiet", "--no-plot"], capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"readme_tables: the study {name} exited {p.returncode}:\n{p.stderr}")
        dest = os.path.join(ROOT, "docs", "studies", name)
        os.makedirs(dest, exist_ok=True)
        for f in ("results.csv", "best.md"):
            shutil.copyfile(os.path.join(out, f), os.path.join(dest, f))
        p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "plot_study.py"), dest, "--figures",
                            os.path.join(ROOT, "docs", "figures"), "--prefix", "study_", "--quiet"],
                           capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"readme_tables: plot_study.py on {dest} exited {p.returncode}:\n{p.stderr}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--measure", action="store_true", help="run the measurements first (needs ./build/rigidae)")
    ap.add_argument("--studies", action="store_true",
                    help="rerun the three studies and their figures first (needs ./build/rigidae)")
    ap.add_argument("--check", action="store_true", help="exit 1 if README.md is not what the records give")
    ap.add_argument("--readme", default=os.path.join(ROOT, "README.md"))
    ap.add_argument("--rigidae", default=os.path.join(ROOT, "build", "rigidae"))
    a = ap.parse_args(argv)
    if a.measure:
        with tempfile.TemporaryDirectory(prefix="readme_tables.") as work:
            measure(a.rigidae, work)
    if a.studies:
        with tempfile.TemporaryDirectory(prefix="readme_tables.") as work:
            rerun_studies(a.rigidae, work)
    with open(a.readme) as f:
        text = f.read()
    try:
        new = rewrite(text)
    except ValueError as e:
        print(f"readme_tables: error: {e}", file=sys.stderr)
        return 2
    if a.check:
        if new != text:
            print(f"readme_tables: {a.readme} differs from the recorded results; run "
                  f"'/usr/bin/python3 tools/readme_tables.py'", file=sys.stderr)
            return 1
        return 0
    if new != text:
        with open(a.readme, "w") as f:
            f.write(new)
        print(f"readme_tables: rewrote {len(blocks(new))} tables in {a.readme}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
