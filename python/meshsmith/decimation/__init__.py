"""Decimation chapter (curriculum §4.1–4.3): vertex clustering, incremental decimation by error
quadrics, and progressive meshes.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); results come back as float64 and
int64 arrays. Bad input raises :class:`meshsmith.InputError`.

Modules, one per algorithm family: ``clustering``, ``qem``, ``progressive``.
"""
from .clustering import CLUSTER_REPRESENTATIVES, ClusteredMesh, cluster
from .progressive import FaceRange, ProgressiveMesh, progressive_mesh
from .qem import DecimatedMesh, DecimationReport, decimate

__all__ = ["CLUSTER_REPRESENTATIVES", "ClusteredMesh", "cluster", "decimate", "DecimatedMesh", "DecimationReport",
           "ProgressiveMesh", "FaceRange", "progressive_mesh"]
