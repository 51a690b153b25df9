"""Deformation chapter (curriculum §3.1): handle-based free-form deformation on k-harmonic
systems, detail-preserving (multiresolution) editing, and as-rigid-as-possible deformation.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); vertex sets (handles, fixed
vertices) are 1-D integer arrays of distinct indices. Every solver factorizes its sparse system
once (CHOLMOD) and reuses it: build a :class:`Deformer` or :class:`ArapDeformer` once, then call
it per frame. Bad input (overlapping handle and fixed sets, empty handles, a connected part that
nothing holds, NaN transforms) raises :class:`meshsmith.InputError`.

Modules, one per algorithm family: ``harmonic`` (k-harmonic interpolation, :class:`Deformer`),
``multiresolution``, ``poisson``, ``arap``.
"""
from .arap import ArapDeformer, arap, arap_energy
from .harmonic import Deformer, harmonic
from .multiresolution import multiresolution_edit
from .poisson import poisson_edit

__all__ = ["harmonic", "Deformer", "multiresolution_edit", "poisson_edit", "arap", "ArapDeformer", "arap_energy"]
