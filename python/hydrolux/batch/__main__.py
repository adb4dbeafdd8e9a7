"""python3 -m hydrolux.batch {rain,lee-atlas} ...: hydrolux's batch jobs on Dask distributed."""
from __future__ import annotations

import argparse
import os
import sys

from . import lee_atlas, rain
from ._common import UsageError


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit code 2, as the CLI
        sys.stderr.write(f"{self.prog}: {message}\n")
        sys.exit(2)


def main(argv=None) -> int:
    p = _Parser(prog="python3 -m hydrolux.batch",
                description="hydrolux's batch jobs on Dask distributed: a LocalCluster on this machine by default, "
                            "or an existing cluster with --scheduler. Outputs are written atomically and recorded "
                            "in hydrolux-manifest.jsonl in the output folder; a re-run skips what is done.")
    sub = p.add_subparsers(dest="job", required=True, parser_class=_Parser)
    jobs = {"rain": (rain, "Rain over a folder of frames (hydrolux rain --input-dir), in chunks of one rain field"),
            "lee-atlas": (lee_atlas, "An atlas of Lee tables (hydrolux lee) from a JSON spec")}
    for name, (module, text) in jobs.items():
        s = sub.add_parser(name, help=text, description=(module.__doc__ or text).strip(),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        module.add_arguments(s)
        s.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                       help="Worker processes of the local cluster [this machine's cores]")
        s.add_argument("--threads-per-worker", type=int, default=1, help="Tasks each worker runs at once [1]")
        s.add_argument("--scheduler", help="Use the Dask cluster at this address (tcp://host:8786) instead of a "
                                           "local one; its workers need hydrolux importable and the folders mounted")
        s.add_argument("-q", "--quiet", action="store_true", help="No progress or summary on stderr")
    a = p.parse_args(argv)
    try:
        if not 1 <= a.workers <= 1024:
            raise UsageError(f"--workers {a.workers}: outside [1, 1024]")
        if not 1 <= a.threads_per_worker <= 256:
            raise UsageError(f"--threads-per-worker {a.threads_per_worker}: outside [1, 256]")
        return jobs[a.job][0].run(a)
    except UsageError as e:
        sys.stderr.write(f"hydrolux.batch {a.job}: {e}\n")
        return 2
    except KeyboardInterrupt:
        sys.stderr.write(f"\nhydrolux.batch {a.job}: interrupted; finished outputs are in the manifest, a re-run "
                         "goes on from there\n")
        return 130


if __name__ == "__main__":
    sys.exit(main())
