"""Shared paths for the Python module's tests: ctest passes them in the environment (tests/CMakeLists.txt)."""

import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("POET_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


# A POET run of a few seconds on one thread, checkpointed every iteration: the runs test_run.py reads and
# test_start.py starts.
TINY_RUN = """
seed: 5
iterations: 8
checkpoint_interval: 1
es { perturbations: 3 }
walker { max_steps: 100 }
poet { mutation_interval: 2 transfer_interval: 2 repro_threshold: -1000 mc_low: -1000 mc_high: 1000
       max_children: 3 max_admitted: 1 active_cap: 3 }
"""


@pytest.fixture(scope="session")
def tiny_config(tmp_path_factory):
    """TINY_RUN's config file."""
    path = tmp_path_factory.mktemp("config") / "tiny.textproto"
    path.write_text(TINY_RUN)
    return path


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
