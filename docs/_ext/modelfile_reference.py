"""The model-file reference in the documentation: ``.. mechdyn-file:: drivetrain`` renders every table
of that file type (``[model]``, ``[[disks]]``, …) from :func:`mechdyn.io.reference.reference`, read
from the pydantic schema that validates the files. A field without a description is a build warning
(an error under ``-W``).
"""

from __future__ import annotations

from typing import Any

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

logger = logging.getLogger(__name__)


def _cell(text: str) -> str:
    return " ".join(text.split()).replace("|", "\\|")


def render(file_type: str) -> tuple[list[str], list[str]]:
    """reST lines for every table of ``file_type`` (one section each, in file order), and the fields
    that have no description."""
    from mechdyn.io.reference import reference

    tables, undocumented = reference(file_type)
    lines: list[str] = []
    for t in tables:
        anchor = f"file-{file_type}-{t.path.replace('.', '-').replace('_', '-')}"
        lines.extend([f".. _{anchor}:", "", t.header, "-" * len(t.header), ""])
        need = "required" if t.required else "optional"
        if t.values:
            lines.extend([f"*{need}.* {_cell(t.description)}", ""])
            lines.extend([f"Each entry is ``name = value``, the value {t.values}.", ""])
            continue
        lines.extend(
            [f"*{need}{'; one table per element' if t.is_array else ''}.* {_cell(t.description)}", ""]
        )
        if t.fields:
            lines.extend([".. list-table::", "   :header-rows: 1", "   :widths: 20 26 14 40", ""])
            lines.extend(["   * - field", "     - type", "     - default", "     - meaning"])
            for f in t.fields:
                lines.extend(
                    [
                        f"   * - ``{f.name}``",
                        f"     - {_cell(f.kind)}",
                        f"     - {f.default}",
                        f"     - {_cell(f.meaning) or '—'}",
                    ]
                )
            lines.append("")
    return lines, undocumented


class ModelFileDirective(SphinxDirective):
    """``.. mechdyn-file:: TYPE``: the reference of one model-file type."""

    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        file_type = self.arguments[0]
        lines, undocumented = render(file_type)
        for what in undocumented:
            logger.warning(
                "model-file reference: %s of %r has no description (add a docstring under the field)",
                what,
                file_type,
                location=self.get_location(),
            )
        node = nodes.section()
        node.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source=f"<schema of {file_type}>"), node)
        return node.children


def setup(app: Any) -> dict[str, Any]:
    app.add_directive("mechdyn-file", ModelFileDirective)
    return {"version": "1", "parallel_read_safe": True}
