"""`parametrize`: any clean manifold mesh to UV by a named method, cutting to a disk first when needed (§5.1).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _arguments, core, geometry, topology
from .._core import InputError
from .._deprecation import positional_options
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from ..geometry import TriangleDistortion
from ..repair.unreferenced import on_referenced_vertices
from .angle_based import abf
from .bijectivity import is_bijective
from .cut import CutMesh, cut_to_disk
from .maps import harmonic, lscm, stretch_minimizing

__all__ = ["PARAMETRIZATION_METHODS", "Parametrization", "parametrize"]


#: The methods :func:`parametrize` knows, with what each one computes.
PARAMETRIZATION_METHODS = {
    "tutte": "Tutte's embedding: harmonic map with uniform weights on a circle (§5.1.1)",
    "harmonic": "harmonic map with cotangent weights on a circle (§5.1.1)",
    "stretch": "stretch-minimizing map from the mean-value harmonic map (§5.1.1)",
    "lscm": "least-squares conformal map with two far-apart pins (§5.1.2)",
    "abf": "angle-based flattening (§5.1.3)",
    "abf++": "ABF++, the reduced-system Newton solver of ABF (§5.1.3)",
}


@dataclass(frozen=True)
class Parametrization(Unpackable):
    """A parametrization made by :func:`parametrize`, with its quality; unpacks in field order
    (``V, F, uv, cut, method, distortion, bijective``).

    V, F: the mesh the texture coordinates belong to (the input, or the input cut to disks);
    uv: (k, 2) float64, one row per vertex of V (NaN rows for vertices no face uses); cut: the
    :class:`CutMesh` when the input had to be cut (its first n vertices are the input's, seam
    copies appended), else None (then V, F are the input); method: the method's name; distortion: the
    :class:`meshsmith.geometry.TriangleDistortion` of the map; bijective: :func:`is_bijective`.
    """

    V: FloatArray
    F: IndexArray
    uv: FloatArray
    cut: CutMesh | None
    method: str
    distortion: TriangleDistortion
    bijective: bool

    def summary(self) -> dict[str, object]:
        """Area-weighted mean angle distortion (sigma1/sigma2), mean area distortion
        (max(a, 1/a) of the map scaled to the surface's area), Sander's normalized L2 stretch,
        flipped triangles and bijectivity, as a dict of plain numbers."""
        d = self.distortion
        weights = d.surface_areas
        scale = weights.sum() / np.abs(d.parameter_areas).sum()
        area = d.area / scale  # 3D area / UV area with the UV scaled to the surface's area
        finite = np.isfinite(d.conformal) & (weights > 0)
        return {"method": self.method,
                "angle distortion (mean sigma1/sigma2)": float(np.average(d.conformal[finite], weights=weights[finite])),
                "area distortion (mean max(a, 1/a))": float(np.average(np.maximum(area, 1 / area)[finite],
                                                                        weights=weights[finite])),
                "stretch (Sander L2, 1 = isometry)": float(d.normalized_global_stretch_l2),
                "flipped triangles": int(len(d.flipped_faces)),
                "bijective": bool(self.bijective),
                "seam edges": 0 if self.cut is None else int(len(self.cut.seam_edges))}


@positional_options("method")
def parametrize(V: ArrayLike, F: ArrayLike, *, method: str = "lscm", progress: ProgressCallback = None
                ) -> Parametrization:
    """Parametrize any clean manifold mesh with one of :data:`PARAMETRIZATION_METHODS`.

    Each connected component is a chart: one that is not a topological disk (closed, higher
    genus, several holes) is first cut with :func:`cut_to_disk`, then flattened; the charts are
    laid side by side along u (in component order, each to the right of the previous one, a gap
    of 5% of the tallest chart between them), so the atlas is bijective when every chart is.
    "abf" / "abf++" use :func:`abf`. Vertices no face uses are left out and get NaN rows in uv.
    V: (n, 3) float array, F: (m, 3) integer array; progress: optional callback
    ``(fraction, stage) -> bool`` of the method's own iterations (stretch, abf, abf++).
    Returns a :class:`Parametrization`. Raises InputError for an unknown method or bad input
    (a non-manifold or inconsistently oriented mesh: clean it first with
    :func:`meshsmith.repair.clean`, ``meshsmith clean`` on the command line; see :func:`cut_to_disk`).
    """
    _arguments.progress(progress)  # checked here: not every method calls it
    if method not in PARAMETRIZATION_METHODS:
        raise InputError(f"unknown parametrization method {method!r}: expected one of "
                         + ", ".join(PARAMETRIZATION_METHODS))
    core.validate_mesh(V, F)
    V, F = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    manifold = topology.is_manifold(F)
    components = topology.connected_components(F, len(V))
    if not manifold or components.count == 1:
        charts = [on_referenced_vertices(V, F)]   # a non-manifold mesh is refused by the map's checks
        chart_faces = [np.arange(len(F))]
    else:
        order = np.argsort(components.face_labels, kind="stable")
        chart_faces = np.split(order, np.cumsum(np.bincount(components.face_labels))[:-1])
        charts = [on_referenced_vertices(V, F[faces]) for faces in chart_faces]
    flattened = []
    for index, chart in enumerate(charts):  # the stages between the maps' own reports (lscm, harmonic and
        # tutte report nothing themselves: one sparse factorization and solve each)
        _arguments.report(progress, 0.9 * index / len(charts), f"{method}: chart {index + 1} of {len(charts)}")
        flattened.append(_flatten_chart(chart.V, chart.F, method, progress))
    _arguments.report(progress, 0.9, "distortion and bijectivity")

    # The atlas on the input's vertex numbering: input vertices first, seam copies appended.
    copies = [len(chart_uv) - len(chart.V) for chart, (_, chart_uv) in zip(charts, flattened)]
    n = len(V)
    uv = np.full((n + sum(copies), 2), np.nan)
    F_out = F.copy()
    origin, seams, offset, first_copy = [np.arange(n, dtype=np.int64)], [], 0.0, n
    gap = 0.05 * max(float(np.ptp(chart_uv[:, 1])) for _, chart_uv in flattened)
    for chart, faces, (cut, chart_uv), extra in zip(charts, chart_faces, flattened, copies):
        kept = len(chart.V)
        renumber = np.concatenate([chart.vertex_map, first_copy + np.arange(extra, dtype=np.int64)])
        chart_uv = chart_uv - [chart_uv[:, 0].min() - offset, 0.0]
        offset = float(chart_uv[:, 0].max()) + gap
        uv[renumber] = chart_uv
        if cut is not None:
            F_out[faces] = renumber[cut.F]
            origin.append(chart.vertex_map[cut.vertex_origin[kept:]])
            seams.append(chart.vertex_map[cut.seam_edges])
        first_copy += extra
    cut = None
    if seams:
        seam_edges = np.concatenate(seams)
        seam_edges = seam_edges[np.lexsort((seam_edges[:, 1], seam_edges[:, 0]))]
        cut = CutMesh(V=np.concatenate([V, V[np.concatenate(origin[1:])]]), F=F_out,
                      vertex_origin=np.concatenate(origin), seam_edges=seam_edges)
    mesh_V = V if cut is None else cut.V
    used_uv = np.where(np.isnan(uv), 0.0, uv)   # unreferenced rows touch no face
    result = Parametrization(mesh_V, F_out, uv, cut, method, geometry.triangle_distortion(mesh_V, F_out, used_uv),
                             is_bijective(used_uv, F_out))
    _arguments.report(progress, 1.0, "parametrize")
    return result


def _flatten_chart(V: np.ndarray, F: np.ndarray, method: str, progress: ProgressCallback) -> tuple[CutMesh | None, np.ndarray]:
    """One chart (a connected mesh, every vertex used): (its cut or None, UV on the cut's vertices)."""
    # Only the topology is needed (topology.info would also compute the area and volume, which
    # are InputErrors for coordinates near 1e155 and beyond).
    is_disk = len(topology.boundary_loops(F)) == 1 and topology.euler_characteristic(F) == 1
    cut = None
    if not is_disk:
        cut = cut_to_disk(V, F)
        V, F = cut.V, cut.F
    if method == "tutte":
        uv = harmonic(V, F, weights="uniform")
    elif method == "harmonic":
        uv = harmonic(V, F, weights="cotan")
    elif method == "stretch":
        uv = stretch_minimizing(V, F, progress=progress).uv
    elif method == "lscm":
        uv = lscm(V, F)
    else:
        uv = abf(V, F, method=method, progress=progress).uv
    return cut, uv
