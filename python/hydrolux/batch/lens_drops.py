"""python3 -m hydrolux.batch lens-drops: water drops on the lens or windshield over a folder of frames
on a Dask cluster.

The frames are one sequence in name order, as ``hydrolux lens-drops --input-dir``: frame k (its place
in the sequence) gets the drops of seed + k, so every frame has its own drops and the output is byte
for byte that of the single-process CLI whatever the chunks (docs/lens-drops.md), frames of several
sizes included (each is rendered at its own, as the CLI does). Each frame is
written atomically and recorded in the manifest as it completes; a re-run skips recorded frames
whose input is unchanged. Clean, degraded and mask folders are what raindrop-removal training uses.
"""
from __future__ import annotations

import argparse
from typing import Any, Dict

from . import _folder

# Seeds wrap as the CLI's do: (seed + k) modulo 2^53 + 1 (rain::kMaxSeed).
_MAX_SEED = 2 ** 53


def params() -> tuple:
    """The lens-drops job's declared parameters, the library's one table (``_core.params("lens_drops")``).

    Example:

    >>> from hydrolux.batch import lens_drops
    >>> p = {p["name"]: p for p in lens_drops.params()}
    >>> p["glass_distance_m"]["flag"], p["contact_angle_deg"]["unit"]
    ('--glass-distance-m', 'deg')
    """
    return _folder.params(LENS_DROPS)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The job's own options on the parser ``p`` (numbers kept as text for :func:`run` to parse as the
    CLI does); ``python3 -m hydrolux.batch`` adds the cluster's (--workers, --threads-per-worker,
    --scheduler, -q).

    Example:

    >>> import argparse
    >>> from hydrolux.batch import lens_drops
    >>> p = argparse.ArgumentParser(prog="lens-drops")
    >>> lens_drops.add_arguments(p)
    >>> a = p.parse_args(["--input-dir", "clean", "--output-dir", "degraded", "--seed", "1000"])
    >>> a.input_dir, a.seed
    ('clean', '1000')
    """
    _folder.add_arguments(p, LENS_DROPS)


def _prepare(first, opts: Dict[str, Any], ground: bool) -> tuple:
    """The options checked on the first readable frame (the library names a bad one)."""
    import hydrolux

    hydrolux.lens_drops(first, **opts)
    return {}, ""


def _render(image, depth, k: int, job: Dict[str, Any]) -> tuple:
    import hydrolux

    opts = dict(job["options"])
    opts["seed"] = (int(opts.get("seed", 0)) + k) % (_MAX_SEED + 1)
    r = hydrolux.lens_drops(image, **opts)
    return r.image, r.mask, None


# Each frame at its own size, as hydrolux lens-drops --input-dir renders a folder of frames of several sizes.
LENS_DROPS = _folder.FrameJob(name="lens-drops", job="lens_drops", noun="frames with drops",
                              prepare=_prepare, render=_render, one_size=False)


def run(a: argparse.Namespace, after_result=None) -> int:
    """The job (``python3 -m hydrolux.batch lens-drops``): 0 when every frame is in place, 1 when some
    failed, a UsageError naming the flag for bad input before any work.

    Example (a local cluster of one worker):

    >>> import argparse, hydrolux, os, tempfile
    >>> from hydrolux.batch import lens_drops
    >>> frames = tempfile.mkdtemp()
    >>> for k in range(2):
    ...     hydrolux.write_image(os.path.join(frames, f"f{k}.png"), hydrolux.builtin_scene(64, 48))
    >>> p = argparse.ArgumentParser()
    >>> lens_drops.add_arguments(p)
    >>> out = os.path.join(tempfile.mkdtemp(), "degraded")
    >>> a = p.parse_args(["--input-dir", frames, "--output-dir", out, "--seed", "7"])
    >>> a.workers, a.threads_per_worker, a.scheduler, a.quiet = 1, None, None, True   # the cluster's options
    >>> lens_drops.run(a)
    0
    >>> sorted(os.listdir(out))
    ['f0.png', 'f1.png', 'hydrolux-manifest.jsonl', ...]
    """
    return _folder.run(a, LENS_DROPS, after_result)
