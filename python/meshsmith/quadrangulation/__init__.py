"""Quadrangulation chapter (curriculum §5.2.2): cross fields and their singularities, cutting a
surface into a disk through them, the mixed-integer (MIQ) seamless parametrization, the quad
extraction that reads it, and quad-mesh quality.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3), quads ``Q`` int64 (k, 4). Bad input
raises :class:`meshsmith.InputError`.

Modules, one per algorithm family: ``cross_field``, ``cut_graph``, ``miq``, ``extraction``, ``quality``, ``pipeline``,
``dual_loops`` (§5.3: dual-loop quad layouts), ``pictures`` (the field, regions),
``spectral`` (§5.2.1: Morse–Smale quadrangulation of a Laplacian eigenfunction).
"""
from .cross_field import CrossField, Singularities, cross_field, field_angles, merge_singularities, singularities
from .cut_graph import FieldCut, cut_graph
from .dual_loops import (DUAL_LOOP_SCHEDULE, DualLoopAttempt, DualLoopLayout, DualLoopReport, dual_loop_layout,
                         RefinedField, refine_field)
from .extraction import QuadExtraction, QuadExtractionReport, extract_quads
from .miq import MiqResult, miq
from .pictures import field_glyphs, field_picture, regions_picture
from .pipeline import Quadrangulation, QuadrangulationReport, quadrangulate
from .quality import QuadQuality, quad_quality
from .spectral import (MorseSmaleComplex, SpectralQuadrangulation, SpectralQuadrangulationReport, morse_smale_complex,
                       spectral_quadrangulate)

__all__ = ["CrossField", "Singularities", "cross_field", "field_angles", "merge_singularities", "singularities", "FieldCut",
           "cut_graph", "MiqResult", "miq", "QuadExtraction", "QuadExtractionReport", "extract_quads",
           "QuadQuality", "quad_quality", "Quadrangulation", "QuadrangulationReport", "quadrangulate",
           "DualLoopLayout", "DualLoopReport", "DualLoopAttempt", "DUAL_LOOP_SCHEDULE", "dual_loop_layout",
           "RefinedField", "refine_field",
           "field_glyphs", "field_picture", "regions_picture",
           "MorseSmaleComplex", "morse_smale_complex", "SpectralQuadrangulation", "SpectralQuadrangulationReport",
           "spectral_quadrangulate"]
