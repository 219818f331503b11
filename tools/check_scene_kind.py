#!/usr/bin/python3
"""Checks that nothing outside the system module branches on the scene's kind.

Every scene runs as a system of bodies (docs/architecture.md, "Data flow"):
a one-body scene (schema 1) is a system of one pivoted body, and the code
above the model (app, cli, settings, the Python module) must not ask which
kind of scene it holds. This script finds the places that do, as written in
C++: the optional `multibody` spec tested as a boolean (`if (scene.multibody)`,
`!s.multibody`, `scene.multibody ? a : b`, `scene.multibody.has_value()`,
`x.multibody && ...`) and the `one_body_scene` flag, outside the modules
whose business the kind is:

  src/model      the scene and its spec (one_body_system / as_system turn any
                 scene into a system)
  src/io         the loaders, which build the spec, and the writers of it
  src/exact      closed forms, which exist for one body only
  src/multibody, src/coords, src/schemes   the system itself
  src/record     the two column sets, chosen once by the system
                 (record/run_columns.cpp) and told apart by their files'
                 reader (record/trajectory_csv.cpp)

and the lines listed in ALLOWED_LINES (each with its reason; none today). Dereferences
(`*scene.multibody`, `scene.multibody->joints`) are not branches and pass.

Usage: /usr/bin/python3 tools/check_scene_kind.py [SOURCE_DIR]
Exit 0 when clean, 1 with one `file:line: text` per branch found.
"""
import os
import re
import sys

SYSTEM_MODULES = ("model", "io", "exact", "multibody", "coords", "schemes", "record")

# The optional spec used as a boolean, or the one-body flag.
BRANCH = re.compile(
    r"(!\s*[A-Za-z_][A-Za-z_0-9.]*\.multibody\b(?!\s*(->|\.)))"
    r"|((?<![*\w.])[A-Za-z_][A-Za-z_0-9.]*\.multibody\s*(\?|&&|\|\||\)))"
    r"|(\.multibody\.has_value\s*\()"
    r"|(\bone_body_scene\b)"
)

# (path relative to the source tree, a substring of the line): allowed, with the reason.
# None today; an entry names its file and line text and says why.
ALLOWED_LINES = []


def scanned_files(root):
    for top in ("src", "include/rigidae", "python/src"):
        base = os.path.join(root, top)
        for dirpath, _, files in os.walk(base):
            rel_dir = os.path.relpath(dirpath, base)
            module = rel_dir.split(os.sep)[0]
            if top in ("src", "include/rigidae") and module in SYSTEM_MODULES:
                continue
            for f in sorted(files):
                if f.endswith((".cpp", ".hpp", ".h")):
                    yield os.path.join(dirpath, f)


def strip_comment(line):
    i = line.find("//")
    return line if i < 0 else line[:i]


def main(argv):
    root = argv[1] if len(argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    found = []
    for path in scanned_files(root):
        rel = os.path.relpath(path, root)
        with open(path, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                code = strip_comment(line)
                if not BRANCH.search(code):
                    continue
                if any(rel == p and s in code for p, s in ALLOWED_LINES):
                    continue
                found.append(f"{rel}:{n}: {line.strip()}")
    for x in found:
        print(x)
    if found:
        print(f"{len(found)} branch(es) on the scene's kind outside the system module "
              "(use as_system(scene) and the system's facts; tools/check_scene_kind.py says why)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
