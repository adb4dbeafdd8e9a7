"""Sphinx directives for hydrolux's documentation site, generated from the code at build time.

``.. hydrolux-parameters::``
    One section per job with the table of its declared parameters, read from the built package
    (``hydrolux._core.jobs()`` and ``hydrolux._core.params(job)``: the library's one table, the same
    the CLI's flags, the Python keywords and docs/reference.md come from). An argument names one job.

``.. hydrolux-gallery::``
    The figures of a gallery rendered by ``hydrolux gallery -o DIR``, with their titles and captions
    as DIR/index.html lists them; DIR is the ``hydrolux_gallery_dir`` setting (conf.py takes it from
    $HYDROLUX_DOCS_GALLERY). Sphinx copies the pictures into the site. Without a folder the page says
    how to make one; a folder without index.html, or a figure missing from it, is a warning.

``.. hydrolux-batch-help:: JOB``
    The ``--help`` text of ``python3 -m hydrolux.batch JOB``, as argparse prints it.

And two checks, each a warning: a name of ``hydrolux.__all__`` that python-api.rst does not
document, and raw HTML in the Markdown (a ``<r>`` that GitHub and the browser would hide).
"""
from __future__ import annotations

import contextlib
import html.parser
import io
import os
import re

from docutils import nodes
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)


# ---- parameter tables ------------------------------------------------------------------------------

_COLUMNS = [("parameter", 14), ("CLI flag", 16), ("group", 8), ("unit", 6), ("valid", 14), ("default", 8),
            ("what it sets", 40)]


def _table(rows: list[list[str]]) -> nodes.table:
    table = nodes.table(classes=["hydrolux-params"])
    group = nodes.tgroup(cols=len(_COLUMNS))
    table += group
    for _, width in _COLUMNS:
        group += nodes.colspec(colwidth=width)
    head = nodes.thead()
    group += head
    row = nodes.row()
    for title, _ in _COLUMNS:
        row += nodes.entry("", nodes.paragraph("", title))
    head += row
    body = nodes.tbody()
    group += body
    for cells in rows:
        row = nodes.row()
        for i, text in enumerate(cells):
            para = nodes.paragraph()
            if text and i in (0, 1):  # names and flags as code
                para += nodes.literal(text, text)
            elif text:
                para += nodes.Text(text)
            row += nodes.entry("", para)
        body += row
    return table


def _param_row(p: dict, flags: dict) -> list[str]:
    unit = p["unit"]
    valid = p["range"]
    if unit and valid.endswith(" " + unit):
        valid = valid[: -len(unit) - 1]
    if p["kind"] == "flag":
        valid = "on / off"
    default = p["default_text"]
    meaning = p["help"]
    if p["excludes"]:
        others = [flags.get(e.strip(), e.strip()) for e in p["excludes"].split(",")]
        if not all(o in meaning for o in others):  # the help mostly says it already ("instead of ...")
            meaning += f" (not with {', '.join(others)})"
    return [p["name"], p["flag"], p["group"], unit, valid, default, meaning]


class ParametersDirective(SphinxDirective):
    optional_arguments = 1
    has_content = False

    def run(self):
        from hydrolux import _core

        jobs = [self.arguments[0]] if self.arguments else list(_core.jobs())
        info = getattr(_core, "job_info", None)
        out = []
        for job in jobs:
            params = _core.params(job)
            section = nodes.section(ids=[f"job-{job.replace('_', '-')}"], names=[f"job {job}"])
            title = nodes.title()
            title += nodes.literal(job, job)
            section += title
            if info is not None:
                i = info(job)
                para = nodes.paragraph()
                para += nodes.Text(f"{i['summary']}. Command line: ")
                para += nodes.literal(i["command"], i["command"])
                if i["python"]:
                    para += nodes.Text(f"; Python: {i['python']}")
                para += nodes.Text(f"; {len(params)} parameters.")
                section += para
            flags = {p["name"]: p["flag"] for p in params}
            section += _table([_param_row(p, flags) for p in params])
            out.append(section)
        return out


# ---- gallery ---------------------------------------------------------------------------------------

class _GalleryIndex(html.parser.HTMLParser):
    """The figures of the gallery's index.html: <figure><img src alt><figcaption><b>title.</b> text."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.figures: list[dict] = []
        self._in_caption = False
        self._in_bold = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "figure":
            self.figures.append({"file": "", "title": "", "caption": ""})
        elif tag == "img" and self.figures:
            self.figures[-1]["file"] = a.get("src", "")
            self.figures[-1]["title"] = a.get("alt", "")
        elif tag == "figcaption":
            self._in_caption = True
        elif tag == "b" and self._in_caption:
            self._in_bold = True

    def handle_endtag(self, tag):
        if tag == "figcaption":
            self._in_caption = False
        elif tag == "b":
            self._in_bold = False

    def handle_data(self, data):
        if self._in_caption and not self._in_bold and self.figures:
            self.figures[-1]["caption"] += data


def read_gallery(folder: str) -> list[dict]:
    with open(os.path.join(folder, "index.html"), encoding="utf-8") as f:
        parser = _GalleryIndex()
        parser.feed(f.read())
    for fig in parser.figures:
        fig["caption"] = re.sub(r"\s+", " ", fig["caption"]).strip()
    return [f for f in parser.figures if f["file"]]


class GalleryDirective(SphinxDirective):
    has_content = False

    def run(self):
        folder = self.config.hydrolux_gallery_dir
        if not folder:
            note = nodes.note()
            para = nodes.paragraph()
            para += nodes.Text("This build of the site has no gallery. ")
            para += nodes.literal("make docs", "make docs")
            para += nodes.Text(" renders it, or set HYDROLUX_DOCS_GALLERY to a folder made by ")
            para += nodes.literal("hydrolux gallery -o DIR", "hydrolux gallery -o DIR")
            para += nodes.Text(".")
            note += para
            return [note]
        folder = os.path.abspath(folder)
        index = os.path.join(folder, "index.html")
        self.env.note_dependency(index)
        if not os.path.isfile(index):
            logger.warning(f"hydrolux-gallery: no {index} (render it with hydrolux gallery -o {folder})",
                           location=self.get_location())
            return []
        out = []
        srcdir = os.path.dirname(self.env.doc2path(self.env.docname))
        for fig in read_gallery(folder):
            path = os.path.join(folder, fig["file"])
            if not os.path.isfile(path):
                logger.warning(f"hydrolux-gallery: {fig['file']} is listed in {index} but missing",
                               location=self.get_location())
                continue
            self.env.note_dependency(path)
            stem = os.path.splitext(fig["file"])[0]
            section = nodes.section(ids=["fig-" + stem.replace("_", "-")], names=[stem])
            section += nodes.title(fig["title"], fig["title"])
            figure = nodes.figure(classes=["hydrolux-gallery"])
            # A path relative to this page: Sphinx copies the picture into the site's _images.
            uri = os.path.relpath(path, srcdir)
            figure += nodes.image(uri=uri, alt=fig["title"], candidates={"*": uri})
            caption = nodes.caption()
            caption += nodes.Text(fig["caption"])
            figure += caption
            figure += nodes.paragraph("", "", nodes.literal(fig["file"], fig["file"]))
            section += figure
            out.append(section)
        return out


# ---- the batch jobs' --help ------------------------------------------------------------------------

class BatchHelpDirective(SphinxDirective):
    required_arguments = 1
    has_content = False

    def run(self):
        from hydrolux.batch.__main__ import main

        text = io.StringIO()
        env = os.environ.get("COLUMNS")
        os.environ["COLUMNS"] = "100"
        try:
            with contextlib.redirect_stdout(text), contextlib.suppress(SystemExit):
                main([self.arguments[0], "--help"])
        finally:
            if env is None:
                del os.environ["COLUMNS"]
            else:
                os.environ["COLUMNS"] = env
        block = nodes.literal_block(text.getvalue(), text.getvalue())
        block["language"] = "text"
        note = nodes.paragraph("", f"python3 -m hydrolux.batch {self.arguments[0]} --help (the core counts in it "
                               "are those of the machine that built this site):")
        return [note, block]


# ---- autodoc ---------------------------------------------------------------------------------------

def _drop_field_aliases(app, what, name, obj, options, lines):
    """A NamedTuple's fields keep their names and types but not Python's "Alias for field number N":
    the class's own docstring says what each holds."""
    if what in ("attribute", "property") and len(lines) <= 2 and lines and lines[0].startswith("Alias for field number"):
        lines.clear()


def _check_all_documented(app, env):
    """Every public name of the package (hydrolux.__all__) has its entry on the API page: a name added
    to __all__ but not to python-api.rst is a warning, so the page cannot fall behind the package."""
    import hydrolux

    objects = env.get_domain("py").objects
    for name in hydrolux.__all__:
        if f"hydrolux.{name}" not in objects:
            logger.warning(f"hydrolux.{name} is in hydrolux.__all__ but not documented: add it to python-api.rst")


# ---- Markdown checks -------------------------------------------------------------------------------

def _check_raw_html(app, doctree):
    """A '<' that opens a tag in the Markdown (sigma / <r>, std::vector<double>) is raw HTML: GitHub and
    the browser hide it. Only comments are welcome; anything else is a warning."""
    for node in doctree.findall(nodes.raw):
        text = node.astext().strip()
        if "html" in node.get("format", "").split() and not (text.startswith("<!--") and text.endswith("-->")):
            logger.warning(f"raw HTML {text[:40]!r} is hidden when the page is shown: escape the '<' as '\\<' "
                           "or put it in `code`", location=node)


def setup(app):
    app.connect("doctree-read", _check_raw_html)
    app.connect("autodoc-process-docstring", _drop_field_aliases)
    app.connect("env-check-consistency", _check_all_documented)
    app.add_config_value("hydrolux_gallery_dir", "", "env")
    app.add_directive("hydrolux-parameters", ParametersDirective)
    app.add_directive("hydrolux-gallery", GalleryDirective)
    app.add_directive("hydrolux-batch-help", BatchHelpDirective)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
