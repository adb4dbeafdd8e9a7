"""Scattering by drops: Lorenz-Mie, a size distribution's bulk optics, the phase function by any theory
and drops as a renderer's medium (``hydrolux mie``, ``phase``, ``medium``). Their names are hydrolux's:
``hydrolux.mie``, ``hydrolux.SizeDistribution``.
"""
from __future__ import annotations

import math
import warnings
from typing import Any, NamedTuple, Optional, Tuple, Union

import numpy as np

from hydrolux import _core, _xarray
from hydrolux._args import (_MEDIUM, ArrayLike, _complex, _deprecated_keyword, _describe, _flag, _history,
                            _opt_real, _real, _reals, _text)
from hydrolux._core import __version__


# ---- Mie ------------------------------------------------------------------------------------------

class MieResult(NamedTuple):
    """Lorenz-Mie results per size parameter (Bohren & Huffman conventions).

    qext, qsca, qabs, qback, g: float64 arrays of x's shape; n_terms: int32, the partial waves summed;
    s1, s2: complex128 of shape x.shape + (angles,), or None when no angles were asked for;
    s11, s12, s33, s34: the Mueller matrix elements (Bohren & Huffman eq. 4.77), float64 of S1's
    shape with ``mueller=True``, else None; info: the call's ``m``, ``x``, ``angles_deg`` and its
    ``history`` line, for :meth:`to_xarray`.

    Example:

    >>> import hydrolux
    >>> r = hydrolux.mie(1.333, [1.0, 10.0], angles_deg=[0, 90, 180])
    >>> isinstance(r, hydrolux.MieResult), r.s1.shape, r.s1.dtype
    (True, (2, 3), dtype('complex128'))
    >>> qext, qsca, qabs, qback, g, *_ = r   # a named tuple: by name or in order
    >>> print(qext.round(4), g.round(4))
    [0.0957 2.1577] [0.1847 0.7059]
    """
    qext: np.ndarray
    qsca: np.ndarray
    qabs: np.ndarray
    qback: np.ndarray
    g: np.ndarray
    n_terms: np.ndarray
    s1: Optional[np.ndarray]
    s2: Optional[np.ndarray]
    s11: Optional[np.ndarray] = None
    s12: Optional[np.ndarray] = None
    s33: Optional[np.ndarray] = None
    s34: Optional[np.ndarray] = None
    info: Optional[dict] = None

    def to_xarray(self):
        """The results as an :class:`xarray.Dataset` with CF attributes, as ``hydrolux mie -o phase.nc``
        writes them: dimensions size_parameter (x, 0-D or 1-D) and scattering_angle; qext, qsca,
        qabs, qback, g, n_terms; s1_real, s1_imag, s2_real, s2_imag (and s11, s12, s33, s34); the
        phase function normalised to 1 over the sphere (sr^-1); ``m`` as attributes m_real and
        m_imag; ``history`` naming the call. ValueError for an x of more than one dimension.

        Example:

        >>> import hydrolux
        >>> ds = hydrolux.mie(1.333, [10.0, 20.0], angles_deg="0:180:7").to_xarray()
        >>> sorted(ds.sizes.items()), ds.phase_function.attrs["units"], ds.attrs["Conventions"]
        ([('scattering_angle', 7), ('size_parameter', 2)], 'sr-1', 'CF-1.8')
        >>> print(ds.qext.sel(size_parameter=20.0).values.round(4))
        2.0999
        """
        info = self.info or {}
        if "m" not in info:
            raise ValueError("to_xarray: this MieResult was not made by hydrolux.mie (it has no info)")
        fields = {k: v for k, v in self._asdict().items() if k != "info"}
        d = _core.mie_dataset(info["m"], info["x"], fields, info["angles_deg"], info["history"])
        return _xarray.from_description(d)


_DEFAULT_ANGLES = "0:180:181"
# Mie's declared defaults (scatter/params.hpp): the same as hydrolux mie's flags.
_MIE = {p["name"]: p["default"] for p in _core.params("mie")}


def mie(m: complex, x: ArrayLike, angles_deg: Union[ArrayLike, str, None] = _DEFAULT_ANGLES,
        threads: int = _MIE["threads"], mueller: bool = False) -> MieResult:
    """Lorenz-Mie scattering by homogeneous spheres (``hydrolux mie``), vectorised over sizes.

    ``m``: relative complex index n + ik (k >= 0 absorbs; n, k up to 1000, ``|m| >= 1e-3``), e.g.
    ``1.333 + 1e-8j``. ``x``: size parameters 2 pi r / lambda in [1e-6, 1e6], any shape.
    ``angles_deg``: scattering angles in [0, 180] degrees (0 = forward) for S1 and S2: an array, or
    ``"A:B:N"`` for N angles from A to B; the default is the CLI's 0:180:181. ``None`` computes the
    efficiencies alone (the fast path for size sweeps, ``--no-angles``). ``threads``: 0 = all cores.
    ``mueller``: also the Mueller matrix elements ``S11 = (|S2|^2 + |S1|^2)/2``, ``S12 = (|S2|^2 - |S1|^2)/2``,
    S33 = Re(S2 S1*), S34 = Im(S2 S1*) (Bohren & Huffman eq. 4.77, ``--mueller``); POL = -S12/S11.

    Example:

    >>> import hydrolux
    >>> import numpy as np
    >>> r = hydrolux.mie(1.333 + 1e-8j, [1.0, 10.0, 100.0])
    >>> print(r.qext.round(4), r.n_terms, r.s1.shape)   # S1, S2 at 0:180:181 degrees
    [0.0957 2.1577 2.12  ] [ 10  27 134] (3, 181)
    >>> sweep = hydrolux.mie(1.333, np.linspace(1, 1000, 1000), angles_deg=None)   # efficiencies only
    >>> print(sweep.qext.shape, sweep.qext[-1].round(3), sweep.s1)
    (1000,) 2.023 None
    >>> print(hydrolux.mie(1.333, 10.0, angles_deg="0:180:3").s1.shape)   # the CLI's A:B:N
    (3,)
    >>> p = hydrolux.mie(1.5, 1e-3, angles_deg=[0, 90, 180], mueller=True)   # Rayleigh's limit
    >>> print((p.s12 / p.s11).round(6), (p.s33 / p.s11).round(6))   # -sin^2/(1+cos^2), 2cos/(1+cos^2)
    [ 0. -1.  0.] [ 1.  0. -1.]
    """
    arguments = dict(m=m, x=x, angles_deg=angles_deg, threads=threads, mueller=mueller)
    m = _complex(m, "m")
    x_arr = _reals(x, "x")
    angles = None
    if angles_deg is not None:
        if isinstance(angles_deg, str):
            angles = _core.parse_angles(angles_deg)  # the CLI's parser: the CLI's angles, bit for bit
        else:
            angles = np.atleast_1d(_reals(angles_deg, "angles_deg"))
    if not isinstance(mueller, (bool, np.bool_)):
        raise TypeError(f"mueller: expected True or False, got {_describe(mueller)}")
    d = _core.mie(m, x_arr, angles, threads, bool(mueller))
    info = {"m": m, "x": np.array(x_arr, dtype=np.float64), "angles_deg": angles,
            "history": _history(mie, arguments)}
    return MieResult(d["qext"], d["qsca"], d["qabs"], d["qback"], d["g"], d["n_terms"], d.get("s1"), d.get("s2"),
                     d.get("s11"), d.get("s12"), d.get("s33"), d.get("s34"), info)


def mie_terms(x: float) -> int:
    """The number of partial waves hydrolux sums for size parameter x: max(4, x + 7 x^(1/3) + 2).

    Example:

    >>> import hydrolux
    >>> hydrolux.mie_terms(1.0), hydrolux.mie_terms(100.0)
    (10, 134)
    """
    return _core.mie_terms(_real(x, "x"))


def sphere(radius_um: ArrayLike, wavelength_nm: float, medium: str = "water", surrounding: str = "air",
           temperature_c: Optional[float] = None) -> Tuple[complex, np.ndarray]:
    """The relative index m and size parameters x of spheres of ``radius_um`` (micrometres) of
    ``medium`` in ``surrounding`` at vacuum wavelength ``wavelength_nm`` (``hydrolux mie --radius-um``).
    Returns (m, x) with x of the shape of ``radius_um``.

    Example:

    >>> import hydrolux
    >>> m, x = hydrolux.sphere([1.0, 10.0], 550)   # water drops of 1 and 10 um in air, green light
    >>> print(round(m.real, 4), x.round(2))
    1.3343 [ 11.43 114.27]
    >>> print(hydrolux.mie(m, x, angles_deg=None).qext.round(3))
    [1.828 2.043]
    """
    return _core.sphere_problem(_reals(radius_um, "radius_um"), _real(wavelength_nm, "wavelength_nm"),
                                _text(medium, "medium", _MEDIUM), _text(surrounding, "surrounding", _MEDIUM),
                                _opt_real(temperature_c, "temperature_c"))


def bulk_optics(m: complex, wavelength_nm: float, distribution: "SizeDistribution", nodes: int = 64,
                medium_index: float = 1.0, threads: int = 0) -> "BulkOptics":
    """Extinction, scattering, absorption and backscatter coefficients (m^-1) and the asymmetry
    parameter g of a population of spheres of index ``m`` (relative to the surrounding medium of
    real index ``medium_index``) at vacuum ``wavelength_nm``, by ``nodes``-point quadrature of the
    distribution (``scatter::mie_bulk_optics``).

    Example:

    >>> import hydrolux
    >>> fog = hydrolux.SizeDistribution.gamma(10e-6, 0.2, number_per_m3=1e8)   # 100 drops per cm^3
    >>> b = hydrolux.bulk_optics(1.333, 550, fog, nodes=32)
    >>> print(round(b["extinction_per_m"], 4), round(b["g"], 3))
    0.068 0.867
    >>> print(f"visibility {3.912 / b['extinction_per_m']:.0f} m")   # Koschmieder
    visibility 58 m
    """
    m = _complex(m, "m")
    wavelength_nm = _real(wavelength_nm, "wavelength_nm")
    medium_index = _real(medium_index, "medium_index")
    if not isinstance(distribution, SizeDistribution):
        raise TypeError(f"distribution: expected a hydrolux.SizeDistribution, got {_describe(distribution)}")
    if not (wavelength_nm > 0 and math.isfinite(wavelength_nm)):
        raise ValueError(f"wavelength_nm = {wavelength_nm} must be a positive number of nanometres")
    if not (1e-3 <= medium_index <= 1e3):
        raise ValueError(f"medium_index = {medium_index} is outside [0.001, 1000]")
    r, w = distribution.quadrature(nodes)
    k = 2 * math.pi * medium_index / (wavelength_nm * 1e-9)
    result = BulkOptics(_core.bulk_optics(m, k, r, w, threads))
    result.setup = {"m": m, "wavelength_nm": wavelength_nm, "distribution": distribution, "nodes": nodes,
                    "medium_index": medium_index,
                    "history": _history(bulk_optics, dict(m=m, wavelength_nm=wavelength_nm,
                                                            distribution=distribution, nodes=nodes,
                                                            medium_index=medium_index, threads=threads))}
    return result


class BulkOptics(dict):
    """What :func:`bulk_optics` returns: a dict of ``extinction_per_m``, ``scattering_per_m``,
    ``absorption_per_m``, ``backscatter_per_m`` (m^-1) and ``g``, with :meth:`to_xarray`.

    Example:

    >>> import hydrolux
    >>> b = hydrolux.bulk_optics(1.333, 550, hydrolux.SizeDistribution.monodisperse(1e-3, 1000), nodes=1)
    >>> isinstance(b, dict), sorted(b)
    (True, ['absorption_per_m', 'backscatter_per_m', 'extinction_per_m', 'g', 'scattering_per_m'])
    """

    def to_xarray(self):
        """The coefficients as an :class:`xarray.Dataset` of scalars with units and long names, the
        drops and the light as attributes, ``history`` naming the call.

        Example:

        >>> import hydrolux
        >>> fog = hydrolux.SizeDistribution.gamma(10e-6, 0.2, number_per_m3=1e8)
        >>> ds = hydrolux.bulk_optics(1.333, 550, fog, nodes=32).to_xarray()
        >>> ds.extinction_coefficient.attrs["units"], round(float(ds.extinction_coefficient), 4)
        ('m-1', 0.068)
        """
        s = getattr(self, "setup", None)
        if s is None:
            raise ValueError("to_xarray: this BulkOptics was not made by hydrolux.bulk_optics (it has no setup)")
        d = s["distribution"]
        m = complex(s["m"])
        values = {"extinction_coefficient": (self["extinction_per_m"], "m-1", "volume extinction coefficient"),
                  "scattering_coefficient": (self["scattering_per_m"], "m-1", "volume scattering coefficient"),
                  "absorption_coefficient": (self["absorption_per_m"], "m-1", "volume absorption coefficient"),
                  "backscatter_coefficient": (self["backscatter_per_m"], "m-1",
                                              "volume backscattering coefficient (Bohren & Huffman's Q_back)"),
                  "asymmetry_parameter": (self["g"], "1", "asymmetry parameter <cos theta>, weighted by C_sca"),
                  "single_scattering_albedo": (self["scattering_per_m"] / self["extinction_per_m"]
                                               if self["extinction_per_m"] > 0 else float("nan"), "1",
                                               "single-scattering albedo")}
        attrs = {"Conventions": "CF-1.8", "title": "hydrolux bulk optics of a drop population",
                 "source": f"hydrolux {__version__}", "history": s.get("history", ""),
                 "wavelength_nm": s["wavelength_nm"], "m_real": m.real, "m_imag": m.imag,
                 "medium_index": s["medium_index"], "quadrature_nodes": s["nodes"],
                 "size_distribution": d.kind, "number_concentration_per_m3": d.number_concentration,
                 "mean_radius_m": d.mean_radius, "effective_radius_m": d.effective_radius}
        return _xarray.scalar_dataset(values, attrs)


# ---- the phase function ---------------------------------------------------------------------------

class PhaseResult(NamedTuple):
    """A phase function against scattering angle (``hydrolux phase``), averaged over the drops.

    angles_deg: the scattering angles (0 = forward); phase: (i1 + i2) / 2, the CLI's column ``i``
    (= S11); ``i1 = <|S1|^2>`` (perpendicular), ``i2 = <|S2|^2>`` (parallel): number-weighted means over the
    drops, float64 arrays of the angles' length, in Bohren & Huffman's normalisation (i / k^2 is the
    intensity per drop per unit incident irradiance at unit distance). info: a dict of what the CLI's
    header states: ``theory`` ("mie", "debye:2", ...), ``drops`` (the distribution in words),
    ``wavelength_nm``, ``m`` (relative index), ``x`` (the size parameter, for one radius; else None),
    ``radii``, ``radius_um`` and ``weight`` (the quadrature averaged over), ``notes`` (where the
    theory is out of its depth, or where too few radii sample the Mie ripple: docs/mie.md, "Size
    averages") and ``history`` (the call, for :meth:`to_xarray`). With ``mueller=True``: s11, s12,
    s33, s34, the size-averaged Mueller elements (Bohren & Huffman eq. 4.77), and pol = -S12/S11, the
    degree of linear polarisation (NaN where S11 = 0, with a RuntimeWarning naming how many angles);
    else None.

    Example:

    >>> import hydrolux
    >>> p = hydrolux.phase(10, 550, angles_deg=[0, 90, 180], mueller=True)
    >>> isinstance(p, hydrolux.PhaseResult), p.phase.shape, p.info["theory"], round(p.info["x"], 2)
    (True, (3,), 'mie', 114.27)
    >>> angles, intensity, i1, i2, info, *mueller = p   # a named tuple: by name or in order
    >>> bool((p.s11 == p.phase).all()), round(float(p.pol[1]), 4)   # S11 is the phase function
    (True, -0.1892)
    """
    angles_deg: np.ndarray
    phase: np.ndarray
    i1: np.ndarray
    i2: np.ndarray
    info: dict
    s11: Optional[np.ndarray] = None
    s12: Optional[np.ndarray] = None
    s33: Optional[np.ndarray] = None
    s34: Optional[np.ndarray] = None
    pol: Optional[np.ndarray] = None

    def to_xarray(self):
        """The phase function as an :class:`xarray.Dataset` with CF attributes: dimension
        scattering_angle (degree); phase, i1, i2 (and s11, s12, s33, s34, pol); the radii and weights
        averaged over on a dimension quadrature_node; the theory, the drops, the wavelength and the
        index as attributes, ``history`` naming the call; for a size average that chose its radii, each
        element's ``estimated_error`` (``phase`` takes S11's) and the tolerance, the last halving's change
        and the shifted grid's difference as attributes.

        Example:

        >>> import hydrolux
        >>> ds = hydrolux.phase(10, 550, angles_deg="0:180:5").to_xarray()
        >>> ds.phase.dims, ds.scattering_angle.attrs["units"], ds.attrs["theory"]
        (('scattering_angle',), 'degree', 'mie')
        """
        xr = _xarray.xarray()
        angle = ("scattering_angle",)
        norm = ("Bohren & Huffman's normalisation: i / k^2 is the intensity scattered per drop per unit incident "
                "irradiance at unit distance; number-weighted mean over the drops")
        data = {"phase": (self.phase, "(i1 + i2) / 2 = <(|S1|^2 + |S2|^2) / 2>, the phase function (= S11); " + norm),
                "i1": (self.i1, "<|S1|^2>, perpendicular to the scattering plane; " + norm),
                "i2": (self.i2, "<|S2|^2>, parallel to the scattering plane; " + norm)}
        if self.s11 is not None:
            data.update(s11=(self.s11, "Mueller element S11, size-averaged (Bohren & Huffman eq. 4.77)"),
                        s12=(self.s12, "Mueller element S12, size-averaged"),
                        s33=(self.s33, "Mueller element S33, size-averaged"),
                        s34=(self.s34, "Mueller element S34, size-averaged"),
                        pol=(self.pol, "degree of linear polarisation -S12 / S11"))
        data_vars = {k: xr.Variable(angle, v, attrs={"units": "1", "long_name": ln}) for k, (v, ln) in data.items()}
        # A size average that chose its radii states each element's estimated error (at its worst angle,
        # relative to S11 there) on the element, and the phase function takes S11's.
        error = self.info.get("error")
        if error is not None:
            for name in ("s11", "s12", "s33", "s34"):
                if name in data_vars:
                    data_vars[name].attrs["estimated_error"] = float(error[name])
            data_vars["phase"].attrs["estimated_error"] = float(error["s11"])
        node = ("quadrature_node",)
        data_vars["quadrature_weight"] = xr.Variable(node, np.asarray(self.info["weight"]), attrs={
            "units": "1", "long_name": "weight of each radius in the number-weighted mean"})
        coords = {"scattering_angle": xr.Variable(angle, self.angles_deg, attrs={
                      "units": "degree", "long_name": "scattering angle (0 forward)"}),
                  "quadrature_radius": xr.Variable(node, np.asarray(self.info["radius_um"]), attrs={
                      "units": "um", "long_name": "drop radii averaged over"})}
        info, m = self.info, complex(self.info["m"])
        attrs = {"Conventions": "CF-1.8", "title": "hydrolux phase function", "source": f"hydrolux {__version__}",
                 "history": info.get("history", ""),
                 "references": "Bohren, C. F. and Huffman, D. R. (1983): Absorption and Scattering of Light by "
                               "Small Particles, Wiley",
                 "theory": info["theory"], "drops": info["drops"], "wavelength_nm": float(info["wavelength_nm"]),
                 "m_real": m.real, "m_imag": m.imag}
        if info.get("x") is not None:
            attrs["size_parameter"] = float(info["x"])
        if error is not None:
            attrs["size_average_tolerance"] = float(info["tolerance"])
            attrs["size_average_last_change"] = float(info["last_change"])
            if info.get("shifted_change") is not None:
                attrs["size_average_shifted_change"] = float(info["shifted_change"])
            attrs["estimated_error_meaning"] = ("each variable's estimated_error: its error at its worst angle, relative "
                                                "to S11 there (docs/mie.md, \"Size averages\")")
        if info.get("notes"):
            attrs["comment"] = "; ".join(info["notes"])
        return xr.Dataset(data_vars=data_vars, coords=coords, attrs=attrs)


# The phase function's declared parameters (scatter/params.hpp): phase()'s defaults, ranges and checks
# (in _core, as the CLI's flags).
_PHASE = {p["name"]: p["default"] for p in _core.params("phase")}


def phase(radius_um: Optional[float], wavelength_nm: float, theory: str = "mie", size_distribution: str = "mono",
          medium: str = "water", surrounding: str = "air", angles_deg: Union[ArrayLike, str] = _DEFAULT_ANGLES,
          nodes: Optional[int] = _PHASE["nodes"], temperature_c: Optional[float] = _PHASE["temperature_c"],
          threads: int = _PHASE["threads"], mueller: bool = _PHASE["mueller"],
          tolerance: Optional[float] = None) -> PhaseResult:
    """The scattered intensity against angle of one drop or a size distribution (``hydrolux phase``):
    the same job, checks and numbers as the CLI, as a :class:`PhaseResult` of arrays.

    ``radius_um``: the drop's radius in micrometres, or the mean radius of a gamma or lognormal
    distribution (ignored, and may be None, for Marshall-Palmer rain). ``wavelength_nm``: in vacuum.
    ``theory``: "mie", "debye:P" (one Debye order: 0 diffraction + reflection, 2 primary rainbow, 3
    secondary), "airy" ("airy:P"; near the rainbow angle only) or "geometric" ("geometric:P").
    ``size_distribution``: "mono", "gamma:W" or "lognormal:W" (relative width W in [0.0001, 1]) or
    "marshall-palmer:H" (H mm/h, radii 50-3000 um), averaged over radii it chooses until the average
    is within ``tolerance`` (None: the CLI's default, 0.005) of the converged one at every angle
    (``info["last_change"]``: how much the last halving of the radii's spacing moved it;
    ``info["shifted_change"]``: for Mie, how far a grid of the last spacing shifted by 0.618 of it
    differs, a check on the halvings, whose grids share their radii; ``info["error"]``: the estimated
    error of each Mueller element at its worst angle, relative to S11 there, a dict of s11, s12, s33,
    s34), or over a fixed count of ``nodes`` radii instead.
    ``medium``, ``surrounding``: names as :func:`media` (or "const:1.49"). ``angles_deg``: scattering
    angles in [0, 180] degrees (0 = forward), an array or the CLI's text "A:B:N" or "0,10,90" (read
    by the CLI's parser: the same angles). ``temperature_c``: of the media that model it (water).
    ``threads``: 0 = all cores. ``mueller``: also the size-averaged Mueller elements and pol.
    Declared parameters (``nodes``, ``tolerance``, ``temperature_c``, ``threads``, ``mueller``) take the ranges of
    the CLI's flags of the same names. A bad argument is a ValueError (a TypeError for a wrong type)
    naming it. Long jobs release the GIL and stop on Ctrl-C.

    Example:

    >>> import hydrolux
    >>> p = hydrolux.phase(10, 550, angles_deg="0:180:5")   # one water drop of 10 um, green light
    >>> print(p.angles_deg, f"forward {p.phase[0]:.4e}, side {p.phase[2]:.4f}")
    [  0.  45.  90. 135. 180.] forward 4.4646e+07, side 94.9763
    >>> fog = hydrolux.phase(10, 550, size_distribution="gamma:0.2", nodes=32, angles_deg=[140], mueller=True)
    >>> fog.info["drops"], fog.info["radii"]
    ('gamma distribution, mean radius 10 um, relative width 0.2, 32 radii', 32)
    >>> bool(fog.s11[0] ** 2 > fog.s12[0] ** 2 + fog.s33[0] ** 2 + fog.s34[0] ** 2)   # averaging depolarises
    True
    """
    arguments = dict(locals())  # the call as given, for the labelled form's history
    theory = _text(theory, "theory", "mie, debye:P, airy[:P] or geometric[:P]")
    radius = None if radius_um is None else _real(radius_um, "radius_um")
    wavelength = _real(wavelength_nm, "wavelength_nm")
    size_distribution = _text(size_distribution, "size_distribution", "mono, gamma:W, lognormal:W or marshall-palmer:H")
    medium, surrounding = _text(medium, "medium", _MEDIUM), _text(surrounding, "surrounding", _MEDIUM)
    if not isinstance(angles_deg, str):
        angles_deg = np.atleast_1d(_reals(angles_deg, "angles_deg"))
    options = {"nodes": nodes, "temperature_c": _opt_real(temperature_c, "temperature_c"), "threads": threads,
               "mueller": _flag(mueller, "mueller")}
    if tolerance is not None:  # else the library's default (given with nodes, refused: they replace one another)
        options["tolerance"] = tolerance
    d = _core.phase(theory, radius, wavelength, size_distribution, medium, surrounding, angles_deg, options)
    pol = None
    if "s11" in d:
        with np.errstate(divide="ignore", invalid="ignore"):
            pol = -d["s12"] / d["s11"]
        undefined = int(np.count_nonzero(~np.isfinite(pol)))
        if undefined:  # S11 = 0: no light scattered there, so no degree of polarisation (NaN, not 0)
            warnings.warn(f"pol: NaN at {undefined} of {pol.size} angles, where S11 = 0 (no light is scattered there, "
                          "so -S12/S11 is undefined)", RuntimeWarning, stacklevel=2)
    d["info"]["history"] = _history(phase, arguments)
    return PhaseResult(d["angles_deg"], d["phase"], d["i1"], d["i2"], d["info"], d.get("s11"), d.get("s12"),
                       d.get("s33"), d.get("s34"), pol)


# hydrolux medium's declared parameters (scatter/renderer_export.hpp): renderer_medium()'s defaults.
_RENDERER_MEDIUM = {p["name"]: p["default"] for p in _core.params("medium")}


class RendererMedium(NamedTuple):
    """Drops as a renderer's participating medium (``hydrolux medium``; docs/renderer-export.md).

    text: the file, a Mitsuba 3 XML medium (``tabphase``) or a pbrt-v4 ``MakeNamedMedium`` statement,
    with its comment header; write it with ``open(path, "w").write(result.text)``. wavelength_nm: 360
    to 830 nm every 10 nm; sigma_t_per_m, sigma_s_per_m, sigma_a_per_m, albedo: as exported (after
    any forward cut), m^-1; phase: the table per steradian at cos(theta) uniform from -1 (backward) to
    +1 (forward), normalised (2 pi times its trapezoid integral is 1). info: ``format``, ``drops``,
    ``number_per_m3``, ``lwc_g_m3``, ``scene_unit_m``, the physical ``extinction_per_m`` and
    ``scattering_per_m``, ``phase_wavelength_nm``, ``l1_error`` (of the table, estimated),
    ``target_met``, ``cut_deg``, ``cut_fraction``, ``g``, ``hg_g`` and ``hg_l1_error`` (pbrt-v4's
    Henyey-Greenstein), ``normalisation``, and for a distribution ``spectra_radii`` and
    ``spectra_error`` (a dict of ``extinction`` and ``g``: the spectra's size average's estimated
    relative error at the worst wavelength; None for one radius), ``phase_radii`` (the radii the phase
    averages over; unless ``nodes`` is given, gamma and lognormal drops double them from 64 until the
    phase moves by at most half of ``max_error`` when they are doubled again), ``phase_radii_chosen``
    (so chosen), ``phase_smoothed`` (Marshall-Palmer rain: each radius's intensity averaged over angle
    before the size average, docs/renderer-export.md "Rain") and ``phase_size_l1``: the phase's size
    average's own error estimated, the L1 distance to the same average over twice the radii (for rain,
    outside the forward cut, to the same smoothed average over half the radii; None for one radius).

    Example:

    >>> import hydrolux
    >>> fog = hydrolux.renderer_medium(5, number_per_cm3=100, values=257, forward_cut_deg=0)
    >>> len(fog.phase), fog.info["format"], bool(fog.phase[-1] > fog.phase[0])   # forward is last
    (257, 'mitsuba3', True)
    """
    text: str
    wavelength_nm: np.ndarray
    sigma_t_per_m: np.ndarray
    sigma_s_per_m: np.ndarray
    sigma_a_per_m: np.ndarray
    albedo: np.ndarray
    phase: np.ndarray
    info: dict


def renderer_medium(radius_um: Optional[float], size_distribution: str = "mono",
                    number_per_cm3: Optional[float] = _RENDERER_MEDIUM["number_per_cm3"],
                    lwc_g_m3: Optional[float] = _RENDERER_MEDIUM["lwc_g_m3"],
                    format: str = "mitsuba3", name: str = "hydrolux_medium", medium: str = "water",
                    surrounding: str = "air", nodes: Optional[int] = _RENDERER_MEDIUM["nodes"],
                    temperature_c: Optional[float] = _RENDERER_MEDIUM["temperature_c"],
                    phase_wavelength_nm: float = _RENDERER_MEDIUM["phase_wavelength_nm"],
                    values: Optional[int] = None, max_error: float = _RENDERER_MEDIUM["max_error"],
                    forward_cut_deg: Optional[float] = None,
                    scene_unit_m: float = _RENDERER_MEDIUM["scene_unit_m"],
                    threads: int = _RENDERER_MEDIUM["threads"],
                    spectra_tolerance: Optional[float] = _RENDERER_MEDIUM["spectra_tolerance"]) -> RendererMedium:
    """A population of drops as a renderer's participating medium (``hydrolux medium``): the same job,
    checks and file text as the CLI, as a :class:`RendererMedium`.

    ``radius_um``: the drop's radius, or the mean radius of gamma and lognormal (None for
    Marshall-Palmer rain). ``size_distribution``: "mono", "gamma:W", "lognormal:W" or
    "marshall-palmer:H". ``number_per_cm3`` or ``lwc_g_m3``: the count (one of them; neither for rain,
    whose count follows from its rate). ``format``: "mitsuba3" (homogeneous medium with a tabphase)
    or "pbrt-v4" (homogeneous medium with Henyey-Greenstein, its error stated). ``name``: the medium's
    id. The declared parameters (``nodes``, ``temperature_c``, ``phase_wavelength_nm``, ``values``,
    ``max_error``, ``forward_cut_deg``, ``scene_unit_m``, ``spectra_tolerance``, ``threads``) take the ranges of the CLI's
    flags of the same names. A bad argument is a ValueError (a TypeError for a wrong type) naming it.

    Example:

    >>> import hydrolux
    >>> fog = hydrolux.renderer_medium(10, number_per_cm3=100, values=257, forward_cut_deg=0)
    >>> print(f"{fog.wavelength_nm[19]:g} nm: sigma_t {fog.sigma_t_per_m[19]:.4f} m^-1, "
    ...       f"visibility {3.912 / fog.sigma_t_per_m[19]:.0f} m")
    550 nm: sigma_t 0.0642 m^-1, visibility 61 m
    >>> rain = hydrolux.renderer_medium(None, "marshall-palmer:5", format="pbrt-v4", nodes=16, values=4097)
    >>> print(rain.text.splitlines()[-1], f"cut {rain.info['cut_deg']:.2f} deg")
        "float g" 0.76... cut 1.79 deg
    """
    radius = None if radius_um is None else _real(radius_um, "radius_um")
    size_distribution = _text(size_distribution, "size_distribution", "mono, gamma:W, lognormal:W or marshall-palmer:H")
    medium, surrounding = _text(medium, "medium", _MEDIUM), _text(surrounding, "surrounding", _MEDIUM)
    format = _text(format, "format", "mitsuba3 or pbrt-v4")
    name = _text(name, "name", "1 to 64 of A-Z a-z 0-9 _ . -")
    options = {"number_per_cm3": _opt_real(number_per_cm3, "number_per_cm3"),
               "lwc_g_m3": _opt_real(lwc_g_m3, "lwc_g_m3"), "nodes": nodes,
               "temperature_c": _opt_real(temperature_c, "temperature_c"),
               "phase_wavelength_nm": phase_wavelength_nm, "values": values, "max_error": max_error,
               "forward_cut_deg": _opt_real(forward_cut_deg, "forward_cut_deg"), "scene_unit_m": scene_unit_m,
               "spectra_tolerance": _opt_real(spectra_tolerance, "spectra_tolerance"),
               "threads": threads}
    d = _core.renderer_medium(radius, size_distribution, medium, surrounding, format, name, options)
    return RendererMedium(d["text"], d["wavelength_nm"], d["sigma_t_per_m"], d["sigma_s_per_m"],
                          d["sigma_a_per_m"], d["albedo"], d["phase"], d["info"])


def _remake_distribution(method: str, args: tuple) -> "SizeDistribution":
    """A pickled SizeDistribution made again: the classmethod that made it, with the same arguments."""
    if method not in ("monodisperse", "gamma", "log_normal", "marshall_palmer"):
        raise ValueError(f"SizeDistribution: no classmethod {method!r}")
    return getattr(SizeDistribution, method)(*args)


class SizeDistribution:
    """A distribution of drop radii n(r) (m^-4): monodisperse, gamma, log-normal or Marshall-Palmer.

    Make one with :meth:`monodisperse`, :meth:`gamma`, :meth:`log_normal` or :meth:`marshall_palmer`.
    Radii in metres in (0, 1]; relative widths sigma_r / <r> in [1e-4, 1]; number concentrations
    in (0, 1e30] m^-3; rain rates in [0.01, 500] mm/h.

    Example:

    >>> import hydrolux
    >>> d = hydrolux.SizeDistribution.gamma(10e-6, 0.2, number_per_m3=1e8)
    >>> d
    SizeDistribution.gamma(mean_radius=1e-05 m, N=1e+08 m^-3)
    >>> print(f"{d.effective_radius * 1e6:.2f} um", d.kind)
    10.80 um gamma
    """

    def __init__(self, native: Any, _made_by: Optional[tuple] = None):
        self._d = native
        self._made_by = _made_by  # (classmethod name, its arguments): what pickling rebuilds it from

    def __reduce__(self):
        # Pickled as the call that made it (Dask ships distributions and results holding them between
        # processes): the same arguments give the same distribution, bit for bit.
        if self._made_by is None:
            raise TypeError("cannot pickle a SizeDistribution not made by one of its classmethods")
        method, args = self._made_by
        return (_remake_distribution, (method, args))

    @classmethod
    def monodisperse(cls, radius_m: float, number_per_m3: float = 1.0) -> "SizeDistribution":
        """Every drop of radius ``radius_m``, ``number_per_m3`` of them.

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.monodisperse(1e-3, number_per_m3=100)
        >>> d.kind, d.mean_radius, d.number_concentration
        ('monodisperse', 0.001, 100.0)
        """
        args = (_real(radius_m, "radius_m"), _real(number_per_m3, "number_per_m3"))
        return cls(_core.SizeDistribution.monodisperse(*args), ("monodisperse", args))

    @classmethod
    def gamma(cls, mean_radius_m: float, relative_width: float, number_per_m3: float = 1.0) -> "SizeDistribution":
        """A gamma distribution of mean radius ``mean_radius_m`` and standard deviation
        ``relative_width`` x the mean (clouds and fog).

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.gamma(10e-6, 0.2)
        >>> print(f"{d.mean_radius * 1e6:.1f} um, sigma {d.radius_variance ** 0.5 * 1e6:.1f} um")
        10.0 um, sigma 2.0 um
        """
        args = (_real(mean_radius_m, "mean_radius_m"), _real(relative_width, "relative_width"),
                _real(number_per_m3, "number_per_m3"))
        return cls(_core.SizeDistribution.gamma(*args), ("gamma", args))

    @classmethod
    def log_normal(cls, mean_radius_m: float, relative_width: float,
                   number_per_m3: float = 1.0) -> "SizeDistribution":
        """A log-normal distribution of mean radius ``mean_radius_m`` and standard deviation
        ``relative_width`` x the mean.

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.log_normal(5e-6, 0.3, number_per_m3=1e9)
        >>> print(d.kind, f"{d.mean_radius * 1e6:.1f} um", f"{d.radius_variance ** 0.5 * 1e6:.1f} um")
        log_normal 5.0 um 1.5 um
        """
        args = (_real(mean_radius_m, "mean_radius_m"), _real(relative_width, "relative_width"),
                _real(number_per_m3, "number_per_m3"))
        return cls(_core.SizeDistribution.log_normal(*args), ("log_normal", args))

    @classmethod
    def marshall_palmer(cls, rain_rate_mmh: Optional[float] = None, n0_per_m4: float = 8e6,
                        **deprecated: Any) -> "SizeDistribution":
        """Marshall & Palmer (1948): n(r) = N0' exp(-Lambda r), N0 = 8e6 m^-4 per metre of diameter.

        ``rain_rate_mmh``: the rain rate in [0.01, 500] mm/h, the range every job takes it in (500 the
        rain's and the sky's upper limit). The keyword ``rain_rate_mm_per_h`` of earlier releases is
        taken for one more, with a DeprecationWarning.

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.marshall_palmer(5.0)   # 5 mm/h
        >>> print(f"{d.number_concentration:.0f} drops per m^3, mean radius {d.mean_radius * 1e3:.3f} mm")
        1368 drops per m^3, mean radius 0.171 mm
        """
        for k in deprecated:
            if k != "rain_rate_mm_per_h":
                raise TypeError(f"marshall_palmer() got an unexpected keyword argument '{k}'")
        kw = _deprecated_keyword({"rain_rate_mmh": rain_rate_mmh, **deprecated}, "rain_rate_mm_per_h",
                                 "rain_rate_mmh", "mm/h", stacklevel=2)
        if kw["rain_rate_mmh"] is None:
            raise TypeError("marshall_palmer() missing the rain rate: rain_rate_mmh (mm/h)")
        args = (_real(kw["rain_rate_mmh"], "rain_rate_mmh"), _real(n0_per_m4, "n0_per_m4"))
        return cls(_core.SizeDistribution.marshall_palmer(*args), ("marshall_palmer", args))

    @property
    def kind(self) -> str:
        return self._d.kind

    def number_density(self, radius_m: ArrayLike) -> np.ndarray:
        """n(r) in m^-4 at the given radii (m); float64 of their shape.

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.gamma(10e-6, 0.2, number_per_m3=1e8)
        >>> [f"{n:.3g}" for n in d.number_density([5e-6, 10e-6, 20e-6])]
        ['3.18e+11', '1.99e+13', '4.63e+09']
        """
        return self._d.number_density(_reals(radius_m, "radius_m"))

    def moment(self, k: float) -> float:
        """M_k = integral of r^k n(r) dr (m^(k-3)).

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.monodisperse(1e-3, number_per_m3=100)
        >>> print(f"{d.moment(0):g} m^-3, liquid water {4 / 3 * 3.14159265 * d.moment(3) * 1e6:.3f} g/m^3")
        100 m^-3, liquid water 0.419 g/m^3
        """
        return self._d.moment(_real(k, "k"))

    @property
    def number_concentration(self) -> float:
        return self._d.number_concentration

    @property
    def mean_radius(self) -> float:
        return self._d.mean_radius

    @property
    def radius_variance(self) -> float:
        return self._d.radius_variance

    @property
    def effective_radius(self) -> float:
        """Hansen & Travis's r_eff = M3 / M2 (m)."""
        return self._d.effective_radius

    @property
    def parameters(self) -> dict:
        return self._d.parameters

    def quadrature(self, nodes: int, r_min_m: Optional[float] = None, r_max_m: Optional[float] = None,
                   log_spaced: bool = False) -> Tuple[np.ndarray, np.ndarray]:
        """Gauss quadrature of the distribution: (radius_m, weight) float64 arrays, the weights in
        drops per m^3, so that sum(w f(r)) approximates the integral of f(r) n(r) dr. With r_min_m and
        r_max_m: over that range (log_spaced: Gauss-Legendre in ln r).

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.gamma(10e-6, 0.2, number_per_m3=1e8)
        >>> r, w = d.quadrature(8)
        >>> r.shape, f"{w.sum():.4g}", f"{(w * r).sum() / w.sum():.4g}"   # N and the mean radius
        ((8,), '1e+08', '1e-05')
        >>> r, w = d.quadrature(24, r_min_m=1e-6, r_max_m=50e-6, log_spaced=True)
        >>> print(f"{w.sum():.3g}")
        1e+08
        """
        return self._d.quadrature(nodes, _opt_real(r_min_m, "r_min_m"), _opt_real(r_max_m, "r_max_m"),
                                  _flag(log_spaced, "log_spaced"))

    def to_xarray(self, radius_m: Optional[ArrayLike] = None, nodes: int = 64):
        """n(r) as an :class:`xarray.Dataset`: the variable number_density (m^-4) over the dimension
        radius (m), at ``radius_m`` (1-D) or else at the radii of a ``nodes``-point quadrature; the
        kind, its parameters and its moments as attributes.

        Example:

        >>> import hydrolux
        >>> ds = hydrolux.SizeDistribution.gamma(10e-6, 0.2, 1e8).to_xarray([5e-6, 10e-6, 20e-6])
        >>> ds.number_density.attrs["units"], [f"{v:.3g}" for v in ds.number_density.values]
        ('m-4', ['3.18e+11', '1.99e+13', '4.63e+09'])
        """
        xr = _xarray.xarray()
        if radius_m is None:
            r = np.sort(self.quadrature(nodes)[0])
        else:
            r = np.atleast_1d(_reals(radius_m, "radius_m")).astype(np.float64)
            if r.ndim != 1:
                raise ValueError(f"radius_m: expected one radius or a 1-D array of radii, got shape {r.shape}")
        n = self.number_density(r)
        attrs = {"Conventions": "CF-1.8", "title": f"hydrolux {self.kind} drop size distribution",
                 "source": f"hydrolux {__version__}", "size_distribution": self.kind,
                 "number_concentration_per_m3": self.number_concentration, "mean_radius_m": self.mean_radius,
                 "radius_variance_m2": self.radius_variance, "effective_radius_m": self.effective_radius}
        attrs.update({f"parameter_{k}": float(v) for k, v in self.parameters.items()})
        return xr.Dataset(
            data_vars={"number_density": xr.Variable(("radius",), n, attrs={
                "units": "m-4", "long_name": "number of drops per unit volume per unit radius n(r)"})},
            coords={"radius": xr.Variable(("radius",), r, attrs={"units": "m", "long_name": "drop radius"})},
            attrs=attrs)

    def __repr__(self) -> str:
        return f"SizeDistribution.{self.kind}(mean_radius={self.mean_radius:.4g} m, N={self.number_concentration:.4g} m^-3)"
