"""Registration chapter (curriculum §2.3.1): the optimal rigid or similarity transform between
corresponding points (Horn's quaternion method) and iterative closest points (ICP) between scans.

Points are float64 arrays of shape (n, 3); transforms are 4×4 float64 arrays ``T`` that map a
point ``x`` to ``T[:3, :3] @ x + T[:3, 3]`` (:func:`apply_transform`). Bad input raises
:class:`meshsmith.InputError`.

Modules, one per algorithm family: ``align`` (Horn), ``icp`` (ICP, multi-scan ICP and voxel reduction).
"""
from .align import align, apply_transform, rotation_angle
from .icp import ICP_METHODS, IcpMultiResult, IcpResult, icp, icp_multi, voxel_downsample

__all__ = ["align", "apply_transform", "rotation_angle", "icp", "IcpResult", "ICP_METHODS", "icp_multi", "IcpMultiResult",
           "voxel_downsample"]
