"""README "Install" says what tests/install/ runs: the same commands, the same
target and paths (the tests themselves are CTest's install.cmake and install.pip)."""
import re

from conftest import SOURCE

README = (SOURCE / "README.md").read_text()


def install_section():
    m = re.search(r"^## Install\n(.*?)^## ", README, re.S | re.M)
    assert m, "README has an Install section"
    return m.group(1)


def test_readme_install_commands_are_the_tested_ones():
    text = install_section()
    check_install = (SOURCE / "tests" / "install" / "check_install.py").read_text()
    check_pip = (SOURCE / "tests" / "install" / "check_pip_install.py").read_text()
    consumer = (SOURCE / "tests" / "install" / "consumer" / "CMakeLists.txt").read_text()
    assert "cmake --install build --prefix" in text and '"--install", build, "--prefix"' in check_install
    for rel in ("bin/rigidae", "lib/librigidae_core.a", "include/rigidae/", "share/rigidae/tools/plot_",
                "lib/cmake/rigidae/", "rigidaeConfig.cmake", "rigidaeConfigVersion.cmake"):
        assert rel in text, rel
    for rel in ("bin/rigidae", "librigidae_core.a", "include/rigidae/app/solve.hpp", "share/rigidae/tools/plot_solve.py",
                "cmake/rigidae/rigidaeConfig.cmake", "cmake/rigidae/rigidaeConfigVersion.cmake"):
        assert rel in check_install, rel
    assert "find_package(rigidae 0.1 REQUIRED)" in text and "find_package(rigidae 0.1 REQUIRED)" in consumer
    assert "rigidae::rigidae_core" in text and "rigidae::rigidae_core" in consumer
    assert "/usr/bin/python3 -m venv --system-site-packages" in text
    assert '"/usr/bin/python3", "-m", "venv", "--system-site-packages"' in check_pip
    assert "RIGIDAE_BUILD_DIR=build" in text and "RIGIDAE_BUILD_DIR=str(build)" in check_pip
    assert "pip install --no-build-isolation --no-index ." in text
    assert '"install", "--no-build-isolation", "--no-index"' in check_pip
    assert "ctest --test-dir build -L install" in text
    for name in ("RIGIDAE_TOOLS_DIR", "RIGIDAE_SHOW_PLOT_SCRIPT", "../share/rigidae/tools"):
        assert name in text, name
