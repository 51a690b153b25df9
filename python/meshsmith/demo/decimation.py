"""Demo stage of the decimation chapter: QEM levels of detail from one progressive mesh (§4.2–4.3)."""
from __future__ import annotations

from typing import Any

import numpy as np

from .. import InputError, decimation, geometry, render, topology
from .context import DemoContext, Section


def stage_decimation(context: DemoContext) -> Section:
    """§4.2–4.3: QEM decimation of the input to 10% and 1% of its faces (read from one progressive
    mesh), with the Hausdorff distance of each level to the input."""
    V, F = context.V, context.F
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    images: list[tuple[str, str]] = []
    figures: dict[str, Any] = {}
    try:
        pm = decimation.progressive_mesh(V, F, target_faces=max(4, len(F) // 100))
        pm.save(context.out / "decimation.pm")
        figures["progressive mesh: vertex splits"] = pm.n_splits
        level = lambda percent: pm.at(max(pm.face_range[0], len(F) * percent // 100))  # noqa: E731
    except InputError as error:   # e.g. a non-manifold --input: decimate each level directly
        figures["progressive mesh"] = f"not built: {error}"
        level = lambda percent: decimation.decimate(V, F, ratio=percent / 100)  # noqa: E731
    for percent in (100, 10, 1):
        Vd, Fd = level(percent)
        name = f"decimated_{percent}.png"
        distance = float(geometry.hausdorff_distance(Vd, Fd, V, F)) if percent < 100 else 0.0
        render.render(Vd, Fd, context.out / name, wireframe=True, size=(700, 520),
                      title=f"{percent}%: {len(Fd)} faces")
        images.append((name, f"{percent}% of the faces ({len(Fd)}), Hausdorff distance "
                             f"{100 * distance / diagonal:.3g}% of the bounding-box diagonal"))
        figures[f"{percent}%: faces"] = len(Fd)
        figures[f"{percent}%: Hausdorff distance / bounding-box diagonal"] = distance / diagonal
        figures[f"{percent}%: manifold, Euler characteristic"] = (topology.is_manifold(Fd),
                                                                 topology.euler_characteristic(Vd, Fd))
    context.figures["decimation"] = figures
    return Section("Decimation", "meshsmith.decimation (§4.2–4.3): greedy edge collapses ordered by error "
                   "quadrics, recorded as a progressive mesh (<code>decimation.pm</code>) from which each "
                   "level of detail is read; the Hausdorff distance is measured to the input.", figures, images)
