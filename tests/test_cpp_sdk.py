"""The C++ SDK: install the `sdk` component from the build tree, build tests/cpp_consumer
against it with find_package(meshsmith), run it on a mesh and compare with the Python API."""
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import numpy as np
import pytest

import meshsmith

REPO = Path(__file__).resolve().parents[1]
# scripts/test_wheel.sh runs the suite against an installed wheel and names it here.
WHEEL_UNDER_TEST = os.environ.get("MESHSMITH_WHEEL_TEST")
pytestmark = pytest.mark.skipif(
    bool(WHEEL_UNDER_TEST),
    reason=f"testing the installed wheel {Path(WHEEL_UNDER_TEST or '').name}: the C++ SDK is not part of "
           "the wheel (it installs from the build tree and builds against the Debian -dev packages); "
           "make test runs these")


def build_tree() -> Path:
    """The scikit-build-core build directory `make test` used (build/<wheel tag>)."""
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    for cache in sorted(REPO.glob("build/*/CMakeCache.txt")):
        if cache.parent.name.startswith(tag):
            return cache.parent
    pytest.skip("no scikit-build-core build tree under build/ (the package was installed some other way)")


@pytest.fixture(scope="module")
def consumer(tmp_path_factory) -> Path:
    cmake = shutil.which("cmake")
    if cmake is None:
        pytest.skip("cmake not on PATH")
    work = tmp_path_factory.mktemp("sdk")
    prefix, build = work / "prefix", work / "build"
    subprocess.run([cmake, "--install", str(build_tree()), "--component", "sdk", "--prefix", str(prefix)],
                   check=True, capture_output=True)
    assert (prefix / "include" / "meshsmith" / "core" / "types.h").is_file()
    assert list(prefix.glob("lib*/libmeshsmith.a")), "static library not installed"
    assert list(prefix.glob("lib*/cmake/meshsmith/meshsmithConfig.cmake"))
    generator = ["-G", "Ninja"] if shutil.which("ninja") else []
    configure = subprocess.run([cmake, "-S", str(REPO / "tests" / "cpp_consumer"), "-B", str(build), *generator,
                                f"-DCMAKE_PREFIX_PATH={prefix}", "-DCMAKE_BUILD_TYPE=Release"],
                               capture_output=True, text=True)
    assert configure.returncode == 0, configure.stdout + configure.stderr
    compile_ = subprocess.run([cmake, "--build", str(build)], capture_output=True, text=True)
    assert compile_.returncode == 0, compile_.stdout + compile_.stderr
    return build / "mesh_counts"


def test_consumer_reads_a_mesh_and_prints_its_counts(consumer, tmp_path):
    from meshsmith import datasets, io
    V, F = datasets.icosphere(2)
    path = tmp_path / "sphere.off"
    io.write_mesh(path, V, F)
    result = subprocess.run([str(consumer), str(path)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    counts = dict(line.split(": ") for line in result.stdout.strip().splitlines())
    assert int(counts["vertices"]) == len(V) == 162
    assert int(counts["faces"]) == len(F) == 320
    assert int(counts["edges"]) == 480
    assert counts["meshsmith"] == meshsmith.__version__
    # QEM decimation and the progressive mesh through the SDK agree with the Python API.
    V_half, F_half = meshsmith.decimation.decimate(V, F, target_faces=160)
    assert int(counts["decimated faces"]) == len(F_half) == 160
    pm = meshsmith.decimation.progressive_mesh(V, F, target_faces=160)
    assert int(counts["progressive splits"]) == pm.n_splits == (320 - 160) // 2
    assert counts["progressive full level equals input"] == "yes"


def test_consumer_reports_bad_input_as_an_error(consumer, tmp_path):
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
    result = subprocess.run([str(consumer), str(bad)], capture_output=True, text=True)
    assert result.returncode == 1
    assert "bad.off" in result.stderr
