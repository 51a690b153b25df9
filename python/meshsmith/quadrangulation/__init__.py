"""Quadrangulation chapter (curriculum §5.2.2): cross fields and their singularities, cutting a
surface into a disk through them, and the mixed-integer (MIQ) seamless parametrization that a
quad extraction reads.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3). Bad input raises
:class:`meshsmith.InputError`.

Modules, one per algorithm family: ``cross_field``, ``cut_graph``, ``miq``.
"""
from .cross_field import CrossField, Singularities, cross_field, field_angles, singularities
from .cut_graph import FieldCut, cut_graph
from .miq import MiqResult, miq

__all__ = ["CrossField", "Singularities", "cross_field", "field_angles", "singularities", "FieldCut",
           "cut_graph", "MiqResult", "miq"]
