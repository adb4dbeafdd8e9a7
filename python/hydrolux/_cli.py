"""The ``hydrolux`` command of an installed package: the CLI executable the package carries in its
bin/ folder (with the plugins it loads from beside itself), run in this process's place."""
from __future__ import annotations

import os
import sys


def cli_path() -> str:
    """The hydrolux executable beside this package: $HYDROLUX_CLI, the package's bin/ (an installed
    copy), or the build tree's bin/ (PYTHONPATH=build/python).

    Example:

    >>> import os
    >>> from hydrolux import _cli
    >>> os.access(_cli.cli_path(), os.X_OK)
    True
    """
    env = os.environ.get("HYDROLUX_CLI")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    for c in (os.path.join(here, "bin", "hydrolux"), os.path.join(here, "..", "..", "bin", "hydrolux")):
        if os.access(c, os.X_OK):
            return os.path.normpath(c)
    raise FileNotFoundError("the hydrolux executable was not found beside the package (set HYDROLUX_CLI)")


def main() -> None:
    """Runs the CLI with this command's arguments (the console script ``hydrolux``)."""
    try:
        path = cli_path()
    except FileNotFoundError as e:
        sys.stderr.write(f"hydrolux: {e}\n")
        sys.exit(2)
    os.execv(path, [path] + sys.argv[1:])
