"""poet.__version__ is the project's version: the top CMakeLists.txt's project(... VERSION ...), which the build
passes to the C++ core."""

import pathlib
import re

import poet

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]


def test_version_is_the_projects():
    cmake = (SOURCE_DIR / "CMakeLists.txt").read_text(encoding="utf-8")
    version = re.search(r"^project\(poet VERSION (\S+)", cmake, re.MULTILINE).group(1)
    assert poet.__version__ == poet._poet.__version__ == version
    assert re.fullmatch(r"\d+\.\d+\.\d+", poet.__version__)
