#!/usr/bin/python3
"""Checks rigidae's layering: which module folder may include which.

A module is a folder under src/ and the same one under include/rigidae/.
A file of module M may include "rigidae/X/..." only when X is M or one of
ALLOWED[M]; SUNDIALS headers only in solver. Run with the source tree as
the argument (default: this script's parent folder). Exit 0 when clean, 1
with one line per violation (file:line: what and the rule), 2 when a
module is missing from the table (add it, with its place in the layers, to
ALLOWED and docs/architecture.md) or the table names a module with no
folder (a deleted module: remove its row, and its name from the other rows).

Usage: /usr/bin/python3 tools/check_layers.py [SOURCE_DIR]
"""
import os
import re
import sys

# Lowest layer first; each module may include the modules listed (and itself).
ALLOWED = {
    "core": set(),
    "so3": {"core"},
    "model": {"core", "so3"},
    "exact": {"core", "so3", "model"},
    "coords": {"core", "so3", "model"},
    "schemes": {"core", "so3", "model", "coords"},
    "solver": {"core"},
    "multibody": {"core", "so3", "model", "coords", "schemes", "solver"},
    "record": {"core", "so3", "model", "coords", "schemes", "multibody", "solver", "io"},
    "settings": {"core", "so3", "model", "coords", "schemes", "solver"},
    "io": {"core", "so3", "model", "exact", "schemes", "settings"},
    "app": {"core", "so3", "model", "exact", "coords", "schemes", "solver", "multibody", "record", "io",
            "settings"},
    "cli": {"core", "so3", "model", "exact", "coords", "schemes", "solver", "multibody", "record", "io",
            "settings", "app"},
}
# Of solver, the modules above it see only the problem interface and the
# driver's API; multibody (which implements the problem) only the interface.
SOLVER_HEADERS_FOR = {
    "settings": {"integrators.hpp"},
    "multibody": {"problem.hpp", "ode_problem.hpp"},
}
SUNDIALS = re.compile(r'#\s*include\s*<(ida|cvode|arkode|sundials|nvector|sunmatrix|sunlinsol|sunnonlinsol)/')
RIGIDAE = re.compile(r'#\s*include\s*"rigidae/([A-Za-z0-9_]+)/([^"]+)"')


def modules(root):
    for base in ("src", os.path.join("include", "rigidae")):
        top = os.path.join(root, base)
        if not os.path.isdir(top):
            continue
        for name in sorted(os.listdir(top)):
            folder = os.path.join(top, name)
            if os.path.isdir(folder):
                yield name, folder


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    problems, unknown = [], set()
    checked = 0
    present = {module for module, _ in modules(root)}
    stale = sorted(set(ALLOWED) - present)
    stale_names = sorted({m for allowed in ALLOWED.values() for m in allowed} - present)
    if stale or stale_names:
        print(f"check_layers: module(s) in the layer table with no folder under src/ or include/rigidae/: "
              f"{', '.join(sorted(set(stale) | set(stale_names)))}; remove them from ALLOWED (and "
              "SOLVER_HEADERS_FOR) in tools/check_layers.py and from docs/architecture.md")
        return 2
    for module, folder in modules(root):
        if module not in ALLOWED:
            unknown.add(module)
            continue
        for dirpath, _, files in os.walk(folder):
            for f in sorted(files):
                if not f.endswith((".cpp", ".hpp", ".h", ".cc")):
                    continue
                path = os.path.join(dirpath, f)
                rel = os.path.relpath(path, root)
                checked += 1
                with open(path, encoding="utf-8", errors="replace") as text:
                    for number, line in enumerate(text, 1):
                        m = RIGIDAE.search(line)
                        if m:
                            target, header = m.group(1), m.group(2)
                            if target != module and target not in ALLOWED[module]:
                                problems.append(f"{rel}:{number}: {module} includes rigidae/{target}/{header}; "
                                                f"{module} may include: {', '.join(sorted(ALLOWED[module])) or 'nothing'}")
                            elif target == "solver" and module in SOLVER_HEADERS_FOR and \
                                    header not in SOLVER_HEADERS_FOR[module]:
                                problems.append(f"{rel}:{number}: {module} includes rigidae/solver/{header}; of "
                                                f"solver it may include only {', '.join(sorted(SOLVER_HEADERS_FOR[module]))}")
                        if SUNDIALS.search(line) and not (module == "solver" and rel.startswith("src")):
                            problems.append(f"{rel}:{number}: SUNDIALS header outside src/solver/: "
                                            f"{line.strip()}")
    if unknown:
        print(f"check_layers: module folder(s) not in the layer table: {', '.join(sorted(unknown))}; "
              "add each to ALLOWED in tools/check_layers.py and to docs/architecture.md")
        return 2
    for p in problems:
        print(p)
    print(f"check_layers: {checked} files, {len(problems)} violation(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
