"""Labelled forms of hydrolux's tables: xarray Datasets with CF attributes.

The library describes each table once (C++ ``core/dataset.hpp``: ``atmos::lee_dataset``,
``scatter::mie_dataset``); ``hydrolux lee -o table.nc`` and ``hydrolux mie -o phase.nc`` write that
description as NetCDF-4, and the ``to_xarray()`` methods build an :class:`xarray.Dataset` from the same
description, so a file opened with ``xarray.open_dataset`` and a table converted in memory hold the
same names, dimensions, units and attributes. xarray is imported on first use (Debian's
python3-xarray).
"""
from __future__ import annotations

from typing import Any, Dict, Optional

import numpy as np

from . import _core


def xarray():
    """The xarray module, or ImportError saying how to get it."""
    try:
        import xarray as xr
    except ImportError as e:  # pragma: no cover - Debian's python3-xarray is a dependency
        raise ImportError("to_xarray() needs xarray (Debian: apt-get install python3-xarray)") from e
    return xr


def history(call: str) -> str:
    """A CF history line for a Python call: "<UTC time> hydrolux <version>: <call>"."""
    return _core.history_line(call)


def call_text(function: str, arguments: Dict[str, Any], defaults: Dict[str, Any]) -> str:
    """``hydrolux.lee(table='corona', size=(4, 8))``: the arguments that differ from their defaults, an
    array shown by its shape and type only (a history line never holds data)."""
    parts = []
    for name, value in arguments.items():
        if name in defaults:
            d = defaults[name]
            try:
                same = d is value or (not isinstance(value, np.ndarray) and type(d) is type(value) and d == value)
            except Exception:  # noqa: BLE001 - a comparison that fails is a difference
                same = False
            if same:
                continue
        if isinstance(value, np.ndarray):
            text = f"<array {value.dtype} of shape {value.shape}>" if value.size > 8 else np.array2string(
                value, separator=", ")
        else:
            text = repr(value)
            if len(text) > 200:
                text = f"<{type(value).__name__}>"
        parts.append(f"{name}={text}")
    return f"hydrolux.{function}({', '.join(parts)})"


def from_description(description: dict, history_text: Optional[str] = None):
    """An :class:`xarray.Dataset` from the bindings' description of a table (dims, variables with their
    dims, values and attributes, global attributes), as xarray itself reads the NetCDF file of the same
    description: variables named by a dimension or by a variable's ``coordinates`` attribute are
    coordinates (and that attribute goes to ``encoding``)."""
    xr = xarray()
    coordinate_names = {name for name, _ in description["dims"]}
    for _name, _dims, _values, attrs in description["variables"]:
        coordinate_names.update(str(attrs.get("coordinates", "")).split())
    coords, data_vars = {}, {}
    for name, dims, values, attrs in description["variables"]:
        attrs = dict(attrs)
        encoding = {}
        if "coordinates" in attrs:
            encoding["coordinates"] = attrs.pop("coordinates")
        var = xr.Variable(dims, values, attrs=attrs, encoding=encoding)
        (coords if name in coordinate_names else data_vars)[name] = var
    attrs = dict(description["attrs"])
    if history_text is not None:
        attrs["history"] = history_text
    return xr.Dataset(data_vars=data_vars, coords=coords, attrs=attrs)


def scalar_dataset(values: Dict[str, tuple], attrs: Dict[str, Any]):
    """A Dataset of named scalars: ``values`` maps a name to (value, units, long_name)."""
    xr = xarray()
    data_vars = {name: xr.Variable((), np.float64(v), attrs={"units": u, "long_name": ln})
                 for name, (v, u, ln) in values.items()}
    return xr.Dataset(data_vars=data_vars, attrs=dict(attrs))
