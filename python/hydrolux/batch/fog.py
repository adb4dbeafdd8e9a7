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
import math
import os
import re
import sys
from typing import Any, Dict, List

from . import _common
from ._common import UsageError, printable

# A frame's float RGB in and out, its mask and the encoded file: about the rain job's ~100 bytes a pixel.
TASK_BYTES_PER_PIXEL = 100


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
    p.add_argument("--input-dir", help="A folder of frames in name order: one fog and one sky colour across them")
    p.add_argument("--output-dir", help="Folder for the foggy frames (created; never the input folder)")
    p.add_argument("--mask-dir", help="Folder for the fog's coverage masks 1 - t (same names as the frames)")
    p.add_argument("--depth-dir", help="Depth maps: each frame's stem as .exr (metres) or .png (16-bit codes x "
                                       "--depth-scale-m); without, a ground plane")
    for q in params():
        text = q["help"].replace("%", "%%")
        if q["kind"] == "flag":
            p.add_argument(q["flag"], dest=q["name"], action="store_const", const=not q["default"],
                           default=q["default"], help=text)
        else:
            p.add_argument(q["flag"], dest=q["name"], default=None,
                           help=f"{text}; valid {q['range']}" + (f" [{q['default_text']}]" if q["default_text"] else ""))
    p.add_argument("--chunk-frames", default=0, help="Frames per task (0: about 4 tasks per worker, at most 32)")


def _parse_numbers(a: argparse.Namespace) -> None:
    for p in params():
        if p["kind"] == "flag":
            continue
        value = getattr(a, p["name"], None)
        setattr(a, p["name"] + "_given", value is not None)
        if value is None:
            value = p["default"] if p["group"] == "files" else None
        if value is None:
            continue
        if p["kind"] == "integer":
            setattr(a, p["name"], _common.integer_flag(p["flag"], value, int(p["lo"]), int(p["hi"]), p["unit"]))
        else:
            setattr(a, p["name"], _common.number_flag(p["flag"], value, p["lo"], p["hi"], p["unit"]))
    a.chunk_frames = _common.integer_flag("--chunk-frames", a.chunk_frames, 0, 100000, extra=" (0: automatic)")


def _options(a: argparse.Namespace) -> Dict[str, Any]:
    opts = {p["name"]: getattr(a, p["name"]) for p in params()
            if p["group"] != "files" and getattr(a, p["name"], None) is not None}
    flags = {p["name"]: p["flag"] for p in params()}
    for p in params():
        if p["excludes"] and p["name"] in opts and p["excludes"] in opts:
            raise UsageError(f"{p['flag']}: give {flags[p['excludes']]} or {p['flag']}, not both")
    return opts


def _flag_error(e: ValueError) -> UsageError:
    named = {p["name"]: p["flag"] for p in params() if p["kind"] != "flag"}
    text = str(e)
    for name in sorted(named, key=len, reverse=True):
        text = re.sub(r"(?<![\w-])" + re.escape(name) + r"(?![\w-])", named[name], text)
    return UsageError(text)


def _render_frames(job: Dict[str, Any], frames: List[tuple]) -> List[dict]:
    """A task: fog over consecutive frames [(input name, output name, depth map), ...], each written; one
    record per frame, a failed one carrying "error"."""
    import hydrolux

    _core = _common.native("_core")
    _image = _common.native("_image")
    if job["threads"]:
        hydrolux.set_threads(job["threads"])
    records = []
    for src, name, depth_name in frames:
        rec: Dict[str, Any] = {"output": name, "input": src}
        try:
            path = os.path.join(job["input_dir"], src)
            stamp = _common.file_stamp(path)
            image = _image.read(path)[0]
            h, w = image.shape[:2]
            if (w, h) != (job["width"], job["height"]):
                raise ValueError(f"is {w}x{h}, unlike the first frame ({job['width']}x{job['height']}); "
                                 "one sequence has one size")
            depth = None
            if depth_name:
                depth = _image.read_depth(os.path.join(job["depth_dir"], depth_name), job["depth_scale_m"], w, h,
                                          "--depth-dir")[:, :, 0]
            result = hydrolux.fog(image, depth, job["sky_rgb"], **job["options"])
            fmt = "exr" if name.endswith(".exr") else "png"
            if job["mask_dir"]:
                _core.write_file(os.path.join(job["mask_dir"], name), _image.encode(result.mask, fmt, 16, True, job.get("png_compression")),
                                 "--mask-dir")
            data = _image.encode(result.image, fmt, 8, False, job.get("png_compression"))
            _core.write_file(os.path.join(job["output_dir"], name), data, "--output-dir")
            rec.update(input_size=stamp["size"], input_mtime_ns=stamp["mtime_ns"], output_size=len(data))
        except Exception as e:
            rec["error"] = str(e)
        records.append(rec)
    return records


def _is_done(rec, input_path: str, output_path: str) -> bool:
    if not rec or "error" in rec:
        return False
    stamp, out = _common.file_stamp(input_path), _common.file_stamp(output_path)
    if stamp is None or out is None:
        return False
    return (stamp["size"], stamp["mtime_ns"]) == (rec.get("input_size"), rec.get("input_mtime_ns")) and \
        out["size"] == rec.get("output_size")


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
    import hydrolux
    _image = _common.native("_image")

    if a.input_dir is None:
        raise UsageError("--input-dir: give the folder of frames")
    if not a.output_dir:
        raise UsageError("--output-dir: give the folder for the foggy frames (with --input-dir)")
    _parse_numbers(a)
    if a.depth_scale_m_given and not a.depth_dir:
        raise UsageError("--depth-scale-m: scales PNG maps of --depth-dir; none is given")
    opts = _options(a)
    if "visibility_m" not in opts and "lwc_g_m3" not in opts:
        raise UsageError("--visibility-m: give the fog's visibility in metres (Koschmieder), or --lwc-g-m3 for Mie "
                         "over the droplets")

    def path(p):
        return None if p is None else os.fsencode(p)

    try:
        plan = _common.native("_core").plan_frame_folder(path(a.input_dir), path(a.output_dir), path(a.mask_dir),
                                                         path(a.depth_dir))
    except UnicodeDecodeError:
        raise UsageError(f"--input-dir {a.input_dir}: holds a name that is not UTF-8") from None
    except ValueError as e:
        raise UsageError(str(e) or f"--input-dir {a.input_dir}: refused") from None
    if plan["skipped_warning"]:
        sys.stderr.write(printable(f"hydrolux.batch fog: warning: {plan['skipped_warning']}") + "\n")
    frames, names = plan["frames"], plan["outputs"]
    in_dir, out_dir = os.path.abspath(a.input_dir), os.path.abspath(a.output_dir)
    mask_dir = os.path.abspath(a.mask_dir) if a.mask_dir else None
    depth_dir = os.path.abspath(a.depth_dir) if a.depth_dir else None
    depths = plan["depth_maps"] if depth_dir else [None] * len(frames)
    inputs = [("--input-dir", os.path.join(in_dir, f)) for f in frames]
    if depth_dir:
        inputs += [("--depth-dir", os.path.join(depth_dir, d)) for d in depths]
    outputs = [("--output-dir", os.path.join(out_dir, n)) for n in names + [_common.MANIFEST, _common.LOCK]]
    if mask_dir:
        outputs += [("--mask-dir", os.path.join(mask_dir, n)) for n in names]
    _common.check_members(inputs, outputs)
    # The sequence's size and sky colour from its first readable frame, the options checked on it.
    first = None
    for f in frames:
        try:
            first = _image.read(os.path.join(in_dir, f))[0]
            break
        except (ValueError, OSError):
            continue
    if first is None:
        raise UsageError(f"--input-dir {in_dir}: no frame could be read")
    size = (first.shape[1], first.shape[0])
    try:
        sky = list(hydrolux.fog(first, **opts).stats["sky_rgb"])
    except ValueError as e:
        raise _flag_error(e) from None
    a.workers, a.threads_per_worker = _common.local_cluster_size(a.workers, a.threads_per_worker,
                                                                 TASK_BYTES_PER_PIXEL * size[0] * size[1], a.scheduler)
    client, cluster = _common.open_client(a.scheduler, a.workers, a.threads_per_worker, a.quiet)
    manifest = None
    failed: List[str] = []
    try:
        for flag, d in (("--output-dir", out_dir), ("--mask-dir", mask_dir)):
            if d:
                _common.make_folder(flag, d)
        manifest = _common.Manifest(out_dir, "fog", {"input_dir": in_dir, "mask_dir": mask_dir, "options": opts,
                                                     "size": list(size), "depth_dir": depth_dir, "sky_rgb": sky,
                                                     "depth_scale_m": a.depth_scale_m if depth_dir else None})
        todo = [(src, name, depths[k]) for k, (src, name) in enumerate(zip(frames, names))
                if not _is_done(manifest.records.get(name), os.path.join(in_dir, src), os.path.join(out_dir, name))]
        workers = max(1, len(client.scheduler_info().get("workers", {})) or a.workers)
        chunk = a.chunk_frames or max(1, min(32, math.ceil(len(todo) / (4 * workers))))
        tasks = [todo[i:i + chunk] for i in range(0, len(todo), chunk)]
        cores = _common.usable_cores()
        job = {"input_dir": in_dir, "output_dir": out_dir, "mask_dir": mask_dir, "width": size[0], "height": size[1],
               "options": opts, "depth_dir": depth_dir, "depth_scale_m": a.depth_scale_m, "sky_rgb": sky,
               "threads": 0 if a.scheduler else max(1, cores // max(1, a.workers * a.threads_per_worker))}
        progress = _common.Progress("batch fog", len(tasks), "frames", a.quiet)

        def on_result(task, result):
            if isinstance(result, Exception):
                for f in task[1]:
                    failed.append(f[0])
                progress.message(f"batch fog: {task[1][0][0]}: {type(result).__name__}: {result}")
                return
            for rec in result:
                if "error" in rec:
                    failed.append(rec["input"])
                    progress.message(f"batch fog: {rec['input']}: {rec['error']}")
                else:
                    manifest.add(rec)

        _common.run_tasks(client, [(job, t) for t in tasks], _render_frames, on_result, progress,
                          lambda r: 0 if isinstance(r, Exception) else len(r), after_result)
        progress.finish()
    finally:
        _common.close_client(client, cluster)
        if manifest is not None:
            for d in (out_dir, mask_dir):
                if d:
                    _common.remove_stale_temporaries(d, names)
            manifest.close()
    if not a.quiet:
        print(f"batch fog: {len(frames) - len(failed)} of {len(frames)} frames in {out_dir}"
              + (f"; {len(failed)} failed: {', '.join(failed[:5])}" if failed else ""), file=sys.stderr)
    return 1 if failed else 0
