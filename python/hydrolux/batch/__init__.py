"""Batch jobs on Dask distributed: ``python3 -m hydrolux.batch rain|fog|lens-drops|lee-atlas --help``.

- :mod:`hydrolux.batch.rain`: rain over a folder of frames, in chunks that continue one rain field
- :mod:`hydrolux.batch.fog`: fog over a folder of frames, one fog and one sky colour for the sequence
- :mod:`hydrolux.batch.lens_drops`: drops on the lens over a folder of frames, frame k with seed + k
- :mod:`hydrolux.batch.lee_atlas`: an atlas of Lee tables from a JSON spec

All run on a LocalCluster on this machine by default, or on an existing cluster with
``--scheduler tcp://host:8786``; write each output atomically and keep a manifest so that a re-run
skips what is done. docs/batch.md explains scaling and limits.
"""
