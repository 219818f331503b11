#!/usr/bin/python3
"""Writes a CTest script that labels each doctest case with its suite (tier).

    /usr/bin/python3 tools/ctest_labels.py TEST_BINARY OUT.cmake

Runs TEST_BINARY --list-test-cases --reporters=xml once and writes one
set_tests_properties(NAME PROPERTIES LABELS SUITE) per case. tests/CMakeLists.txt
adds OUT.cmake to the test directory's TEST_INCLUDE_FILES after the file of
doctest_discover_tests, which defines the tests. (Debian's doctest 2.4.9 can
label by suite itself, ADD_LABELS, but it asks one case at a time with an
unescaped filter: a name holding a comma matches nothing and gets no label.)
"""
import subprocess
import sys
import xml.etree.ElementTree as ET


def main():
    binary, out = sys.argv[1], sys.argv[2]
    listing = subprocess.run([binary, "--list-test-cases", "--reporters=xml"], capture_output=True, text=True,
                             check=True).stdout
    lines = []
    for case in ET.fromstring(listing).iter("TestCase"):
        name, suite = case.get("name"), case.get("testsuite") or "unlabelled"
        if "]==]" in name:
            sys.exit(f"{binary}: test name {name!r} holds ']==]', which a CMake bracket argument cannot")
        lines.append(f"set_tests_properties([==[{name}]==] PROPERTIES LABELS {suite})")
    text = "\n".join(lines) + "\n"
    try:
        if open(out).read() == text:
            return
    except OSError:
        pass
    with open(out, "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
