"""Loaded into each worker of hydrolux.batch's local cluster (Dask's preload): the workers leave
Ctrl-C to the client, which stops the run and closes the cluster, instead of each printing a
traceback when the terminal's SIGINT reaches their process group. A handler that does nothing, not
SIG_IGN: an ignored signal stays ignored across exec, and the `hydrolux lee` a lee-atlas task runs
must still stop on Ctrl-C (it removes its pending files and exits 130)."""
import signal


def _ignore(signum, frame):
    pass


def dask_setup(worker):  # Dask's preload entry point
    signal.signal(signal.SIGINT, _ignore)
