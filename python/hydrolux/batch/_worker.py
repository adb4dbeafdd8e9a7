"""Loaded into each worker of hydrolux.batch's local cluster (Dask's preload): the workers leave
Ctrl-C to the client, which stops the run and closes the cluster, instead of each printing a
traceback when the terminal's SIGINT reaches their process group."""
import signal


def dask_setup(worker):  # noqa: ARG001 (Dask's preload entry point)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
