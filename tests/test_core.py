"""core: validation at the boundary, defects, OpenMesh conversion, progress plumbing."""
import re
import threading
import time

import numpy as np
import pytest

import meshsmith
from meshsmith._core import core as _core

TETRA_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def test_exceptions_are_python_standard_types():
    assert issubclass(meshsmith.InputError, ValueError)
    assert issubclass(meshsmith.SolverError, RuntimeError)
    assert issubclass(meshsmith.Cancelled, Exception)


def test_dependency_versions_come_from_the_linked_libraries():
    versions = meshsmith.core.dependency_versions()
    assert set(versions) == {"Eigen", "OpenMesh", "CGAL", "CHOLMOD", "Spectra", "TBB", "nanoflann"}
    assert versions["CGAL"] != "unusable"
    assert all(v and v[0].isdigit() for v in versions.values())
    assert meshsmith.__version__ == "0.1.0"


def test_valid_mesh_passes_for_any_integer_dtype():
    for dtype in (np.int8, np.int16, np.int32, np.int64, np.uint32, np.uint64):
        meshsmith.core.validate_mesh(TETRA_V.astype(np.float32), TETRA_F.astype(dtype))
    meshsmith.core.validate_mesh(TETRA_V.tolist(), TETRA_F.tolist())


@pytest.mark.parametrize("V, F, message", [
    (np.zeros((0, 3)), TETRA_F, "V is empty"),
    (TETRA_V, np.zeros((0, 3), int), "F is empty"),
    (TETRA_V[:, :2], TETRA_F, "V has shape (4, 2)"),
    (TETRA_V, TETRA_F[:, :2], "F has shape (4, 2)"),
    (TETRA_V, TETRA_F.ravel(), "F has shape (12,)"),
    (TETRA_V, TETRA_F.astype(float), "expected integer indices"),
    (TETRA_V, TETRA_F.astype(bool), "expected integer indices"),
    (TETRA_V.astype(str), TETRA_F, "expected real numbers"),
    (np.where(np.eye(4, 3) > 0, np.nan, TETRA_V), TETRA_F, "V[0, 0] is nan"),
    (np.where(np.eye(4, 3) > 0, np.inf, TETRA_V), TETRA_F, "V[0, 0] is inf"),
    (TETRA_V, TETRA_F - 1, "indexes vertex -1"),
    (TETRA_V, TETRA_F + 1, "indexes vertex 4"),
    (TETRA_V, np.array([[0, 1, 2**33]]), "outside the 32-bit range"),
    (TETRA_V, np.array([[0, 1, 2**64 - 1]], dtype=np.uint64), "outside the 32-bit range"),
    (None, TETRA_F, "V is None"),
])
def test_bad_input_raises_input_error_naming_the_problem(V, F, message):
    with pytest.raises(meshsmith.InputError, match=re.escape(message)):
        meshsmith.core.validate_mesh(V, F)


def test_inputs_are_not_modified():
    V, F = TETRA_V.copy(), TETRA_F.copy()
    _core.trimesh_roundtrip(V, F)
    meshsmith.core.mesh_defects(V, F)
    assert np.array_equal(V, TETRA_V) and np.array_equal(F, TETRA_F)


def test_mesh_defects_finds_each_kind():
    V = np.vstack([TETRA_V, [[5.0, 5, 5]], [[0.5, 0, 0]]])      # 4: unreferenced, 5: on edge 0-1
    F = np.vstack([TETRA_F, [[1, 2, 3]], [[0, 0, 1]], [[0, 1, 5]], [[3, 2, 1]]])
    defects = meshsmith.core.mesh_defects(V, F)
    assert defects.degenerate_faces.tolist() == [5]
    assert defects.zero_area_faces.tolist() == [6]
    assert defects.duplicate_faces.tolist() == [4, 7]
    assert defects.unreferenced_vertices.tolist() == [4]
    assert "2 duplicate faces" in defects.summary and not defects.empty
    assert meshsmith.core.mesh_defects(TETRA_V, TETRA_F).empty


def test_openmesh_roundtrip_keeps_indices_and_positions():
    rng = np.random.default_rng(0)
    V = TETRA_V + rng.normal(scale=0.01, size=TETRA_V.shape)
    V2, F2 = _core.trimesh_roundtrip(V, TETRA_F)
    assert F2.dtype == np.int64
    assert np.array_equal(V2, V) and np.array_equal(F2, TETRA_F)


def test_openmesh_conversion_rejects_a_non_manifold_edge_by_face():
    V = np.random.default_rng(1).random((5, 3))
    with pytest.raises(meshsmith.InputError, match=r"F\[2\].*non-manifold"):
        _core.trimesh_roundtrip(V, [[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.raises(meshsmith.InputError, match="repeats a vertex"):
        _core.trimesh_roundtrip(V, [[0, 1, 1]])


def test_progress_reports_monotone_fractions_ending_at_one():
    seen = []
    assert _core.progress_loop(5, 0.06, lambda f, stage: seen.append((f, stage))) == 5
    fractions = [f for f, _ in seen]
    assert fractions[-1] == 1.0 and fractions == sorted(fractions) and len(fractions) >= 3
    assert {stage for _, stage in seen} == {"progress_loop"}


def test_progress_callback_returning_false_cancels():
    with pytest.raises(meshsmith.Cancelled, match="progress_loop"):
        _core.progress_loop(1000, 0.01, lambda f, stage: f < 0.01)


def test_exception_in_callback_propagates():
    def explode(fraction, stage):
        raise ZeroDivisionError("from the callback")
    with pytest.raises(ZeroDivisionError, match="from the callback"):
        _core.progress_loop(10, 0.0, explode)


def test_gil_is_released_while_cpp_runs():
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.005)
    worker = threading.Thread(target=count)
    worker.start()
    _core.progress_loop(1, 0.3, None)       # one long step, no callback in between
    stop.set()
    worker.join()
    assert len(ticks) >= 10


def test_ctrl_c_interrupts_a_long_loop():
    import _thread
    timer = threading.Timer(0.2, _thread.interrupt_main)
    timer.start()
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        _core.progress_loop(10_000, 0.01, None)   # would take 100 s
    assert time.perf_counter() - start < 5
