"""`parametrize`: any clean manifold mesh to UV by a named method, cutting to a disk first when needed (§5.1).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import geometry, topology
from .._core import InputError
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
class Parametrization:
    """A parametrization made by :func:`parametrize`, with its quality.

    V, F: the mesh the texture coordinates belong to (the input, or the input cut to a disk);
    uv: (k, 2) float64, one row per vertex of V; cut: the :class:`CutMesh` when the input had to
    be cut, else None (then V, F are the input); method: the method's name; distortion: the
    :class:`meshsmith.geometry.TriangleDistortion` of the map; bijective: :func:`is_bijective`.
    """

    V: np.ndarray
    F: np.ndarray
    uv: np.ndarray
    cut: CutMesh | None
    method: str
    distortion: object
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


def parametrize(V, F, method: str = "lscm", *, progress=None) -> Parametrization:
    """Parametrize any clean manifold mesh with one of :data:`PARAMETRIZATION_METHODS`.

    A mesh that is not a topological disk (closed, higher genus, several holes) is first cut
    with :func:`cut_to_disk`. "abf" / "abf++" use :func:`abf`.
    V: (n, 3) float array, F: (m, 3) integer array; progress: optional callback
    ``(fraction, stage) -> bool`` of the method's own iterations (stretch, abf, abf++).
    Returns a :class:`Parametrization`. Raises InputError for an unknown method or bad input
    (see :func:`cut_to_disk`).
    """
    if method not in PARAMETRIZATION_METHODS:
        raise InputError(f"unknown parametrization method {method!r}: expected one of "
                         + ", ".join(PARAMETRIZATION_METHODS))
    info = topology.info(V, F)
    cut = None
    if not (info.n_boundary_loops == 1 and info.euler_characteristic == 1):
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
    return Parametrization(np.asarray(V), np.asarray(F), uv, cut, method,
                           geometry.triangle_distortion(V, F, uv), is_bijective(uv, F))
