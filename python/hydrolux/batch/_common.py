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
import os
import re
import sys
import time
import uuid
from typing import Any, Callable, Dict, Iterable, List, Optional

MANIFEST = "hydrolux-manifest.jsonl"
LOCK = "hydrolux-manifest.lock"


class UsageError(Exception):
    """A bad argument: printed as one line, exit code 2."""


# ---- the cluster ----------------------------------------------------------------------------------

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
        except OSError as e:
            raise UsageError(f"--scheduler {scheduler}: cannot connect: {e}") from None
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


def close_client(client, cluster) -> None:
    """Closes the client, then the local cluster (its workers stop before this returns)."""
    try:
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
        """A line of its own (an error), not overwritten by the next update."""
        if self.tty and self.printed:
            sys.stderr.write("\r\033[K")
        sys.stderr.write(text + "\n")
        sys.stderr.flush()
        self.last = 0.0


# ---- the manifest ---------------------------------------------------------------------------------

class Manifest:
    """The journal of finished outputs in ``folder`` (see the module's docstring). Written whole through
    hydrolux's atomic output path when opened; each record is then appended and fsync'd (a journal
    cannot be renamed into place per line: a torn last line is what the next open drops)."""

    def __init__(self, folder: str, job: str, params: Dict[str, Any]):
        self.folder, self.job, self.params = folder, job, params
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
        try:
            with open(self.path, "rb") as f:
                lines = f.read().split(b"\n")
        except FileNotFoundError:
            return None
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
            if isinstance(r, dict) and "output" in r:
                records[r["output"]] = r
        return header, records

    def _rewrite(self, lines: List[dict]) -> None:
        from hydrolux import _core  # hydrolux's checked, atomic output path

        _core.write_file(self.path, "".join(json.dumps(line, sort_keys=True) + "\n" for line in lines).encode(),
                         "manifest")

    def add(self, record: dict) -> None:
        line = (json.dumps(record, sort_keys=True) + "\n").encode()
        os.write(self._fd, line)
        os.fsync(self._fd)
        self.records[record["output"]] = record

    def close(self) -> None:
        os.close(self._fd)
        os.close(self._lock_fd)


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
