"""As-rigid-as-possible deformation (§3.1.2; Sorkine & Alexa 2007, spokes-and-rims energy as
libigl's default); binding cpp/python/deformation.cpp, C++ src/deformation/arap.cpp."""
from __future__ import annotations

from .._core import deformation as _core
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback

__all__ = ["arap", "ArapDeformer", "arap_energy"]


class ArapDeformer:
    """The precomputed ARAP solver: ``ArapDeformer(V, F, handles)``, then :meth:`solve` per frame.

    Precomputes the cotangent weights, the constant parts of the right-hand side and the CHOLMOD
    factorization of the cotan Laplacian on the free (non-handle) vertices; an iteration is then
    one parallel pass of 3×3 rotation fits (local step) and one back-substitution (global step).

    V: (n, 3) float rest positions, F: (m, 3) int, handles: (h,) distinct vertex indices.
    Raises InputError for an empty, out-of-range or repeated handle set, or a connected part of the
    mesh without a handle (it could drift freely: the system is singular).
    """

    def __init__(self, V: ArrayLike, F: ArrayLike, handles: ArrayLike) -> None:
        self._deformer = _core.ArapDeformer(V, F, handles)

    @property
    def handles(self) -> IndexArray:
        """(h,) int64 handle vertices, in the order positions are given."""
        return self._deformer.handles

    def solve(self, positions: ArrayLike, iterations: int = 10, *, initial: ArrayLike | None = None,
              progress: ProgressCallback = None) -> FloatArray:
        """`iterations` local/global ARAP steps with the handles at `positions` ((h, 3)).

        initial: (n, 3) starting positions; None starts from the rest mesh with the handles'
        displacement spread harmonically (one extra back-substitution). Returns (n, 3) float64.
        Raises InputError for wrong shapes, NaN/Inf or iterations < 0; Cancelled from `progress`.
        """
        return self._deformer.solve(positions, iterations, initial, progress)

    def energy(self, U: ArrayLike) -> float:
        """The spokes-and-rims ARAP energy of deformed positions U (n, 3); see :func:`arap_energy`."""
        return float(self._deformer.energy(U))


def arap(V: ArrayLike, F: ArrayLike, handles: ArrayLike, positions: ArrayLike, *, iterations: int = 10,
         initial: ArrayLike | None = None, progress: ProgressCallback = None) -> FloatArray:
    """As-rigid-as-possible deformation with the `handles` moved to `positions`.

    Minimizes the spokes-and-rims energy (:func:`arap_energy`) by `iterations` alternations of the
    local step (a best-fit rotation per vertex) and the global step (a cotan-Laplacian solve with
    the handles held). One call is ``ArapDeformer(V, F, handles).solve(positions, iterations,
    initial=initial)``; for interactive use keep the :class:`ArapDeformer`.

    V: (n, 3) float, F: (m, 3) int, handles: (h,) distinct indices, positions: (h, 3), initial:
    (n, 3) or None (the harmonic spread of the handles' displacement). Returns (n, 3) float64.
    Raises InputError as :class:`ArapDeformer` and :meth:`ArapDeformer.solve`.
    """
    return ArapDeformer(V, F, handles).solve(positions, iterations, initial=initial, progress=progress)


def arap_energy(V: ArrayLike, F: ArrayLike, U: ArrayLike) -> float:
    """The spokes-and-rims ARAP energy of the deformed positions U of the rest mesh (V, F).

    E(U) = Σ_i min_{R_i ∈ SO(3)} Σ_{t ∋ i} Σ_{(j,k) ∈ t} c_jk ‖(u_j − u_k) − R_i (v_j − v_k)‖², with
    c_jk the half-cotangent of the angle of t opposite edge jk (libigl's cotmatrix_entries): the
    energy :func:`arap` decreases. E(V) = 0, and E is invariant to rigid motions of U.
    V: (n, 3), F: (m, 3), U: (n, 3). Raises InputError for bad shapes or NaN/Inf.
    """
    return float(_core.arap_energy(V, F, U))
