"""Repair chapter (curriculum §2.4): cleaning a mesh into a manifold, consistently oriented one
and saying what changed; removing unreferenced vertices.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); results come back as float64 and
int64 arrays, with maps back to the input's indices. Bad input raises :class:`meshsmith.InputError`.

Modules, one per algorithm family: ``unreferenced``, ``orient``, ``clean``, ``holes`` (hole filling,
§2.4.1), ``intersections`` (self-intersecting face pairs, and their removal), ``degenerate`` (needles and caps),
``stitching`` (cracks and T-junctions between boundaries), ``zipper`` (joining overlapping scans), ``volumetric`` (volumetric repair, §2.4.2), ``defects``
(counting what is wrong).
"""
from .clean import CleanMesh, CleanReport, clean, merge_close_vertices
from .defects import MeshDefectCounts, find_defects
from .degenerate import NeedlesAndCaps, remove_needles_and_caps
from .holes import FilledMesh, FillHolesReport, HolePatch, fill_holes
from .intersections import IntersectionFreeMesh, IntersectionRemoval, remove_self_intersections, self_intersections
from .orient import OrientedFaces, orient_faces
from .stitching import StitchedMesh, stitch_boundaries
from .unreferenced import ReferencedMesh, remove_unreferenced
from .volumetric import VolumetricMesh, VolumetricReport, volumetric_repair
from .zipper import ZipperedMesh, ZipperReport, zipper

__all__ = ["clean", "CleanMesh", "CleanReport", "merge_close_vertices", "orient_faces", "OrientedFaces",
           "remove_unreferenced", "ReferencedMesh", "fill_holes", "FilledMesh", "FillHolesReport", "HolePatch",
           "self_intersections", "remove_self_intersections", "IntersectionFreeMesh", "IntersectionRemoval",
           "remove_needles_and_caps", "NeedlesAndCaps",
           "stitch_boundaries", "StitchedMesh", "volumetric_repair", "VolumetricMesh", "VolumetricReport",
           "find_defects", "MeshDefectCounts", "zipper", "ZipperedMesh", "ZipperReport"]
