"""The demo's HTML report."""
from __future__ import annotations

import html

from .context import DemoContext, Section


def html_report(context: DemoContext, sections: list[Section], timings: dict[str, float], version: str,
                dependencies: dict[str, str]) -> str:
    def cell(value: object) -> str:
        if isinstance(value, float):
            return f"{value:.6g}"
        if isinstance(value, (list, tuple)):
            return ", ".join(cell(v) for v in value)
        return html.escape(str(value))

    parts = [f"""<!doctype html><html><head><meta charset="utf-8"><title>meshsmith demo</title>
<style>body{{font-family:system-ui,sans-serif;max-width:1000px;margin:2em auto;color:#222}}
h1{{font-weight:600}} h2{{border-bottom:1px solid #ddd;padding-bottom:.2em;margin-top:2em}}
table{{border-collapse:collapse;font-size:.9em}} td{{padding:.15em .8em;border-bottom:1px solid #eee}}
td:first-child{{color:#555}} figure{{margin:1em 0}} img{{max-width:100%;border:1px solid #eee}}
figcaption{{color:#555;font-size:.9em}} .meta{{color:#777;font-size:.85em}}</style></head><body>
<h1>meshsmith demo</h1>
<p class="meta">meshsmith {html.escape(version)} &middot; input: {html.escape(context.name)} &middot;
{len(context.V)} vertices, {len(context.F)} faces &middot; built with
{html.escape(", ".join(f"{k} {v}" for k, v in dependencies.items()))}</p>"""]
    for section, seconds in zip(sections, timings.values()):
        parts.append(f"<h2>{html.escape(section.title)}</h2><p>{section.text} "
                     f"<span class='meta'>({seconds:.2f} s)</span></p>")
        if section.table:
            rows = "".join(f"<tr><td>{html.escape(str(k))}</td><td>{cell(v)}</td></tr>"
                           for k, v in section.table.items())
            parts.append(f"<table>{rows}</table>")
        for image, caption in section.images:
            parts.append(f"<figure><img src='{html.escape(image)}' alt='{html.escape(caption)}'>"
                         f"<figcaption>{html.escape(caption)}</figcaption></figure>")
    parts.append("</body></html>")
    return "\n".join(parts)
