"""python3 -m hydrolux.batch fog: fog, haze or mist over a folder of frames on a Dask cluster.

The frames are one sequence in name order, as ``hydrolux fog --input-dir``: one fog (the library's
declared parameters, docs/fog.md) and one sky colour, estimated on the client from the first
readable frame and passed to every task, so that the output is byte for byte that of the
single-process CLI whatever the chunks. Each frame is written atomically and recorded in the
manifest as it completes; a re-run skips recorded frames whose input is unchanged.
"""
from __future__ import annotations

import argparse
import functools
from typing import Any, Dict

from . import _common, _folder
from ._common import UsageError


@functools.lru_cache(maxsize=None)
def params() -> tuple:
    """The fog job's declared parameters, the library's one table (``_core.params("fog")``).

    Example:

    >>> from hydrolux.batch import fog
    >>> p = {p["name"]: p for p in fog.params()}
    >>> p["visibility_m"]["flag"], p["visibility_m"]["range"]
    ('--visibility-m', '[1, 100000] m')
    """
    return tuple(_common.native("_core").params("fog"))


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The fog job's own options on the parser ``p``, numbers kept as text for :func:`run` to parse as
    the CLI does; ``python3 -m hydrolux.batch`` adds the cluster's (--workers, --threads-per-worker,
    --scheduler, -q).

    Example:

    >>> import argparse
    >>> from hydrolux.batch import fog
    >>> p = argparse.ArgumentParser(prog="fog")
    >>> fog.add_arguments(p)
    >>> a = p.parse_args(["--input-dir", "frames", "--output-dir", "foggy", "--visibility-m", "150", "--no-glow"])
    >>> a.input_dir, a.visibility_m, a.glow
    ('frames', '150', False)
    """
    _folder.add_arguments(p, FOG)


def _prepare(first, opts: Dict[str, Any], ground: bool) -> tuple:
    """The sequence's sky colour, from its first readable frame (the options checked on it)."""
    import hydrolux

    return {"sky_rgb": list(hydrolux.fog(first, **opts).stats["sky_rgb"])}, ""


def _render(image, depth, k: int, job: Dict[str, Any]) -> tuple:
    import hydrolux

    r = hydrolux.fog(image, depth, job["sky_rgb"], **job["options"])
    return r.image, r.mask, None


def _require(opts: Dict[str, Any]) -> None:
    if "visibility_m" not in opts and "lwc_g_m3" not in opts:
        raise UsageError("--visibility-m: give the fog's visibility in metres (Koschmieder), or --lwc-g-m3 for Mie "
                         "over the droplets")


FOG = _folder.FrameJob(name="fog", job="fog", noun="foggy frames", prepare=_prepare, render=_render,
                       require=_require)


def run(a: argparse.Namespace, after_result=None) -> int:
    """The job (``python3 -m hydrolux.batch fog``): 0 when every frame is in place, 1 when some failed,
    a UsageError naming the flag for bad input before any work.

    Example (a local cluster of one worker):

    >>> import argparse, hydrolux, os, tempfile
    >>> from hydrolux.batch import fog
    >>> frames = tempfile.mkdtemp()
    >>> for k in range(2):
    ...     hydrolux.write_image(os.path.join(frames, f"f{k}.png"), hydrolux.builtin_scene(64, 48))
    >>> p = argparse.ArgumentParser()
    >>> fog.add_arguments(p)
    >>> out = os.path.join(tempfile.mkdtemp(), "foggy")
    >>> a = p.parse_args(["--input-dir", frames, "--output-dir", out, "--visibility-m", "150"])
    >>> a.workers, a.threads_per_worker, a.scheduler, a.quiet = 1, None, None, True   # the cluster's options
    >>> fog.run(a)
    0
    >>> sorted(os.listdir(out))
    ['f0.png', 'f1.png', 'hydrolux-manifest.jsonl', ...]
    """
    return _folder.run(a, FOG, after_result)
