"""Shared paths for the Python module's tests: ctest passes them in the environment (tests/CMakeLists.txt)."""

import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("POET_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def walker_path():
    return SOURCE_DIR / "data" / "walkers" / "flat-walker.json"


@pytest.fixture
def eval_bin():
    path = os.environ.get("POET_EVAL_BIN")
    if not path:
        pytest.skip("POET_EVAL_BIN is not set (ctest sets it)")
    return path


def pytest_sessionfinish(session, exitstatus):
    """The tests' temporary directories (runs, files) go with the session, whatever its outcome."""
    import shutil

    factory = getattr(session.config, "_tmp_path_factory", None)
    if factory is not None:
        try:
            shutil.rmtree(factory.getbasetemp(), ignore_errors=True)
        except (OSError, ValueError):
            pass
