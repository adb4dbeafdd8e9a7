"""What every batch job shares: the Dask client, the manifest, progress, and clean-up.

The manifest is a journal of JSON lines in the output folder (``hydrolux-manifest.jsonl``): a
header naming the job and its parameters, then one record per finished output, appended and
fsync'd as each task's result reaches the client. A torn last line (a crash mid-write) is ignored;
a re-run with the same parameters skips every output whose record matches what is on disk, and a
run with other parameters starts a new journal (everything is redone). A lock on
``hydrolux-manifest.lock`` keeps two runs out of one output folder at a time.
"""
from __future__ import annotations

import fcntl
import json
import logging
import math
import os
import re
import stat
import sys
import time
import uuid
from typing import Any, Callable, Dict, Iterable, List, Optional

MANIFEST = "hydrolux-manifest.jsonl"
LOCK = "hydrolux-manifest.lock"
# The largest manifest a run reads back (a rain frame's record is ~700 bytes, a lee-atlas table's at most
# ~17 KB: 256 MiB holds ~380,000 frames or the 10,000 tables of the largest atlas); a larger one is refused
# as any oversized input is, with the limit in the message.
MANIFEST_MAX_BYTES = 256 << 20


class UsageError(Exception):
    """A bad argument: printed as one line, exit code 2."""


class RunFailure(Exception):
    """The system failed midway (a full disk, an I/O error): printed as one line naming the path and the
    OS's reason, exit code 1."""


def printable(text: str) -> str:
    """``text`` on one line that cannot drive the terminal, as the CLI prints names (docs/safe-io.md): the
    library's own hydrolux::printable (a name that is not UTF-8 reaches it as its bytes)."""
    return native("_core").printable(str(text).encode("utf-8", "surrogateescape"))


def clip(value, limit: int = 60) -> str:
    """``value`` as text for a message, at most about ``limit`` characters: a longer one is cut and says how
    long it was ("aaaa... (1073741824 characters)"), so that a hostile value cannot make the one-line error
    a gigabyte."""
    text = value if isinstance(value, str) else repr(value)
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text)} characters)"


def fs(path):
    """A path as the bindings take it: bytes (``os.fsencode``), so that a name that is not UTF-8 (a folder
    named with byte 0xff, which Python holds as a surrogate escape) reaches the library as the bytes it
    is, as the CLI gets it from argv. None stays None."""
    return None if path is None else os.fsencode(path)


# ---- files the batch reads itself -----------------------------------------------------------------
# A lee-atlas spec, a manifest, an atlas's index, a staged chunk: checked as the CLI checks the files it
# reads whole (io::read_file, src/io/files.cpp), with its words: a regular file (not a FIFO, which would
# block, nor a device like /dev/zero, which never ends), of at most a limit of bytes, opened without
# blocking and checked again on the open descriptor.

def _file_kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def read_input(path: str, label: str, max_bytes: int, error=None) -> bytes:
    """The bytes of the file ``path`` (named in messages as "<label> <path>"), checked as the CLI's
    io::read_file checks an input: a regular file of at most ``max_bytes`` bytes, opened non-blocking.
    ``error`` (default UsageError) otherwise, one line in the CLI's words: "--spec /dev/zero: a
    character device, not a regular file; give a file", "--spec big.json: the file has 5000000 bytes,
    more than the limit of 4194304 bytes", "--spec x.json: no such file". FileNotFoundError's case is
    ``error`` too."""
    error = error or UsageError
    shown = f"{label} {path}" if label else f"'{path}'"
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise error(f"{shown}: no such file") from None
    except OSError as e:
        raise error(f"{shown}: {e.strerror or e}") from None
    if not stat.S_ISREG(st.st_mode):
        raise error(f"{shown}: {_file_kind(st.st_mode)}, not a regular file; give a file")
    if st.st_size > max_bytes:
        raise error(f"{shown}: the file has {st.st_size} bytes, more than the limit of {max_bytes} bytes")
    try:  # non-blocking, so that a FIFO swapped in after the check cannot stall the open
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | os.O_NOCTTY)
    except OSError as e:
        raise error(f"{shown}: cannot open: {e.strerror or e}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_size > max_bytes:
            raise error(f"{shown}: changed while being opened; not a regular file of at most {max_bytes} bytes")
        parts, got = [], 0
        while got <= max_bytes:  # at most one byte more than the limit: a file that grew is refused
            try:
                block = os.read(fd, min(1 << 20, max_bytes + 1 - got))
            except InterruptedError:
                continue
            except OSError as e:
                raise RunFailure(f"{path}: read failed: {e.strerror or e}") from None
            if not block:
                break
            parts.append(block)
            got += len(block)
        if got > max_bytes:
            raise error(f"{shown}: grew while being read, past the limit of {max_bytes} bytes")
        return b"".join(parts)
    finally:
        os.close(fd)


def os_error_text(e: OSError, path: Optional[str] = None) -> str:
    """An OSError as "<path>: <the OS's reason>" (hydrolux's own OSErrors already read so)."""
    path = path if path is not None else e.filename
    if e.strerror and path is not None:
        return f"{path}: {e.strerror}"
    return str(e) or type(e).__name__


# ---- numeric flags, parsed as the CLI parses them --------------------------------------------------
# The library's own strict parsers (hydrolux::parse::number and ::integer, bound as _core.parse_number and
# _core.parse_integer): the whole text or nothing, no spaces, underscores, "inf" or "nan"; whole numbers also
# in exponent form ("1e3"). The messages are the CLI's (tools/hydrolux/common.cpp): "--seed: 1.5 is not a
# whole number; valid range [0, 9007199254740992]".

_DECIMAL = re.compile(r"^-?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?$")


def _text(value) -> str:
    return value if isinstance(value, str) else repr(value)


def refuse_unused(job: str, a, held: Iterable[str]) -> None:
    """UsageError for a flag of ``job`` given (``a.<name>_given``) where the run leaves it unused, by the
    table's conditions (only with --video, not with --video, only with depth maps): the library's one
    message, as the CLI says it ("--crf 20: sets the H.264 quality of --video's output; ...")."""
    given = {}
    for p in native("_core").params(job):
        if getattr(a, p["name"] + "_given", False):
            v = getattr(a, p["name"])
            given[p["name"]] = format(v, "g") if isinstance(v, float) else str(v)
    try:
        native("_core").report_unused(job, given, list(held))
    except ValueError as e:
        raise UsageError(str(e)) from None


def conditional(params: Iterable[dict]) -> set:
    """The names of the parameters that have an effect only in some runs (the table's only_with /
    not_with): their argparse default is None, so that a run can tell whether they were given."""
    return {p["name"] for p in params if p.get("only_with") or p.get("not_with")}


def _core_parse(kind: str, text: str):
    _core = native("_core")
    try:  # bytes, so that a word of argv that is not UTF-8 reaches the parser as it is (and fails there)
        return getattr(_core, kind)(text.encode("utf-8", "surrogateescape"))
    except (UnicodeError, ValueError, TypeError):
        return None


def _range(lo, hi, unit: str, lo_open: bool = False) -> str:
    return ("(" if lo_open else "[") + f"{lo:g}, {hi:g}]" + (" " + unit if unit else "")


def number_flag(flag: str, value, lo: float, hi: float, unit: str = "", lo_open: bool = False) -> float:
    """A finite number in [lo, hi] (or (lo, hi]) given to ``flag``, as the CLI's number_in accepts it; text is
    parsed by the library, a number (the Python API) only range-checked. UsageError otherwise."""
    range_text = _range(lo, hi, unit, lo_open)
    if isinstance(value, str):
        v = _core_parse("parse_number", value)
        if v is None:
            beyond = False
            if _DECIMAL.match(value):  # "1e400", "1e-400": numbers, just not ones a double holds
                try:
                    x = float(value)
                    beyond = math.isinf(x) or (x == 0 and re.search(r"[1-9]", value.split("e")[0].split("E")[0])
                                               is not None)
                except ValueError:
                    pass
            raise UsageError(f"{flag}: '{value}' is " +
                             ("beyond what a double holds (about 1e-308 to 1e308 in magnitude)" if beyond
                              else "not a finite number") + f"; valid range {range_text}")
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        v = float(value)
    else:
        raise UsageError(f"{flag}: '{_text(value)}' is not a finite number; valid range {range_text}")
    if not math.isfinite(v):
        raise UsageError(f"{flag}: '{_text(value)}' is not a finite number; valid range {range_text}")
    if (not (v > lo) if lo_open else not (v >= lo)) or not (v <= hi):
        raise UsageError(f"{flag}: {_text(value) if isinstance(value, str) else f'{v:g}'} is outside "
                         f"the valid range {range_text}")
    return v


def _flag_of(name: str) -> str:
    return "--" + name.replace("_", "-")


def add_deprecated_flag(p, q: dict) -> None:
    """The old flag of the declared parameter ``q`` where it was renamed (``q["deprecated"]``, kept for one
    release): hidden from --help, and kept apart (``<name>_deprecated``) for :func:`take_deprecated_flags`."""
    if q.get("deprecated"):
        import argparse

        p.add_argument(_flag_of(q["deprecated"]), dest=q["name"] + "_deprecated", default=None, help=argparse.SUPPRESS)


def take_deprecated_flags(a, params, given: Callable[[dict], bool], tag: str) -> None:
    """Each renamed parameter given by its old flag, in place: its value as the new flag's, with one warning
    line on stderr in the CLI's words (``hydrolux.<tag>: warning: --rate-mmh is deprecated ...: give
    --rain-rate-mmh ...``); both flags given (``given(q)``: the new one was) is a UsageError naming both."""
    for q in params:
        value = getattr(a, q["name"] + "_deprecated", None) if q.get("deprecated") else None
        if value is None:
            continue
        old = _flag_of(q["deprecated"])
        if given(q):
            raise UsageError(f"{old}: give {q['flag']} or {old} ({q['flag']}'s deprecated name), not both")
        setattr(a, q["name"], value)
        text = native("_core").deprecation_warning(old, q["flag"], q["unit"])
        sys.stderr.write(printable(f"hydrolux.{tag}: warning: {text}") + "\n")


def integer_flag(flag: str, value, lo: int, hi: int, unit: str = "", extra: str = "") -> int:
    """A whole number in [lo, hi] given to ``flag``, as the CLI's integer_in accepts it ("1e3" is 1000).
    ``extra`` follows the range in the message (what the bound means)."""
    range_text = f"[{lo}, {hi}]" + (" " + unit if unit else "") + extra
    if isinstance(value, str):
        v = _core_parse("parse_integer", value)
        if v is None:
            x = _core_parse("parse_number", value)
            shown = value
            if x is not None and x == math.floor(x):
                raise UsageError(f"{flag}: {shown} is outside the valid range {range_text}")
            if x is not None:
                raise UsageError(f"{flag}: {shown} is not a whole number; valid range {range_text}")
            raise UsageError(f"{flag}: '{shown}' is not a whole number; valid range {range_text}")
        shown = value
    elif isinstance(value, int) and not isinstance(value, bool):
        v, shown = value, str(value)
    else:
        raise UsageError(f"{flag}: '{_text(value)}' is not a whole number; valid range {range_text}")
    if v < lo or v > hi:
        raise UsageError(f"{flag}: {shown} is outside the valid range {range_text}")
    return int(v)


# ---- the cluster ----------------------------------------------------------------------------------

# What one worker of the local cluster costs, measured (docs/batch.md, "Memory"): a worker process is 62 MB
# resident once Dask is up and 184 MB once hydrolux and OpenImageIO are imported and a frame rendered, and
# its nanny adds its own; 32 workers took 6.1 GB for 64 small frames (issue 23), ~190 MB each. A task adds
# its frame's buffers (the caller's task_bytes).
WORKER_BYTES = 200 << 20


def native(name: str):
    """hydrolux's compiled module ``name`` (_core, _image, _video) itself: imported by its full name, so that
    a package attribute of the same name (a helper function of hydrolux/__init__.py) cannot stand in for it."""
    import importlib

    full = "hydrolux." + name
    if full in sys.modules:
        return sys.modules[full]
    pkg = importlib.import_module("hydrolux")
    missing = object()
    before = pkg.__dict__.get(name, missing)
    module = importlib.import_module(full)
    if before is not missing and before is not module:
        setattr(pkg, name, before)  # the import bound the module over the package's own name: put it back
    return module


def usable_cores() -> int:
    """The cores this process may run on (its affinity mask, which a container or taskset narrows)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def available_memory() -> Optional[int]:
    """Bytes of memory a new process may still take: the library's available_memory_bytes (MemAvailable,
    less where a cgroup v2 limit or ulimit -v leaves less)."""
    return int(native("_core").available_memory_bytes())


def _gib(n: int) -> str:
    return f"{n / (1 << 30):.1f} GiB" if n >= 1 << 30 else f"{n / (1 << 20):.0f} MiB"


def local_cluster_size(workers, threads_per_worker, task_bytes: int = 0, scheduler: Optional[str] = None):
    """--workers and --threads-per-worker checked (the CLI's parsing and message shape) and bounded for a
    local cluster, before any cluster starts: at most one task per core at a time (each task's render is
    parallel already, so more only adds memory), and workers x (WORKER_BYTES + threads x task_bytes) within
    the memory available. ``workers`` None: as many as that allows. Returns (workers, threads_per_worker)."""
    tpw = integer_flag("--threads-per-worker", 1 if threads_per_worker is None else threads_per_worker, 1, 256)
    if scheduler:
        if workers is not None or threads_per_worker is not None:
            flag = "--workers" if workers is not None else "--threads-per-worker"
            raise UsageError(f"{flag}: sizes the local cluster; with --scheduler the cluster's own workers run the "
                             "tasks (dask worker --nworkers, --nthreads)")
        return 0, 1
    cores = usable_cores()
    memory = available_memory()
    per_worker = WORKER_BYTES + tpw * max(0, task_bytes)
    by_memory = memory // per_worker if memory is not None else None
    if by_memory == 0 and not scheduler:
        raise UsageError(f"--workers: even one worker running {tpw} task(s) at a time needs about {_gib(per_worker)} "
                         f"for frames of this size, and {_gib(memory)} of memory is available")
    if tpw > cores:
        raise UsageError(f"--threads-per-worker: {threads_per_worker} is outside the valid range "
                         f"[1, {cores}] here (a local cluster runs at most one task per core: {cores} cores)")
    by_cores = cores // tpw
    bound = min(by_cores, by_memory) if by_memory is not None else by_cores
    why = (f" here (at most one task per core: {cores} cores / {tpw} thread(s) per worker"
           + (f"; about {_gib(per_worker)} a worker, {_gib(memory)} of memory available" if memory is not None
              else "") + "; more workers on other machines with --scheduler)")
    if workers is None:
        return bound, tpw
    return integer_flag("--workers", workers, 1, bound, extra=why), tpw


def open_client(scheduler: Optional[str], workers: int, threads_per_worker: int, quiet: bool):
    """A Dask client: on the cluster at ``scheduler`` (tcp://host:8786), or on a LocalCluster of
    ``workers`` processes on 127.0.0.1 (no set-up). Returns (client, cluster or None)."""
    # Dask's own chatter (worker restarts, etc.) only as warnings; the job reports what matters.
    for name in ("distributed", "distributed.nanny", "distributed.scheduler", "distributed.worker"):
        logging.getLogger(name).setLevel(logging.ERROR if quiet else logging.WARNING)
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except Exception as e:  # OSError, TimeoutError; ValueError or TypeError for an address Dask cannot parse
            reason = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            raise UsageError(f"--scheduler {scheduler}: cannot connect: {reason} (expected "
                             "an address like tcp://host:8786 of a running dask scheduler)") from None
        return client, None
    # The scheduler's HTTP server (metrics; the dashboard too where bokeh is installed, which Debian 12
    # does not package) on a free port of 127.0.0.1, never a fixed one two runs would compete for.
    # Dask starts its workers with MALLOC_TRIM_THRESHOLD_ set, which turns off glibc's dynamic mmap
    # threshold: every buffer over 128 KiB (a frame, its PNG) is then mmap'd and page-faulted anew,
    # which made decoding and rendering 1.3-2x slower in a worker than in the CLI (BENCHMARKS.md).
    # Buffers up to 64 MiB (a 1080p float frame is 25 MB) come from the heap again.
    import dask

    # Workers log only warnings and errors (not each start-up step) on the client's terminal.
    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_MMAP_THRESHOLD_": 64 << 20,
                          "distributed.nanny.pre-spawn-environ.DASK_LOGGING__DISTRIBUTED": "warning"}):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=threads_per_worker, processes=True,
                               host="127.0.0.1", dashboard_address="127.0.0.1:0",
                               preload=["hydrolux.batch._worker"])  # Ctrl-C is the client's
    return Client(cluster), cluster


def _quiet_worker_log() -> None:
    """On a worker: only critical messages from here on (its own shutdown's)."""
    for name in ("distributed", "distributed.worker", "distributed.nanny", "distributed.core"):
        logging.getLogger(name).setLevel(logging.CRITICAL)


def close_client(client, cluster) -> None:
    """Closes the client, then the local cluster (its workers stop before this returns). The local
    workers' log is quieted first: a worker whose heartbeat crosses the scheduler's goodbye logs
    "Scheduler was unaware of this worker" as an error on the terminal, after the job has ended."""
    try:
        if cluster is not None:
            try:
                client.run(_quiet_worker_log)
            except Exception:  # a worker already gone: nothing of it to quiet
                pass
        client.close()
    finally:
        if cluster is not None:
            cluster.close()


def dashboard_link(client) -> Optional[str]:
    """The dashboard's address, if the scheduler serves one: without bokeh (Debian 12 has none) its
    /status page only says that bokeh is missing."""
    import urllib.request

    try:
        if "dashboard" not in client.scheduler_info().get("services", {}):
            return None
        link = client.dashboard_link
        with urllib.request.urlopen(link, timeout=2) as r:
            return link if r.status == 200 and b"needs bokeh" not in r.read(4096) else None
    except Exception:
        return None


# ---- progress -------------------------------------------------------------------------------------

class Progress:
    """Tasks done / total with an ETA on stderr: redrawn in place on a terminal (every 0.1 s),
    a line every 5 s in a log."""

    def __init__(self, job: str, total: int, unit: str, quiet: bool):
        self.job, self.total, self.unit, self.quiet = job, total, unit, quiet
        self.tty = sys.stderr.isatty()
        self.start = time.monotonic()
        self.last = 0.0
        self.done = 0
        self.items = 0
        self.printed = False

    def update(self, tasks_done: int, items_done: int, force: bool = False) -> None:
        self.done, self.items = tasks_done, items_done
        if self.quiet:
            return
        now = time.monotonic()
        if not force and now - self.last < (0.1 if self.tty else 5.0):
            return
        self.last = now
        elapsed = now - self.start
        frac = tasks_done / self.total if self.total else 1.0
        eta = f"{elapsed * (1 - frac) / frac:.0f} s" if frac > 0.02 else "--"
        rate = f", {items_done / elapsed:.2f} {self.unit}/s" if elapsed > 0 and items_done else ""
        line = (f"[{self.job}] {tasks_done}/{self.total} tasks ({100 * frac:3.0f}%){rate}  elapsed {elapsed:.1f} s  "
                f"ETA {eta}")
        sys.stderr.write(("\r\033[K" if self.tty else "") + line + ("" if self.tty else "\n"))
        sys.stderr.flush()
        self.printed = True

    def finish(self) -> None:
        if not self.quiet:
            self.update(self.done, self.items, force=True)
            if self.tty and self.printed:
                sys.stderr.write("\n")
                sys.stderr.flush()

    def message(self, text: str) -> None:
        """A line of its own (an error), not overwritten by the next update; one line whatever a name holds."""
        if self.tty and self.printed:
            sys.stderr.write("\r\033[K")
        sys.stderr.write(printable(text) + "\n")
        sys.stderr.flush()
        self.last = 0.0


# ---- the manifest ---------------------------------------------------------------------------------

class Manifest:
    """The journal of finished outputs in ``folder`` (see the module's docstring). Written whole through
    hydrolux's atomic output path when opened; each record is then appended and fsync'd (a journal
    cannot be renamed into place per line: a torn last line is what the next open drops)."""

    def __init__(self, folder: str, job: str, params: Dict[str, Any], label: str = "--output-dir"):
        self.folder, self.job, self.params, self.label = folder, job, params, label
        self.path = os.path.join(folder, MANIFEST)
        self.records: Dict[str, dict] = {}
        self.restarted = False
        self._lock_fd = os.open(os.path.join(folder, LOCK), os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(self._lock_fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(self._lock_fd)
            raise UsageError(f"--output-dir {folder}: another hydrolux.batch run is writing into it") from None
        try:
            header = {"manifest": "hydrolux.batch", "job": job, "params": params}
            old = self._read()
            if old is not None and old[0] == header:
                self.records = old[1]
            else:
                self.restarted = old is not None
            # Written afresh, atomically: the header and the records that still count, one per output
            # (a torn last line of a crashed run is dropped here, not glued to the next record).
            self._rewrite([header] + list(self.records.values()))
            self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        except BaseException:
            os.close(self._lock_fd)
            raise

    def _read(self):
        if not os.path.lexists(self.path):
            return None
        # Checked as every file the batch reads (a regular file, at most MANIFEST_MAX_BYTES): a UsageError
        # naming it otherwise, before any work.
        lines = read_input(self.path, self.label, MANIFEST_MAX_BYTES).split(b"\n")
        try:
            header = json.loads(lines[0])
        except (ValueError, IndexError):
            return ({}, {})
        records = {}
        for line in lines[1:]:
            try:
                r = json.loads(line)
            except ValueError:
                continue  # a torn last line
            if isinstance(r, dict) and isinstance(r.get("output"), str):
                records[r["output"]] = r
        return header, records

    def _rewrite(self, lines: List[dict]) -> None:
        _core = native("_core")  # hydrolux's checked, atomic output path

        try:
            _core.write_file(fs(self.path), "".join(json.dumps(line, sort_keys=True) + "\n" for line in lines).encode(),
                             "manifest")
        except OSError as e:  # hydrolux's message names the path and the OS's reason
            raise RunFailure(str(e)) from None

    def add(self, record: dict) -> None:
        """Appends the record whole and syncs it, or leaves the journal as it was and raises RunFailure (a full
        disk, a file-size limit, an I/O error): what was written of the line is truncated away, so a failed
        append never leaves a torn line behind."""
        line = (json.dumps(record, sort_keys=True) + "\n").encode()
        length = None
        try:
            length = os.fstat(self._fd).st_size
            view = memoryview(line)
            while view:
                n = os.write(self._fd, view)
                if n <= 0:
                    raise OSError(28, os.strerror(28))  # ENOSPC: a write that writes nothing
                view = view[n:]
            os.fsync(self._fd)
        except OSError as e:
            if length is not None:
                try:
                    os.ftruncate(self._fd, length)
                    os.fsync(self._fd)
                except OSError:
                    pass
            raise RunFailure(os_error_text(e, self.path)) from None
        self.records[record["output"]] = record

    def close(self) -> None:
        os.close(self._fd)
        os.close(self._lock_fd)


def check_members(inputs: List[tuple], outputs: List[tuple]) -> None:
    """"Never over an input, never two outputs on one path", member by member, before any work, by the
    library's own io::FileSet, as the CLI checks its files: ``inputs`` and ``outputs`` are (flag, path). An
    input must be a regular file; an output must not be (through a symbolic or hard link, or as the same
    resolved path) an input or another output, nor a folder or a device. A UsageError naming both
    otherwise. The folder-level guards (an output folder that is the input folder) come first."""
    try:
        native("_core").check_files([(f, fs(p)) for f, p in inputs], [(f, fs(p)) for f, p in outputs])
    except OSError as e:
        raise UsageError(str(e)) from None


def make_folder(flag: str, folder: str) -> None:
    """Creates an output folder (and its parents): one that cannot be made (read-only, not a folder) is a bad
    argument, as the CLI's reservation of an output finds it (exit 2), not a traceback."""
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        raise UsageError(f"{flag} {folder}: cannot create the folder: {e.strerror or e}") from None


def remove_staging(folder: str, pattern: str) -> None:
    """Removes a staging folder after a failed run: the files this job writes there (names matching
    ``pattern``, of any run's chunking; the manifest, its lock; their temporaries), then the folder if that
    left it empty. Nothing else is touched, even if the folder is a link to one that holds other files."""
    ours = re.compile(r"^(?:\.)?(?:" + pattern + "|" + re.escape(MANIFEST) + "|" + re.escape(LOCK) +
                      r")(?:\.tmp-\d+-\d+)?$")
    try:
        entries = os.listdir(folder)
    except OSError:
        return
    for n in entries:
        if ours.match(n):
            try:
                os.unlink(os.path.join(folder, n))
            except OSError:
                pass
    try:
        os.rmdir(folder)
    except OSError:
        pass


def file_digest(path: str) -> Optional[dict]:
    """{"size", "sha256"} of the regular file ``path`` (its content's SHA-256 in hex), or None where it is
    missing, not a regular file (opened without blocking: a FIFO cannot stall it) or cannot be read."""
    import hashlib

    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | os.O_NOCTTY)
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        h = hashlib.sha256()
        size = 0
        while True:
            block = os.read(fd, 1 << 20)
            if not block:
                break
            h.update(block)
            size += len(block)
        return {"size": size, "sha256": h.hexdigest()}
    except OSError:
        return None
    finally:
        os.close(fd)


def file_stamp(path: str) -> Optional[dict]:
    try:
        st = os.stat(path)
    except OSError:
        return None
    return {"size": st.st_size, "mtime_ns": st.st_mtime_ns}


def remove_stale_temporaries(folder: str, names: Iterable[str]) -> int:
    """Removes the temporary files hydrolux's safe output path leaves when a writer is killed
    outright (``.<name>.tmp-<pid>-<n>`` beside ``<name>``): called once no task of the run is left,
    under the manifest's lock, so no live writer of this job owns one. Returns how many."""
    wanted = set(names)
    pattern = re.compile(r"^\.(.+)\.tmp-\d+-\d+$")
    removed = 0
    try:
        entries = os.listdir(folder)
    except OSError:
        return 0
    for e in entries:
        m = pattern.match(e)
        if m and m.group(1) in wanted:
            try:
                os.unlink(os.path.join(folder, e))
                removed += 1
            except OSError:
                pass
    return removed


def run_tasks(client, tasks: List[tuple], fn: Callable, on_result: Callable[[tuple, Any], None], progress: Progress,
              count: Callable[[Any], int], after_result: Optional[Callable[[int, Any], None]] = None) -> None:
    """Submits fn(*task) for each task and hands (task, result) to ``on_result`` as each arrives. A
    task whose worker dies is rerun elsewhere by Dask (up to its allowed failures); one that still
    fails (its own error, or workers lost once too often: KilledWorker) comes as the exception."""
    from distributed import as_completed

    token = uuid.uuid4().hex[:8]
    futures = {client.submit(fn, *t, pure=False, key=f"{fn.__name__}-{token}-{i}"): t for i, t in enumerate(tasks)}
    done = items = 0
    for fut in as_completed(list(futures)):
        try:
            result = fut.result()
        except Exception as e:
            result = e
        on_result(futures[fut], result)
        done += 1
        items += count(result)
        progress.update(done, items)
        if after_result:
            after_result(done, client)
        fut.release()
