"""meshsmith.repair.stitch_boundaries (§2.4.1): two grids side by side across a crack, at the same
and at different resolutions (T-junctions), stitched into one manifold, oriented sheet with one
boundary loop and the summed area; a sphere cut in two and pulled apart by less than the
tolerance comes back closed; nothing happens beyond the tolerance."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, repair, topology


def two_sheets(nx_right, ny_right, gap):
    """Grids [0, 1]² (8 × 8) and [1 + gap, 2 + gap] × [0, 1] (nx_right × ny_right) as one mesh."""
    VA, FA = datasets.grid(8, 8)
    VB, FB = datasets.grid(nx_right, ny_right)
    VB = VB + [1 + gap, 0, 0]
    return np.vstack([VA, VB]), np.vstack([FA, FB + len(VA)])


@pytest.mark.parametrize("ny_right", [8, 16, 24])
def test_crack_between_two_grids_is_closed(ny_right):
    V, F = two_sheets(8, ny_right, 1e-4)
    assert len(topology.boundary_loops(F)) == 2
    out = repair.stitch_boundaries(V, F, tolerance=1e-3)
    assert topology.is_manifold(out.F) and topology.is_oriented(out.F)
    assert len(topology.boundary_loops(out.F)) == 1 and topology.connected_components(out.F).count == 1
    assert out.merged_vertices == 9                                      # the grid vertices matching one to one
    assert out.inserted_vertices == ny_right - 8                         # the others are T-junctions
    assert geometry.surface_area(out.V, out.F) == pytest.approx(2.0, abs=1e-3)
    np.testing.assert_array_equal(out.V, V[out.vertex_map])              # nothing moved
    assert out.boundary_edges_after == out.boundary_edges_before - 8 - ny_right   # the seam, both sides
    assert not meshsmith.core.mesh_defects(out.V, out.F).degenerate_faces.size


def test_beyond_the_tolerance_nothing_changes():
    V, F = two_sheets(8, 16, 1e-2)
    out = repair.stitch_boundaries(V, F, tolerance=1e-3)
    assert out.merged_vertices == out.inserted_vertices == out.split_edges == 0
    np.testing.assert_array_equal(out.F, F)


def test_cut_sphere_is_closed_again():
    V, F = datasets.icosphere(3)
    upper = V[F].mean(axis=1)[:, 2] > 0
    V2 = np.vstack([V, V + [0, 0, 1e-5]])                    # the upper half lifted, its own vertices
    F2 = np.vstack([F[~upper], F[upper] + len(V)])
    out = repair.stitch_boundaries(V2, F2, tolerance=1e-4)
    assert topology.boundary_loops(out.F) == [] and topology.is_manifold(out.F) and topology.is_oriented(out.F)
    assert len(out.F) == len(F) and len(out.V) == len(V)


def test_bad_tolerance():
    V, F = two_sheets(8, 8, 0.0)
    for tolerance in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(meshsmith.InputError):
            repair.stitch_boundaries(V, F, tolerance=tolerance)
