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


@pytest.fixture
def batch_matches_cli(tmp_path, cli):
    """Runs a frame job over a sequence of three frames (the built-in scene at 64 x 48, brighter each
    time) through ``hydrolux JOB --input-dir`` and ``python3 -m hydrolux.batch JOB`` (one worker, chunks
    of 2), with the same options, checks that their frames and masks are the same bytes, and returns
    the batch's output folder; the frames are in tmp_path / "frames"."""
    import hydrolux
    from hydrolux.batch.__main__ import main

    def run(job, *options):
        frames = tmp_path / "frames"
        frames.mkdir()
        base = hydrolux.builtin_scene(64, 48)
        for k in range(3):
            hydrolux.write_image(str(frames / f"f{k}.png"), base * (1 + 0.3 * k))
        cli(job, "-q", "--input-dir", frames, "--output-dir", tmp_path / "cli", "--mask-dir", tmp_path / "cli_masks",
            *options)
        assert main([job, "--input-dir", str(frames), "--output-dir", str(tmp_path / "batch"), "--mask-dir",
                     str(tmp_path / "batch_masks"), *map(str, options), "--workers", "1", "--chunk-frames", "2",
                     "-q"]) == 0
        for k in range(3):
            assert (tmp_path / "cli" / f"f{k}.png").read_bytes() == (tmp_path / "batch" / f"f{k}.png").read_bytes()
            assert (tmp_path / "cli_masks" / f"f{k}.png").read_bytes() == \
                (tmp_path / "batch_masks" / f"f{k}.png").read_bytes()
        return tmp_path / "batch"

    return run


def pytest_configure(config):
    # Debian's tornado 6.2 under distributed 2022.12: a deprecation inside Dask, not ours.
    config.addinivalue_line("filterwarnings", "ignore:make_current is deprecated:DeprecationWarning")
