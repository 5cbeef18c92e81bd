"""MkDocs hooks: the benchmark reports as pages, and Sphinx roles of docstrings as code spans.

The measured numbers live in ``benchmarks/*.md`` beside the scripts that produce them;
:func:`on_files` publishes those reports (and the images and videos they link to) under
``benchmarks/`` of the site, so the pages link to them instead of copying numbers. The
papers' tables, ours beside them and the verdicts, are pages of ``docs/papers/``.

The docstrings are written for Sphinx as much as for mkdocstrings (``:class:`Arena```,
``:func:`~reciprocity.env.rollout```, ``:mod:`intents <reciprocity.intents>```); Markdown
leaves the role's name in front of a code span. This hook (``hooks:`` in mkdocs.yml)
drops the role, shows the title as Sphinx would (the text before ``<target>``, or the last
dotted part after ``~``) and links it to the object's anchor when the target, or a unique
object whose dotted name ends with it, is documented on the same page.
"""

from __future__ import annotations

import html
import re
from pathlib import Path

from mkdocs.structure.files import File, InclusionLevel

ROOT = Path(__file__).resolve().parents[1]
_IMAGE = re.compile(r"\]\(([^)\s]+\.(?:png|svg|jpg|mp4))\)")  # images and videos

_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|exc|obj|const):<code>(.*?)</code>")
_ANCHOR = re.compile(r'id="([A-Za-z_][\w.]*)"')


def on_files(files, config):
    """Add ``benchmarks/*.md`` and the images and videos they link to as ``benchmarks/...`` of the site.

    They are not in the nav (docs/measurements.md lists them), so a new report builds
    without editing mkdocs.yml."""
    bench = ROOT / "benchmarks"
    for md in sorted(bench.glob("*.md")):
        files.append(File.generated(config, f"benchmarks/{md.name}", abs_src_path=str(md),
                                    inclusion=InclusionLevel.NOT_IN_NAV))
        for image in _IMAGE.findall(md.read_text()):
            src = (md.parent / image).resolve()
            if src.is_file() and src.is_relative_to(bench):
                uri = f"benchmarks/{src.relative_to(bench).as_posix()}"
                if files.get_file_from_path(uri) is None:
                    files.append(File.generated(config, uri, abs_src_path=str(src)))
    return files


def _title_and_target(text: str) -> tuple[str, str]:
    explicit = re.fullmatch(r"(.*?)\s*<(.+)>", text)
    if explicit:
        return explicit.group(1), explicit.group(2)
    target = text.lstrip("~")
    return (target.rsplit(".", 1)[-1] if text.startswith("~") else target), target


def _resolve(target: str, anchors: set[str]) -> str | None:
    if target in anchors:
        return target
    ends = [a for a in anchors if a.endswith("." + target)]
    return ends[0] if len(ends) == 1 else None


def on_page_content(html_text: str, page, config, files) -> str:
    """Replace each ``:role:<code>x</code>`` of the rendered page."""
    anchors = set(_ANCHOR.findall(html_text))

    def span(m: re.Match) -> str:
        title, target = _title_and_target(html.unescape(m.group(1)))
        code = f"<code>{html.escape(title)}</code>"
        anchor = _resolve(target.rstrip("()"), anchors)
        return f'<a href="#{anchor}">{code}</a>' if anchor else code

    return _ROLE.sub(span, html_text)
