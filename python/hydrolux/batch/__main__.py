"""python3 -m hydrolux.batch {rain,fog,lens-drops,lee-atlas} ...: hydrolux's batch jobs on Dask distributed."""
from __future__ import annotations

import argparse
import sys

from . import fog, lee_atlas, lens_drops, rain
from ._common import WORKER_BYTES, RunFailure, UsageError, printable, usable_cores


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit code 2, as the CLI
        sys.stderr.write(f"{self.prog}: {message}\n")
        sys.exit(2)


def main(argv=None) -> int:
    """``python3 -m hydrolux.batch`` with the arguments ``argv`` (None: the command line's): the job's
    exit code, 0 when done, 2 for a bad argument or input (one line on stderr, before any work), 1 for
    a failure midway, 130 for Ctrl-C.

    Example:

    >>> from hydrolux.batch.__main__ import main
    >>> main(["rain", "--input-dir", "no-such-folder", "--output-dir", "rainy", "-q"])   # says why on stderr
    2
    """
    p = _Parser(prog="python3 -m hydrolux.batch",
                description="hydrolux's batch jobs on Dask distributed: a LocalCluster on this machine by default, "
                            "or an existing cluster with --scheduler. Outputs are written atomically and recorded "
                            "in hydrolux-manifest.jsonl in the output folder; a re-run skips what is done.")
    sub = p.add_subparsers(dest="job", required=True, parser_class=_Parser)
    jobs = {"rain": (rain, "Rain over a folder of frames (hydrolux rain --input-dir), in chunks of one rain field"),
            "fog": (fog, "Fog, haze or mist over a folder of frames (hydrolux fog --input-dir), one fog and one sky"),
            "lens-drops": (lens_drops, "Drops on the lens or windshield over a folder of frames (hydrolux lens-drops "
                                       "--input-dir), frame k with the drops of seed + k"),
            "lee-atlas": (lee_atlas, "An atlas of Lee tables (hydrolux lee) from a JSON spec")}
    for name, (module, text) in jobs.items():
        s = sub.add_parser(name, help=text, description=(module.__doc__ or text).strip(),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        module.add_arguments(s)
        cores = usable_cores()
        s.add_argument("--workers", default=None,
                       help=f"Worker processes of the local cluster: at most one task per core at a time, so "
                            f"workers x --threads-per-worker <= the cores ({cores} here), and each worker takes "
                            f"about {WORKER_BYTES >> 20} MB plus its tasks' frames (~210 MB at 1080p), within "
                            f"the memory available; more is refused before any cluster starts [as many as both "
                            f"allow]")
        s.add_argument("--threads-per-worker", default=None,
                       help=f"Tasks each worker of the local cluster runs at once [1] (at most the cores, {cores})")
        s.add_argument("--scheduler", help="Use the Dask cluster at this address (tcp://host:8786) instead of a "
                                           "local one; its workers need hydrolux importable and the folders mounted")
        s.add_argument("-q", "--quiet", action="store_true", help="No progress or summary on stderr")
    a = p.parse_args(argv)
    prog = f"hydrolux.batch {a.job}"
    # Every way out is one line on stderr and an exit code, never a traceback: 2 for a bad argument or input
    # (found before any work), 1 for a failure of the system midway (a full disk: the path and the OS's reason)
    # or an internal error (with the exception's type), 130 for Ctrl-C.
    try:
        return jobs[a.job][0].run(a)
    except UsageError as e:
        _line(f"{prog}: {e}")
        return 2
    except RunFailure as e:
        _line(f"{prog}: {e}")
        return 1
    except KeyboardInterrupt:
        _line(f"\n{prog}: interrupted; finished outputs are in the manifest, a re-run goes on from there")
        return 130
    except OSError as e:
        _line(f"{prog}: {e.filename}: {e.strerror}" if e.filename and e.strerror else f"{prog}: {e}")
        return 1
    except MemoryError:
        _line(f"{prog}: out of memory")
        return 1
    except Exception as e:  # a bug, or a library's surprise: still one line, with what it was
        _line(f"{prog}: internal error: {type(e).__name__}: {e}")
        return 1


def _line(text: str) -> None:
    """One line on stderr (a leading newline ends a progress line first), whatever the text holds."""
    lead = "\n" if text.startswith("\n") else ""
    body = text[len(lead):]
    try:
        body = printable(body)
    except Exception:  # the library itself cannot be loaded: every control and non-ASCII character escaped
        body = body.encode("unicode_escape", "backslashreplace").decode("ascii")
    try:
        sys.stderr.write(lead + body + "\n")
        sys.stderr.flush()
    except OSError:
        pass


if __name__ == "__main__":
    sys.exit(main())
