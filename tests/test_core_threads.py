"""The process-wide thread cap (DESIGN.md, "Threads"): MESHSMITH_NUM_THREADS and
meshsmith.core.set_num_threads cap TBB's workers, results do not depend on the cap, bad values
are an InputError (or, in the environment, a warning at import)."""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import meshsmith
from meshsmith import core, datasets, geometry


def run_python(code: str, **environment: str) -> subprocess.CompletedProcess:
    env = {name: value for name, value in os.environ.items() if name != "MESHSMITH_NUM_THREADS"}
    env.update(environment)
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=env,
                          timeout=120)


@pytest.fixture
def restore_cap():
    yield
    core.set_num_threads(None)


def test_cap_is_reported_and_lifted(restore_cap):
    core.set_num_threads(1)
    assert core.num_threads() == 1
    core.set_num_threads(None)
    assert core.num_threads() >= 1


@pytest.mark.parametrize("bad", [0, -2, 1.5, "two", True, 10**6])
def test_bad_cap_is_an_input_error(bad, restore_cap):
    with pytest.raises(meshsmith.InputError):
        core.set_num_threads(bad)


def test_results_do_not_depend_on_the_cap(restore_cap):
    V, F = datasets.icosphere(5)
    capped = []
    for cap in (1, None):
        core.set_num_threads(cap)
        capped.append((geometry.vertex_normals(V, F), geometry.face_areas(V, F)))
    for one, every in zip(*capped):
        np.testing.assert_array_equal(one, every)


def test_environment_variable_sets_the_cap():
    done = run_python("import meshsmith; print(meshsmith.core.num_threads())", MESHSMITH_NUM_THREADS="1")
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "1"


def test_bad_environment_value_warns_and_is_ignored():
    done = run_python("""
        import warnings
        warnings.simplefilter("always")
        import meshsmith
        print(meshsmith.core.num_threads())""", MESHSMITH_NUM_THREADS="many")
    assert done.returncode == 0, done.stderr
    assert "MESHSMITH_NUM_THREADS='many' is not a positive integer" in done.stderr
    assert int(done.stdout.strip()) >= 1


@pytest.mark.skipif(not os.path.isdir("/proc/self/task") or (os.cpu_count() or 1) < 2,
                    reason="counts OS threads through Linux's /proc on a machine with two or more cores")
def test_cap_of_one_starts_no_worker_threads():
    """A parallel loop under a cap of 1 starts no TBB worker; without the cap it starts at least one."""
    code = """
        import os
        import meshsmith
        from meshsmith import datasets, geometry
        V, F = datasets.icosphere(6)
        before = len(os.listdir("/proc/self/task"))
        for _ in range(5):
            geometry.vertex_normals(V, F)
        print(len(os.listdir("/proc/self/task")) - before)"""
    capped = run_python(code, MESHSMITH_NUM_THREADS="1")
    free = run_python(code)
    assert capped.returncode == 0 and free.returncode == 0, capped.stderr + free.stderr
    assert int(capped.stdout) == 0
    assert int(free.stdout) >= 1
