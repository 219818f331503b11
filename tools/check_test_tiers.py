#!/usr/bin/python3
"""Checks the test tiers of tests/unit (docs/testing.md).

Every doctest file declares its tier once, after its includes:
TEST_SUITE_BEGIN("unit") for tests of one piece of code in-process, or
TEST_SUITE_BEGIN("system") for tests that run the rigidae binary or a whole
solve with its files; single test cases measured above a few seconds carry
`* doctest::test_suite("slow")`. CTest turns the suite into the test's label
(doctest_discover_tests ADD_LABELS), so `ctest -LE slow` is the fast tier.
A file that runs the command line (run_cli) must be "system". A test name
must not hold ';': CTest reads it as a list separator, splits the case into
two tests that each match nothing, and both pass without running anything.

    /usr/bin/python3 tools/check_test_tiers.py [SOURCE_DIR]

Exit 0 when every file is in order, 1 with `file: problem` lines otherwise.
"""
import pathlib
import re
import sys

TIERS = ("unit", "system")


def problems(root):
    for f in sorted((root / "tests" / "unit").glob("test_*.cpp")):
        text = f.read_text()
        rel = f.relative_to(root)
        suites = re.findall(r'^\s*TEST_SUITE_BEGIN\("([^"]*)"\);', text, re.M)
        if len(suites) != 1 or suites[0] not in TIERS:
            yield f"{rel}: needs exactly one TEST_SUITE_BEGIN(\"unit\") or TEST_SUITE_BEGIN(\"system\"), has {suites}"
            continue
        if not re.search(r"^\s*TEST_SUITE_END\(\);", text, re.M):
            yield f"{rel}: TEST_SUITE_BEGIN without TEST_SUITE_END"
        for name in re.findall(r'TEST_CASE\(\s*"((?:[^"\\]|\\.)*)"', text):
            if ";" in name:
                yield f"{rel}: test name {name!r} holds ';', which CTest splits into two tests that run nothing"
        if suites[0] == "unit" and "run_cli(" in text:
            yield f"{rel}: runs the command line (run_cli) but is in the \"unit\" tier; make it \"system\""


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    found = list(problems(root))
    for p in found:
        print(p)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
