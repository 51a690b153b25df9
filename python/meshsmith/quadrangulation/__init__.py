"""Quadrangulation chapter (curriculum §5.2): quad extraction from a seamless parametrization and
quad-mesh quality.

Vertices ``V`` are float64 (n, 3), triangles ``F`` integer (m, 3), quads ``Q`` int64 (k, 4). Bad input
raises :class:`meshsmith.InputError`.

Modules, one per algorithm family: ``extraction``, ``quality``.
"""
from .extraction import QuadExtraction, QuadExtractionReport, extract_quads
from .quality import QuadQuality, quad_quality

__all__ = ["QuadExtraction", "QuadExtractionReport", "extract_quads", "QuadQuality", "quad_quality"]
