"""Demo stage of the render chapter: shaded views, wireframe, a texture."""
from __future__ import annotations

from .. import render
from .context import DemoContext, Section


def stage_pictures(context: DemoContext) -> Section:
    images = []
    render.render(context.V, context.F, context.out / "shaded.png",
                  views=["three-quarter", "front", "top", "left"], size=(520, 400), title=context.name)
    images.append(("shaded.png", "smooth shading from four views"))
    render.render(context.V, context.F, context.out / "wireframe.png", wireframe=True,
                  size=(900, 650), title="wireframe")
    images.append(("wireframe.png", "the triangles"))
    if context.uv is not None:
        render.render(context.V, context.F, context.out / "checkerboard.png", uv=context.uv,
                      size=(900, 650), title="texture coordinates")
        images.append(("checkerboard.png", "checkerboard texture through the shape's texture coordinates"))
    return Section("Pictures", "meshsmith.render: shaded views, wireframe, a texture.", {}, images)
