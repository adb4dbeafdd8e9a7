"""A per-frame effect over a folder of frames on a Dask cluster: the one planner of ``hydrolux.batch
rain``, ``fog`` and ``lens-drops``.

A :class:`FrameJob` names the job's declared parameters (the library's one table), what it adds to
the job from the sequence's first frame (fog: the sky colour; rain: the field, checked), and its
per-frame render. The folder is planned as the CLI plans it (``plan_frame_folder``), every input and
output checked before any work, the sequence cut into chunks of consecutive frames (frame k at index
start + k: rain's --frame-index, else 0), each frame written atomically and recorded in the manifest
as it completes; a re-run skips recorded frames whose input, depth map and index are unchanged. A
task whose worker dies is tried again frame by frame, so that only the culprit fails. The output is
byte for byte the single-process CLI's.
"""
from __future__ import annotations

import argparse
import functools
import math
import os
import sys
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Tuple

from . import _common
from ._common import UsageError, printable

# What a task holds per pixel of its frame, measured on a worker (docs/batch.md, "Memory"): a 1080p frame
# raised a worker's peak by 208 MB (the frame as float RGB in and out, its mask, the 8-bit copy, the
# encoded file), ~100 bytes a pixel.
TASK_BYTES_PER_PIXEL = 100


@dataclass(frozen=True)
class FrameJob:
    name: str          # the batch job's name, "fog" ("batch fog: ..." in messages)
    job: str           # its declared parameters' job, _core.params(job)
    noun: str          # what --output-dir receives, "foggy frames"
    # From the first readable frame, the options and whether a ground plane stands for depth maps: the
    # job's entries for the manifest and the tasks (fog: its sky colour) and what the run's first line
    # adds (rain: "; N drops in the field"); raises ValueError naming a parameter for options the
    # library refuses (or a UsageError of the job's own words).
    prepare: Callable[[Any, Dict[str, Any], bool], Tuple[Dict[str, Any], str]]
    # One frame: (image, depth or None, the frame's index in the sequence, the job) -> (image, mask,
    # stats or None). A module-level function: the workers receive it by reference.
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


# The paths of a frame job the batch takes (the folders; rain's also --video and -o): declared in the
# library's table with the CLI's, read from it with their flags and help.
FOLDER_PATHS = ("input_dir", "output_dir", "mask_dir", "depth_dir")


def add_path_arguments(p: argparse.ArgumentParser, declared, names) -> None:
    """The declared paths of ``declared`` named in ``names`` (those the job's table has), as options."""
    for q in declared:
        if q["kind"] == "path" and q["name"] in names:
            flags = ([q["short_flag"]] if q["short_flag"] else []) + [q["flag"]]
            p.add_argument(*flags, dest=q["name"], metavar=q["words"][0], help=q["help"].replace("%", "%%"))


def add_arguments(p: argparse.ArgumentParser, fj: FrameJob) -> None:
    add_path_arguments(p, params(fj), FOLDER_PATHS)
    for q in params(fj):
        text = q["help"].replace("%", "%%")
        if q["kind"] == "path":
            continue
        if q["kind"] == "flag":
            p.add_argument(q["flag"], dest=q["name"], action="store_const", const=not q["default"],
                           default=q["default"], help=text)
        else:
            p.add_argument(q["flag"], dest=q["name"], default=None,
                           help=f"{text}; valid {q['range']}" + (f" [{q['default_text']}]" if q["default_text"] else ""))
            _common.add_deprecated_flag(p, q)
    p.add_argument("--chunk-frames", default=0, help="Frames per task (0: about 4 tasks per worker, at most 32)")


def _parse_numbers(a: argparse.Namespace, fj: FrameJob) -> None:
    _common.take_deprecated_flags(a, params(fj), lambda q: getattr(a, q["name"], None) is not None, f"batch {fj.name}")
    for p in params(fj):
        if p["kind"] in ("flag", "path"):
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
            if p["group"] != "files" and p["kind"] != "path" and getattr(a, p["name"], None) is not None}
    flags = {p["name"]: p["flag"] for p in params(fj)}
    for p in params(fj):
        if p["excludes"] and p["name"] in opts and p["excludes"] in opts:
            raise UsageError(f"{p['flag']}: give {flags[p['excludes']]} or {p['flag']}, not both")
    return opts


def flag_error(e: ValueError, fj: FrameJob, named_too: Optional[Dict[str, str]] = None) -> UsageError:
    """The library's message naming parameters, said with their flags (and the names of ``named_too``,
    what the message names that is no flag, in its words): the library's errors that name parameters
    carry ``said`` (the message with each name spelled by a dict), so no text is rewritten here."""
    said = getattr(e, "said", None)
    if said is None:
        return UsageError(str(e))
    named = {p["name"]: p["flag"] for p in params(fj) if p["kind"] != "flag"}
    named.update(named_too or {})
    return UsageError(said(named))


def render_frames(job: Dict[str, Any], frames: List[tuple], render: Optional[Callable] = None) -> List[dict]:
    """A task: consecutive frames [(input name, output name, frame index, depth map), ...], each rendered
    by ``render`` (else ``job["render"]``) and written; one record per frame, a failed one carrying
    "error" while the others go on."""
    import hydrolux

    _core = _common.native("_core")
    _image = _common.native("_image")
    render = render or job["render"]
    if job["threads"]:
        hydrolux.set_threads(job["threads"])
    records = []
    for src, name, index, depth_name in frames:
        rec: Dict[str, Any] = {"output": name, "input": src, "frame_index": index}
        try:
            path = os.path.join(job["input_dir"], src)
            stamp = _common.file_stamp(path)
            image = _image.read(_common.fs(path))[0]
            h, w = image.shape[:2]
            if job.get("one_size", True) and (w, h) != (job["width"], job["height"]):
                raise ValueError(f"is {w}x{h}, unlike the first frame ({job['width']}x{job['height']}); "
                                 "one sequence has one size")
            depth = depth_stamp = None
            if depth_name:
                depth_stamp = _common.file_stamp(os.path.join(job["depth_dir"], depth_name))
                depth = _image.read_depth(_common.fs(os.path.join(job["depth_dir"], depth_name)),
                                          job["depth_scale_m"], w, h, "--depth-dir")[:, :, 0]
            out, mask, stats = render(image, depth, index, job)
            fmt = "exr" if name.endswith(".exr") else "png"
            if job["mask_dir"]:
                _core.write_file(_common.fs(os.path.join(job["mask_dir"], name)),
                                 _image.encode(mask, fmt, 16, True, job.get("png_compression")), "--mask-dir")
            data = _image.encode(out, fmt, 8, False, job.get("png_compression"))
            _core.write_file(_common.fs(os.path.join(job["output_dir"], name)), data, "--output-dir")
            rec.update(input_size=stamp["size"], input_mtime_ns=stamp["mtime_ns"], output_size=len(data))
            if stats is not None:
                rec["stats"] = stats
            if depth_name:
                rec["depth"] = depth_stamp
        except Exception as e:  # reported by name; the chunk's other frames go on
            rec["error"] = str(e)
        records.append(rec)
    return records


# ---- on the client --------------------------------------------------------------------------------

def _is_done(rec: Optional[dict], frame_index: int, input_path: str, output_path: str, mask_path: Optional[str],
             depth_path: Optional[str]) -> bool:
    if not rec or "error" in rec or rec.get("frame_index") != frame_index:  # a frame added or removed before it
        return False
    if depth_path and rec.get("depth") != _common.file_stamp(depth_path):
        return False
    stamp = _common.file_stamp(input_path)
    out = _common.file_stamp(output_path)
    if stamp is None or out is None or (mask_path and _common.file_stamp(mask_path) is None):
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
    depth_dir_arg = getattr(a, "depth_dir", None)  # None where the job's table has no --depth-dir
    if a.input_dir is None:
        raise UsageError("--input-dir: give the folder of frames")
    if not a.output_dir:
        raise UsageError(f"--output-dir: give the folder for the {fj.noun} (with --input-dir)")
    _parse_numbers(a, fj)
    _common.refuse_unused(fj.job, a, ["depth_dir"] if depth_dir_arg else [])
    opts = _options(a, fj)
    if fj.require:
        fj.require(opts)
    return run_folder(a, fj, opts, after_result)


def run_folder(a: argparse.Namespace, fj: FrameJob, opts: Dict[str, Any], after_result=None,
               task: Optional[Callable] = None) -> int:
    """The frames of ``a.input_dir`` into ``a.output_dir`` (and their masks into ``a.mask_dir``) with the
    job's options ``opts``, every input checked before the cluster starts; each task runs
    ``task(job, frames)`` (by default :func:`render_frames`). ``a`` holds the parsed flags (the folders,
    ``depth_scale_m`` and whether it was given, ``png_compression``, rain's ``frame_index``,
    ``chunk_frames``) and the cluster's (``workers``, ``threads_per_worker``, ``scheduler``, ``quiet``)."""
    tag = f"batch {fj.name}"
    task = task or render_frames
    depth_dir_arg = getattr(a, "depth_dir", None) or None
    start = a.frame_index if any(p["name"] == "frame_index" for p in params(fj)) else None
    plan = plan_folder(a.input_dir, a.output_dir, a.mask_dir or None, depth_dir_arg, tag)
    frames, names = plan["frames"], plan["outputs"]
    exr_depth = next((d for d in plan["depth_maps"] if depth_dir_arg and d.lower().endswith(".exr")), None)
    if exr_depth and a.depth_scale_m_given:
        raise UsageError(f"--depth-scale-m: scales the codes of a PNG depth map; --depth-dir "
                         f"{os.path.abspath(depth_dir_arg)}: {exr_depth} holds metres already")
    in_dir, out_dir, mask_dir, depth_dir, depths = checked_members(a.input_dir, a.output_dir, a.mask_dir or None,
                                                                   depth_dir_arg, plan)
    # The sequence's size (and the job's own entries) from its first readable frame (an unreadable one is
    # reported with the rest), every option checked on it before any task starts.
    first = first_readable_frame(in_dir, frames)
    size = (first.shape[1], first.shape[0])
    try:
        extra, about = fj.prepare(first, opts, depth_dir is None)
    except ValueError as e:
        raise flag_error(e, fj) from None
    # The local cluster's size within the cores and the memory (a task holds a frame's buffers), then the
    # cluster: an unreachable scheduler leaves no output folder behind.
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
        entries = {"input_dir": in_dir, "mask_dir": mask_dir, "options": opts, "size": list(size),
                   "depth_dir": depth_dir, "depth_scale_m": depth_scale,
                   "png_compression": getattr(a, "png_compression", None), **extra}
        if start is not None:
            entries["frame_index"] = start
        manifest = _common.Manifest(out_dir, fj.name, entries)
        if manifest.restarted and not a.quiet:
            print(f"{tag}: {out_dir} holds a run with other parameters; every frame is redone", file=sys.stderr)
        first_index = start or 0
        todo = [(src, name, first_index + k, depths[k]) for k, (src, name) in enumerate(zip(frames, names))
                if not _is_done(manifest.records.get(name), first_index + k, os.path.join(in_dir, src),
                                os.path.join(out_dir, name), os.path.join(mask_dir, name) if mask_dir else None,
                                os.path.join(depth_dir, depths[k]) if depth_dir else None)]
        workers = max(1, len(client.scheduler_info().get("workers", {})) or a.workers)
        chunk = a.chunk_frames or max(1, min(32, math.ceil(len(todo) / (4 * workers))))
        tasks = [todo[i:i + chunk] for i in range(0, len(todo), chunk)]
        cores = _common.usable_cores()
        job = {"input_dir": in_dir, "output_dir": out_dir, "mask_dir": mask_dir, "width": size[0], "height": size[1],
               "options": opts, "depth_dir": depth_dir, "depth_scale_m": depth_scale, "render": fj.render,
               "one_size": fj.one_size, "png_compression": getattr(a, "png_compression", None),
               "threads": 0 if a.scheduler else max(1, cores // max(1, a.workers * a.threads_per_worker)), **extra}
        progress = _common.Progress(tag, len(tasks), "frames", a.quiet)
        if not a.quiet:
            link = _common.dashboard_link(client)
            where = a.scheduler or f"a local cluster of {a.workers} worker(s)"
            print(f"{tag}: {len(frames)} frames ({len(frames) - len(todo)} done before), {len(tasks)} tasks of up to "
                  f"{chunk} on {where}{about}" + (f"; dashboard {link}" if link else ""), file=sys.stderr)

        retry: List[tuple] = []
        final_round = False
        negatives = [0, 0]  # negative input values read as 0, and the frames that had them

        def on_result(task, result):
            if isinstance(result, Exception):
                # The task as a whole failed: a frame that kills its worker every time (KilledWorker), or
                # a bystander queued on that worker. Its frames go again alone, one task at a time, so
                # that only the culprit can fail and the others are kept.
                if not final_round:
                    retry.extend(task[1])
                    return
                failed.append(task[1][0][0])
                progress.message(f"{tag}: {task[1][0][0]}: {type(result).__name__}: {result}")
                return
            for rec in result:
                if "error" in rec:
                    failed.append(rec["input"])
                    progress.message(f"{tag}: {rec['input']}: {rec['error']}")
                else:
                    manifest.add(rec)
                    n = rec.get("stats", {}).get("negative_values_clamped", 0)
                    negatives[0] += n
                    negatives[1] += 1 if n else 0

        def count(r):
            return 0 if isinstance(r, Exception) else len(r)

        _common.run_tasks(client, [(job, t) for t in tasks], task, on_result, progress, count, after_result)
        if retry:
            final_round = True
            progress.message(f"{tag}: {len(retry)} frame(s) of failed tasks, again one at a time")
            progress = _common.Progress(f"{tag} (again)", len(retry), "frames", a.quiet)
            for k, f in enumerate(sorted(retry)):
                _common.run_tasks(client, [(job, [f])], task, on_result, progress, count)
                progress.update(k + 1, k + 1)
        progress.finish()
        if negatives[0]:
            progress.message(f"{tag}: warning: --input-dir {a.input_dir}: {negatives[0]} negative value"
                             f"{'s' if negatives[0] != 1 else ''} in {negatives[1]} frame(s) read as 0 (light cannot "
                             "be negative)")
    finally:
        _common.close_client(client, cluster)
        if manifest is not None:
            for d in (out_dir, mask_dir):
                if d:
                    _common.remove_stale_temporaries(d, names)
            manifest.close()
    if not a.quiet:
        print(printable(f"{tag}: {len(frames) - len(failed)} of {len(frames)} frames in {out_dir}"
                        + (f"; {len(failed)} failed: {', '.join(failed[:5])}{' ...' if len(failed) > 5 else ''}"
                           if failed else "")), file=sys.stderr)
    return 1 if failed else 0
