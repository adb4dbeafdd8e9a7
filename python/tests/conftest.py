"""Shared fixtures: the CLI beside the package (ctest sets HYDROLUX_CLI) and a helper to run it."""
import json
import os
import subprocess

import pytest


def cli_path():
    path = os.environ.get("HYDROLUX_CLI")
    if not path:
        here = os.path.dirname(os.path.abspath(__file__))
        path = os.path.join(here, "..", "..", "build", "bin", "hydrolux")
    return path


@pytest.fixture(scope="session")
def cli():
    path = cli_path()
    if not os.access(path, os.X_OK):
        pytest.fail(f"the hydrolux CLI is not at {path} (set HYDROLUX_CLI)")

    def run(*args, check=True, json_out=False):
        p = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        if check and p.returncode != 0:
            raise AssertionError(f"hydrolux {' '.join(map(str, args))} failed ({p.returncode}): {p.stderr}")
        return json.loads(p.stdout) if json_out else p

    run.path = path
    return run


def pytest_configure(config):
    # Debian's tornado 6.2 under distributed 2022.12: a deprecation inside Dask, not ours.
    config.addinivalue_line("filterwarnings", "ignore:make_current is deprecated:DeprecationWarning")
