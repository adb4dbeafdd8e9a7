"""Atmospheric optics tables: Lee diagrams, corona and glory tables (``hydrolux lee``). Their names are
hydrolux's: ``hydrolux.lee``, ``hydrolux.LeeTable``.
"""
from __future__ import annotations

from typing import NamedTuple, Optional, Tuple

import numpy as np

from hydrolux import _core, _xarray
from hydrolux._args import _MEDIUM, _flag, _history, _opt_real, _pair, _real, _text


class LeeTable(NamedTuple):
    """A Lee diagram (``hydrolux lee``): rows are scattering angles, columns drop radii.

    rgb: (rows, columns, 3) float64, gamut-mapped linear RGB in sr^-1 relative to the sun;
    xyz: (rows, columns, 3) float64, CIE XYZ (unmapped); display: (rows, columns, 3) float32, the
    tone-mapped display values in [0, 1] (linear; apply the sRGB curve to show them);
    radius_um: (columns,), angle_deg and cos_angle: (rows,), wavelengths_nm: (K,).
    With ``stokes=True``: q_xyz, (rows, columns, 3) float64, the Stokes Q weighted as xyz, in the
    scattering-plane basis (Q > 0: polarised tangentially to the bow; U = 0 in this basis); dolp,
    (rows, columns) float64, Q_Y / I_Y, the luminance-weighted degree of linear polarisation (0 where
    I_Y = 0). Both None otherwise. info: the theory, colour space, display exposure and white, the
    evaluations, the drops' shape, ``notes`` (what the table cannot resolve at its settings, e.g.
    supernumeraries narrower than its rows, naming the keywords that fix it; empty when nothing),
    ``error`` (the table's estimated error: ``luminance_rms``, and ``q_rms`` with ``stokes``, relative
    root mean squares over the table, None with one wavelength; docs/lee.md), and for
    :meth:`to_xarray` the labelled description (``dataset``, whose arrays are these) and the call's
    ``history`` line.

    Example:

    >>> import hydrolux
    >>> t = hydrolux.lee(table="corona", size=(4, 8), wavelengths=4)
    >>> isinstance(t, hydrolux.LeeTable), t.display.dtype, t.wavelengths_nm
    (True, dtype('float32'), array([430., 530., 630., 730.]))
    >>> print(t.radius_um.round(2), t.angle_deg[[0, -1]])
    [ 1.    3.68 13.57 50.  ] [ 0. 20.]
    """
    rgb: np.ndarray
    xyz: np.ndarray
    display: np.ndarray
    radius_um: np.ndarray
    angle_deg: np.ndarray
    cos_angle: np.ndarray
    wavelengths_nm: np.ndarray
    info: dict
    q_xyz: Optional[np.ndarray] = None
    dolp: Optional[np.ndarray] = None

    def to_xarray(self):
        """The table as an :class:`xarray.Dataset` with CF attributes, the same variables, coordinates,
        units and attributes as ``hydrolux lee -o table.nc`` writes: dimensions scattering_angle (rows),
        radius (columns), wavelength, channel (R, G, B) and xyz_component (X, Y, Z); rgb, xyz and
        display (and q_xyz, dolp with ``stokes=True``); the settings as global attributes, ``history``
        naming the call. Save it with ``.to_netcdf(path)``.

        Example:

        >>> import hydrolux
        >>> ds = hydrolux.lee(table="corona", size=(4, 8), wavelengths=4).to_xarray()
        >>> sorted(ds.sizes.items())
        [('channel', 3), ('radius', 4), ('scattering_angle', 8), ('wavelength', 4), ('xyz_component', 3)]
        >>> ds.rgb.dims, ds.rgb.attrs["units"], ds.radius.attrs["units"], ds.attrs["table"]
        (('scattering_angle', 'radius', 'channel'), 'sr-1', 'um', 'corona')
        >>> print(ds.attrs["history"].split(": ", 1)[1])   # after "<UTC time> hydrolux <version>: "
        hydrolux.lee(table='corona', size=(4, 8), wavelengths=4)
        """
        return _xarray.from_description(self.info["dataset"], self.info["history"])


def _span(value, name):
    """One value, (A, B), or the CLI's text "A:B" / "A", read by the CLI's parsers (the library's
    parse::number and parse::pair): the same text gives the same numbers, and the same text is refused."""
    if value is None:
        return None
    if isinstance(value, str):
        one = _core.parse_number(value)
        if one is not None:
            return (one, one)
        pair = _core.parse_pair(value, ":")
        if pair is None or pair[1] < pair[0]:
            raise ValueError(f"{name} '{_core.printable(value)}': expected A:B (numbers, A <= B) or one value")
        return tuple(pair)
    if isinstance(value, (tuple, list, np.ndarray)) and np.ndim(value) == 1:
        a, b = _pair(value, name, "one value or (A, B)")
        return (_real(a, f"{name}[0]"), _real(b, f"{name}[1]"))
    v = _real(value, name)
    return (v, v)


# The Lee table's declared parameters (the library's one table, src/atmos/lee_params.cpp): lee()'s
# defaults below, their ranges and checks (in _core, as the CLI's flags).
_LEE = {p["name"]: p for p in _core.params("lee")}


def lee(table: str = _LEE["table"]["default"], theory: str = "mie", radius_um=None, angle_deg=None,
        size: Optional[Tuple[int, int]] = None, radius_scale: str = _LEE["radius_scale"]["default"],
        axis: str = _LEE["axis"]["default"],
        sun_disk_deg: float = _LEE["sun_disk_deg"]["default"], limb_darkening: bool = _LEE["limb_darkening"]["default"],
        size_spread: float = _LEE["size_spread"]["default"], wavelengths_nm: Tuple[float, float] = (380.0, 780.0),
        wavelengths: int = 0, temperature_c: Optional[float] = _LEE["temperature_c"]["default"],
        medium: str = "water", sun: str = "astm-g173-direct", color_space: str = "rec709",
        sampling: Optional[float] = _LEE["sampling"]["default"], seed: int = _LEE["seed"]["default"],
        threads: int = _LEE["threads"]["default"], shape: str = "sphere",
        sun_elevation_deg: float = _LEE["sun_elevation_deg"]["default"],
        position_deg: float = _LEE["position_deg"]["default"],
        canting_deg: float = _LEE["canting_deg"]["default"],
        stokes: bool = _LEE["stokes"]["default"]) -> LeeTable:
    """A Lee diagram, corona or glory table, computed spectrally (``hydrolux lee``; docs/lee.md).

    ``table``: "rainbow" (90-180 deg, 5-800 um), "corona" (0-20 deg, 1-50 um) or "glory"
    (160-180 deg, 1-50 um). ``theory``: "mie", "debye:P", "airy" ("airy:3" secondary) or
    "geometric[:P]". ``radius_um``: (A, B) in [0.1, 5000] um or one radius; ``angle_deg``: (A, B) in
    [0, 180]; ``size``: (columns, rows), default (512, 1024), (1, rows) for one radius.
    ``wavelengths``: samples over ``wavelengths_nm`` (0: one every 10 nm / sampling). ``shape``:
    "sphere", "spheroid:Q" (oblate, axis ratio Q = polar / equatorial in [0.77, 1], axis vertical)
    or "beard-chuang" (falling drops, Q from the radius); non-spherical drops need theory "airy" or
    "airy:3" and a rainbow table, and take ``sun_elevation_deg`` [0, 89], ``position_deg`` (the
    bow's position angle around the antisolar point: 0 top, 90 side, 180 bottom) and
    ``canting_deg`` [0, 30] (docs/non-spherical.md); ``info["drop_shape"]`` holds the shape's name
    and, for those, the three angles and ``axis_ratio`` per column. Other arguments as the CLI's
    flags of the same names (``sampling`` None: chosen, 1 and once more at up to 4 where the table's
    estimated error is above 1%; ``info["sampling"]`` says which, with the first pass's estimate).
    ``stokes``: also the Stokes Q (``q_xyz``) and ``dolp`` (docs/lee.md, "Polarisation"). Long: the
    GIL is released and Ctrl-C stops it.

    Example:

    >>> import hydrolux
    >>> t = hydrolux.lee(size=(4, 8), wavelengths=4)   # radii 5-800 um (columns), 90-180 degrees (rows)
    >>> t.rgb.shape, t.radius_um.shape, t.angle_deg.shape, t.info["theory"]
    ((8, 4, 3), (4,), (8,), 'mie')
    >>> bow = hydrolux.lee(theory="airy", radius_um=500, angle_deg=(135, 145), size=(1, 11), wavelengths=8)
    >>> bow.rgb.shape   # one radius: one column
    (11, 1, 3)
    >>> flat = hydrolux.lee(theory="airy", shape="beard-chuang", position_deg=0, radius_um=800,
    ...                     angle_deg=(135, 145), size=(1, 11), wavelengths=8)   # the top of the bow
    >>> flat.info["drop_shape"]["name"], flat.info["drop_shape"]["axis_ratio"].round(3)
    ('beard-chuang', array([0.953]))
    """
    arguments = dict(locals())  # the call as given, for the labelled form's history
    # Each argument's type is checked in the signature's order; the declared ones go to _core by name.
    theory = _text(theory, "theory", "mie, debye:P, airy, airy:3 or geometric[:P]")
    radius_um, angle_deg = _span(radius_um, "radius_um"), _span(angle_deg, "angle_deg")
    options = {"table": table, "radius_scale": radius_scale, "angle_deg": angle_deg, "axis": axis, "size": size,
               "sun_disk_deg": _real(sun_disk_deg, "sun_disk_deg"),
               "limb_darkening": _flag(limb_darkening, "limb_darkening"),
               "size_spread": _real(size_spread, "size_spread")}
    wavelengths_nm = _span(wavelengths_nm, "wavelengths_nm")
    options["temperature_c"] = _opt_real(temperature_c, "temperature_c")
    medium, sun = _text(medium, "medium", _MEDIUM), _text(sun, "sun", "a spectrum name as the CLI's --sun")
    color_space = _text(color_space, "color_space", "an RGB space as the CLI's --color-space")
    options.update(sampling=_opt_real(sampling, "sampling"), seed=seed, threads=threads)
    # The drops' shape and the bow's point: last in the signature, so positional calls keep working.
    shape = _text(shape, "shape", "sphere, spheroid:Q or beard-chuang")
    options.update(sun_elevation_deg=_real(sun_elevation_deg, "sun_elevation_deg"),
                   position_deg=_real(position_deg, "position_deg"), canting_deg=_real(canting_deg, "canting_deg"))
    options["stokes"] = _flag(stokes, "stokes")
    d = _core.lee(theory, radius_um, wavelengths_nm, wavelengths, shape, medium, sun, color_space,
                  options)
    info = {k: d[k] for k in ("theory", "color_space", "exposure", "white", "evaluations", "drop_shape", "dataset",
                              "notes", "error", "sampling")}
    info["history"] = _history(lee, arguments)
    return LeeTable(d["rgb"], d["xyz"], d["display"], d["radius_um"], d["angle_deg"], d["cos_angle"],
                    d["wavelengths_nm"], info, d.get("q_xyz"), d.get("dolp"))
