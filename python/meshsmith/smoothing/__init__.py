"""Smoothing chapter (curriculum §3.0): bi-Laplacian fairing.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3). Modules, one per algorithm family:
``fairing``.
"""
from .fairing import bilaplacian

__all__ = ["bilaplacian"]
