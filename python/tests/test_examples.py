"""Every example runs (miepython's habit): the doctests of hydrolux's public modules, where each public
function, class and method has an ``Example``, and the Python examples of README.md and docs/python.md.

- Public: a module's ``__all__``, or else the functions and classes it defines whose names do not start
  with "_"; and the methods (not properties) of those classes whose names do not start with "_". A name
  of ``__all__`` that lives in another module (``hydrolux.mie`` in ``hydrolux.scatter``) is tested under
  the name it is public by.
- Doctests run with ELLIPSIS and NORMALIZE_WHITESPACE, in a temporary folder that is also
  ``tempfile``'s, so that an example's files (``tempfile.mkdtemp()``) land in pytest's tmp_path.
- In the Markdown files: each fenced ```python block runs as a script, and each ```console or
  ```pycon block holding ``>>>`` lines runs as a doctest, in a temporary folder. A ```python block
  whose first line is ``# example: not run (<why>)`` is skipped, the reason given; a ``>>>`` line
  may carry ``# doctest: +SKIP``. Aim for every example to run.
"""
import doctest
import importlib
import inspect
import os
import re
import tempfile
import time

import pytest

MODULES = ["hydrolux", "hydrolux.batch", "hydrolux.batch.rain", "hydrolux.batch.fog", "hydrolux.batch.lens_drops",
           "hydrolux.batch.lee_atlas", "hydrolux.batch.__main__"]
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
NOT_RUN = "# example: not run"
SOURCE = os.environ.get("HYDROLUX_SOURCE_DIR") or os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DOCS = ["README.md", os.path.join("docs", "python.md")]


def public_objects(module):
    """(qualified name, object) of what the module makes public, with the public methods of its classes."""
    if hasattr(module, "__all__"):
        names = list(module.__all__)
    else:
        names = [n for n, v in vars(module).items() if not n.startswith("_")
                 and (inspect.isfunction(v) or inspect.isclass(v)) and v.__module__ == module.__name__]
    out = []
    for n in names:
        obj = getattr(module, n)
        out.append((f"{module.__name__}.{n}", obj))
        if inspect.isclass(obj):
            for m, v in vars(obj).items():
                if m.startswith("_"):
                    continue
                if isinstance(v, (classmethod, staticmethod)):
                    v = v.__func__
                if inspect.isfunction(v):
                    out.append((f"{module.__name__}.{n}.{m}", v))
    return out


def test_every_public_call_has_an_example():
    missing = []
    for name in MODULES:
        for qualname, obj in public_objects(importlib.import_module(name)):
            if ">>>" not in (inspect.getdoc(obj) or ""):
                missing.append(qualname)
    assert not missing, "no Example (a >>> line) in the docstring of: " + ", ".join(missing)


def _doctests():
    """Each module's doctests, and those of each name of its __all__ that lives in another module
    (hydrolux.mie in hydrolux.scatter), under the name it is public by (hydrolux.mie)."""
    finder = doctest.DocTestFinder(exclude_empty=True)
    found = []
    for name in MODULES:
        module = importlib.import_module(name)
        found += finder.find(module, name)
        for n in getattr(module, "__all__", ()):
            obj = getattr(module, n)
            if inspect.getmodule(obj) is not module:
                found += finder.find(obj, f"{name}.{n}")
    return sorted((t for t in found if t.examples), key=lambda t: t.name)


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    """A temporary working folder, also tempfile's, for the examples' files."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    return tmp_path


def _run(test):
    out = []
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    start = time.perf_counter()
    result = runner.run(test, out=out.append, clear_globs=True)
    assert result.failed == 0, "".join(out)
    return time.perf_counter() - start


@pytest.mark.parametrize("test", _doctests(), ids=lambda t: t.name)
def test_docstring_example(test, in_tmp):
    _run(test)


def _fenced_blocks(path):
    """(language, first line number, text) of each fenced block of a Markdown file."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    blocks, i = [], 0
    while i < len(lines):
        m = re.match(r"^\s*```\s*([\w+-]*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        j = i + 1
        while j < len(lines) and not re.match(r"^\s*```\s*$", lines[j]):
            j += 1
        blocks.append((m.group(1).lower(), i + 2, "\n".join(lines[i + 1:j]) + "\n"))
        i = j + 1
    return blocks


def _doc_examples():
    params = []
    for doc in DOCS:
        path = os.path.join(SOURCE, doc)
        for lang, line, text in _fenced_blocks(path):
            if lang in ("python", "py") or (lang in ("console", "pycon") and ">>>" in text):
                params.append(pytest.param(path, lang, line, text, id=f"{doc}:{line}"))
    return params


def test_the_docs_are_there():
    for doc in DOCS:
        assert os.path.isfile(os.path.join(SOURCE, doc)), f"{doc} not found under {SOURCE} (set HYDROLUX_SOURCE_DIR)"


@pytest.mark.parametrize("path,lang,line,text", _doc_examples())
def test_docs_example(path, lang, line, text, in_tmp):
    where = f"{os.path.relpath(path, SOURCE)}:{line}"
    if lang in ("python", "py"):
        first = text.lstrip().split("\n", 1)[0]
        if first.startswith(NOT_RUN):
            pytest.skip(f"{where}: {first[len(NOT_RUN):].strip(' ()') or 'marked not to run'}")
        exec(compile(text, where, "exec"), {"__name__": "__main__"})
    else:
        test = doctest.DocTestParser().get_doctest(text, {"__name__": "__main__"}, where, path, line - 1)
        _run(test)
