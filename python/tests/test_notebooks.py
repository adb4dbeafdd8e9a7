"""Every example notebook runs: each examples/*.ipynb is executed top to bottom by nbconvert's
ExecutePreprocessor on the python3 kernel, and any cell that raises fails its test. The notebooks carry
their own checks (assert statements on the physics they show), so an example that stops being true
fails here too.

- Found by glob: a notebook added to examples/ is tested without editing this file.
- Executed in a temporary folder (the kernel's working directory and its TMPDIR, so files a notebook
  writes with tempfile land there), with MPLBACKEND=Agg (figures are drawn, not shown) and the package
  on the kernel's PYTHONPATH: the kernel is a subprocess and inherits this process's environment.
- The stored notebooks carry no outputs and no execution counts (they are kept clean in git); a
  notebook saved after running it fails test_stored_without_outputs.
- The timeout per cell guards against a hang; it is not a performance limit.
"""
import glob
import os
import re

import nbformat
import pytest
from nbconvert.preprocessors import CellExecutionError, ExecutePreprocessor

SOURCE = os.environ.get("HYDROLUX_SOURCE_DIR") or os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
EXAMPLES = os.path.join(SOURCE, "examples")
NOTEBOOKS = sorted(glob.glob(os.path.join(EXAMPLES, "*.ipynb")))
CELL_TIMEOUT_S = 600


def _ids():
    return [os.path.basename(p) for p in NOTEBOOKS]


def test_there_are_notebooks():
    assert NOTEBOOKS, f"no notebooks in {EXAMPLES}"


def _package_path():
    """The folder holding the hydrolux package this process imports (the build's, under ctest), absolute."""
    import hydrolux
    return os.path.dirname(os.path.dirname(os.path.abspath(hydrolux.__file__)))


def _kernel_env(monkeypatch, folder):
    """The environment the kernel subprocess inherits: the package importable (absolute paths, since
    the kernel runs in another folder), figures off-screen, temporary files and Jupyter's and
    IPython's state in the test's folder."""
    paths = [_package_path()] + [os.path.abspath(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(dict.fromkeys(paths)))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("TMPDIR", str(folder))
    monkeypatch.setenv("JUPYTER_RUNTIME_DIR", str(folder / "jupyter-runtime"))
    monkeypatch.setenv("IPYTHONDIR", str(folder / "ipython"))
    monkeypatch.setenv("PYDEVD_DISABLE_FILE_VALIDATION", "1")   # quiets the debugger's frozen-modules note
    cli = os.environ.get("HYDROLUX_CLI")
    if cli:
        monkeypatch.setenv("HYDROLUX_CLI", os.path.abspath(cli))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=_ids())
def test_stored_without_outputs(path):
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    assert nb.metadata.get("kernelspec", {}).get("name") == "python3", "the kernel should be python3"
    dirty = [i for i, cell in enumerate(nb.cells) if cell.cell_type == "code"
             and (cell.get("outputs") or cell.get("execution_count") is not None)]
    assert not dirty, (f"{os.path.basename(path)}: code cells {dirty} hold outputs or execution counts; clear them "
                       "(jupyter nbconvert --clear-output --inplace) before committing")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=_ids())
def test_notebook_runs(path, tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    _kernel_env(monkeypatch, tmp_path)
    nb = nbformat.read(path, as_version=4)
    executor = ExecutePreprocessor(kernel_name="python3", timeout=CELL_TIMEOUT_S)
    error = None
    try:
        executor.preprocess(nb, {"metadata": {"path": str(work)}})
    except CellExecutionError as e:
        error = re.sub(r"\x1b\[[0-9;]*m", "", str(e))   # the cell and its traceback, without terminal colours
    if error is not None:
        pytest.fail(f"{os.path.basename(path)}: a cell raised\n{error}", pytrace=False)
    ran = [c for c in nb.cells if c.cell_type == "code"]
    assert ran and all(c.execution_count is not None for c in ran), "not every code cell ran"
    # A notebook writes its files into a temporary folder, never where it runs.
    assert not any(work.iterdir()), f"{os.path.basename(path)} wrote into its working folder: {sorted(os.listdir(work))}"
