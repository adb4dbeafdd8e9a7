"""A per-frame effect over a folder of frames on a Dask cluster: the skeleton ``hydrolux.batch fog``
and ``hydrolux.batch lens-drops`` share (the rain job, whose frames share one rain field in time, has
its own in rain.py).

A :class:`FrameJob` names the job's declared parameters (the library's one table), what it adds to
the job from the sequence's first frame (fog: the sky colour), and its per-frame render. The folder
is planned as the CLI plans it (``plan_frame_folder``), every input and output checked before any
work, each frame written atomically and recorded in the manifest as it completes; a re-run skips
recorded frames whose input is unchanged. The output is byte for byte the single-process CLI's.
"""
from __future__ import annotations

import argparse
import functools
import math
import os
import re
import sys
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional

from . import _common
from ._common import UsageError, printable

# A frame's float RGB in and out, its mask and the encoded file: about the rain job's ~100 bytes a pixel.
TASK_BYTES_PER_PIXEL = 100


@dataclass(frozen=True)
class FrameJob:
    name: str          # the batch job's name, "fog" ("batch fog: ..." in messages)
    job: str           # its declared parameters' job, _core.params(job)
    noun: str          # what --output-dir receives, "foggy frames"
    depth: bool        # whether it takes --depth-dir
    # The job's entries from the options and the first readable frame (fog: its sky colour); raises
    # ValueError naming a parameter for options the library refuses.
    prepare: Callable[[Any, Dict[str, Any]], Dict[str, Any]]
    # One frame: (image, depth or None, the frame's index in the sequence, the job) -> (image, mask).
    # A module-level function: the workers receive it by reference.
    render: Callable[[Any, Any, int, Dict[str, Any]], tuple]
    # The options' own requirement (fog: a visibility or a liquid water content), as a UsageError.
    require: Optional[Callable[[Dict[str, Any]], None]] = None
    # Whether the sequence has one size, as the CLI's job has it: fog refuses a frame of another size than
    # the first (its sky colour and fog are the first frame's), lens-drops renders each frame at its own.
    one_size: bool = True


@functools.lru_cache(maxsize=None)
def _declared(job: str) -> tuple:
    return tuple(_common.native("_core").params(job))


def params(fj: FrameJob) -> tuple:
    """The job's declared parameters, the library's one table (``_core.params(fj.job)``)."""
    return _declared(fj.job)


def add_arguments(p: argparse.ArgumentParser, fj: FrameJob) -> None:
    p.add_argument("--input-dir", help="A folder of frames in name order")
    p.add_argument("--output-dir", help=f"Folder for the {fj.noun} (created; never the input folder)")
    p.add_argument("--mask-dir", help="Folder for the coverage masks (same names as the frames)")
    if fj.depth:
        p.add_argument("--depth-dir", help="Depth maps: each frame's stem as .exr (metres) or .png (16-bit codes x "
                                           "--depth-scale-m); without, a ground plane")
    for q in params(fj):
        text = q["help"].replace("%", "%%")
        if q["kind"] == "flag":
            p.add_argument(q["flag"], dest=q["name"], action="store_const", const=not q["default"],
                           default=q["default"], help=text)
        else:
            p.add_argument(q["flag"], dest=q["name"], default=None,
                           help=f"{text}; valid {q['range']}" + (f" [{q['default_text']}]" if q["default_text"] else ""))
    p.add_argument("--chunk-frames", default=0, help="Frames per task (0: about 4 tasks per worker, at most 32)")


def _parse_numbers(a: argparse.Namespace, fj: FrameJob) -> None:
    for p in params(fj):
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


def _options(a: argparse.Namespace, fj: FrameJob) -> Dict[str, Any]:
    opts = {p["name"]: getattr(a, p["name"]) for p in params(fj)
            if p["group"] != "files" and getattr(a, p["name"], None) is not None}
    flags = {p["name"]: p["flag"] for p in params(fj)}
    for p in params(fj):
        if p["excludes"] and p["name"] in opts and p["excludes"] in opts:
            raise UsageError(f"{p['flag']}: give {flags[p['excludes']]} or {p['flag']}, not both")
    return opts


def flag_error(e: ValueError, fj: FrameJob) -> UsageError:
    """The library's message naming a parameter, said with its flag."""
    named = {p["name"]: p["flag"] for p in params(fj) if p["kind"] != "flag"}
    text = str(e)
    for name in sorted(named, key=len, reverse=True):
        text = re.sub(r"(?<![\w-])" + re.escape(name) + r"(?![\w-])", named[name], text)
    return UsageError(text)


def _render_frames(job: Dict[str, Any], frames: List[tuple]) -> List[dict]:
    """A task: consecutive frames [(index, input name, output name, depth map), ...], each written; one
    record per frame, a failed one carrying "error"."""
    import hydrolux

    _core = _common.native("_core")
    _image = _common.native("_image")
    if job["threads"]:
        hydrolux.set_threads(job["threads"])
    records = []
    for k, src, name, depth_name in frames:
        rec: Dict[str, Any] = {"output": name, "input": src}
        try:
            path = os.path.join(job["input_dir"], src)
            stamp = _common.file_stamp(path)
            image = _image.read(_common.fs(path))[0]
            h, w = image.shape[:2]
            if job["one_size"] and (w, h) != (job["width"], job["height"]):
                raise ValueError(f"is {w}x{h}, unlike the first frame ({job['width']}x{job['height']}); "
                                 "one sequence has one size")
            depth = None
            if depth_name:
                depth = _image.read_depth(_common.fs(os.path.join(job["depth_dir"], depth_name)),
                                          job["depth_scale_m"], w, h, "--depth-dir")[:, :, 0]
            out, mask = job["render"](image, depth, k, job)
            fmt = "exr" if name.endswith(".exr") else "png"
            if job["mask_dir"]:
                _core.write_file(_common.fs(os.path.join(job["mask_dir"], name)),
                                 _image.encode(mask, fmt, 16, True, job.get("png_compression")), "--mask-dir")
            data = _image.encode(out, fmt, 8, False, job.get("png_compression"))
            _core.write_file(_common.fs(os.path.join(job["output_dir"], name)), data, "--output-dir")
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


def plan_folder(input_dir: str, output_dir: str, mask_dir: Optional[str], depth_dir: Optional[str],
                tag: str) -> Dict[str, Any]:
    """The frames of ``input_dir`` as the CLI plans them (the library's one definition,
    ``_core.plan_frame_folder``), a UsageError naming the flag otherwise; skipped entries said in one
    warning line on stderr, ``hydrolux.<tag>: warning: ...``."""
    def path(p):  # as bytes: a name that is not UTF-8 reaches the library as it is
        return None if p is None else os.fsencode(p)

    try:
        plan = _common.native("_core").plan_frame_folder(path(input_dir), path(output_dir), path(mask_dir),
                                                         path(depth_dir))
    except ValueError as e:
        raise UsageError(str(e) or f"--input-dir {input_dir}: refused (a path that is not UTF-8)") from None
    if plan["skipped_warning"]:
        sys.stderr.write(printable(f"hydrolux.{tag}: warning: {plan['skipped_warning']}") + "\n")
        sys.stderr.flush()
    return plan


def checked_members(input_dir: str, output_dir: str, mask_dir: Optional[str], depth_dir: Optional[str],
                    plan: Dict[str, Any]) -> tuple:
    """The run's folders made absolute and each frame's depth map (or None), after checking member by
    member that no output file (a frame, a mask, the manifest or its lock) is, through a link, an input
    frame, a depth map or another output: ``(in_dir, out_dir, mask_dir, depth_dir, depths)``."""
    frames, names = plan["frames"], plan["outputs"]
    in_dir, out_dir = os.path.abspath(input_dir), os.path.abspath(output_dir)
    mask_dir = os.path.abspath(mask_dir) if mask_dir else None
    depth_dir = os.path.abspath(depth_dir) if depth_dir else None
    depths = plan["depth_maps"] if depth_dir else [None] * len(frames)
    inputs = [("--input-dir", os.path.join(in_dir, f)) for f in frames]
    if depth_dir:
        inputs += [("--depth-dir", os.path.join(depth_dir, d)) for d in depths]
    outputs = [("--output-dir", os.path.join(out_dir, n)) for n in names + [_common.MANIFEST, _common.LOCK]]
    if mask_dir:
        outputs += [("--mask-dir", os.path.join(mask_dir, n)) for n in names]
    _common.check_members(inputs, outputs)
    return in_dir, out_dir, mask_dir, depth_dir, depths


def first_readable_frame(in_dir: str, frames: List[str]):
    """The first of the frames that can be read (an unreadable one is reported with the rest by the
    run), as an array; a UsageError when none can."""
    _image = _common.native("_image")
    for f in frames:
        try:
            return _image.read(_common.fs(os.path.join(in_dir, f)))[0]
        except (ValueError, OSError):
            continue
    raise UsageError(f"--input-dir {in_dir}: no frame could be read")


def run(a: argparse.Namespace, fj: FrameJob, after_result=None) -> int:
    """The job: 0 when every frame is in place, 1 when some failed, a UsageError naming the flag for bad
    input before any work."""
    tag = f"batch {fj.name}"
    depth_dir_arg = getattr(a, "depth_dir", None) if fj.depth else None
    if a.input_dir is None:
        raise UsageError("--input-dir: give the folder of frames")
    if not a.output_dir:
        raise UsageError(f"--output-dir: give the folder for the {fj.noun} (with --input-dir)")
    _parse_numbers(a, fj)
    if fj.depth and a.depth_scale_m_given and not depth_dir_arg:
        raise UsageError("--depth-scale-m: scales PNG maps of --depth-dir; none is given")
    opts = _options(a, fj)
    if fj.require:
        fj.require(opts)

    plan = plan_folder(a.input_dir, a.output_dir, a.mask_dir, depth_dir_arg, tag)
    frames, names = plan["frames"], plan["outputs"]
    in_dir, out_dir, mask_dir, depth_dir, depths = checked_members(a.input_dir, a.output_dir, a.mask_dir,
                                                                   depth_dir_arg, plan)
    # The sequence's size (and the job's own entries) from its first readable frame, the options
    # checked on it.
    first = first_readable_frame(in_dir, frames)
    size = (first.shape[1], first.shape[0])
    try:
        extra = fj.prepare(first, opts)
    except ValueError as e:
        raise flag_error(e, fj) from None
    a.workers, a.threads_per_worker = _common.local_cluster_size(a.workers, a.threads_per_worker,
                                                                 TASK_BYTES_PER_PIXEL * size[0] * size[1], a.scheduler)
    client, cluster = _common.open_client(a.scheduler, a.workers, a.threads_per_worker, a.quiet)
    manifest = None
    failed: List[str] = []
    try:
        for flag, d in (("--output-dir", out_dir), ("--mask-dir", mask_dir)):
            if d:
                _common.make_folder(flag, d)
        depth_scale = a.depth_scale_m if depth_dir else None
        manifest = _common.Manifest(out_dir, fj.name, {"input_dir": in_dir, "mask_dir": mask_dir, "options": opts,
                                                       "size": list(size), "depth_dir": depth_dir,
                                                       "depth_scale_m": depth_scale, **extra})
        todo = [(k, src, name, depths[k]) for k, (src, name) in enumerate(zip(frames, names))
                if not _is_done(manifest.records.get(name), os.path.join(in_dir, src), os.path.join(out_dir, name))]
        workers = max(1, len(client.scheduler_info().get("workers", {})) or a.workers)
        chunk = a.chunk_frames or max(1, min(32, math.ceil(len(todo) / (4 * workers))))
        tasks = [todo[i:i + chunk] for i in range(0, len(todo), chunk)]
        cores = _common.usable_cores()
        job = {"input_dir": in_dir, "output_dir": out_dir, "mask_dir": mask_dir, "width": size[0], "height": size[1],
               "options": opts, "depth_dir": depth_dir, "depth_scale_m": depth_scale, "render": fj.render,
               "one_size": fj.one_size,
               "png_compression": getattr(a, "png_compression", None),
               "threads": 0 if a.scheduler else max(1, cores // max(1, a.workers * a.threads_per_worker)), **extra}
        progress = _common.Progress(tag, len(tasks), "frames", a.quiet)

        def on_result(task, result):
            if isinstance(result, Exception):
                for f in task[1]:
                    failed.append(f[1])
                progress.message(f"{tag}: {task[1][0][1]}: {type(result).__name__}: {result}")
                return
            for rec in result:
                if "error" in rec:
                    failed.append(rec["input"])
                    progress.message(f"{tag}: {rec['input']}: {rec['error']}")
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
        print(printable(f"{tag}: {len(frames) - len(failed)} of {len(frames)} frames in {out_dir}"
                        + (f"; {len(failed)} failed: {', '.join(failed[:5])}" if failed else "")), file=sys.stderr)
    return 1 if failed else 0
