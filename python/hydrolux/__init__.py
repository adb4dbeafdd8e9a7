"""hydrolux: physically based light transport through water drops, with numpy in and out.

The same physics, defaults, units and validation as the ``hydrolux`` command line tool:

- :func:`fresnel`, :func:`refractive_index`, :func:`media` -- interface optics and media
- :func:`mie`, :func:`sphere`, :func:`bulk_optics` -- Lorenz-Mie scattering, vectorised over sizes
- :func:`phase` -- a drop's or a size distribution's phase function and Mueller elements, by any theory
- :class:`SizeDistribution` -- monodisperse, gamma, log-normal and Marshall-Palmer drops
- :func:`lee` -- Lee diagrams, corona and glory tables with their axes
- :func:`drop_render`, :func:`drop_undistort` -- a rain drop seen by a camera, and its view undone
- :func:`rain`, :class:`RainRenderer`, :func:`builtin_scene` -- rain over images and sequences
- :func:`read_image`, :func:`write_image` -- image files (linear float32), written atomically

A bad argument raises ``ValueError`` naming it and its valid range; calls that take time release the
GIL, and Lee tables, drop renders and large Mie calls stop on Ctrl-C (``KeyboardInterrupt``). Images are numpy arrays of shape (height, width, channels),
linear light, float32. Batch jobs on Dask: ``python3 -m hydrolux.batch --help``.
"""
from __future__ import annotations

import functools
import inspect
import math
import os
import warnings
from typing import Any, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core, _xarray

__version__: str = _core.__version__
__all__ = [
    "fresnel", "media", "refractive_index", "sphere", "mie", "mie_terms", "bulk_optics", "SizeDistribution",
    "lee", "LeeTable", "drop_render", "drop_undistort", "rain", "RainResult", "RainRenderer", "builtin_scene",
    "lens_drops", "LensDropsResult",
    "fog", "FogResult",
    "renderer_medium", "RendererMedium",
    "read_image", "write_image", "simd_target", "set_threads", "MieResult", "phase", "PhaseResult", "BulkOptics",
]

ArrayLike = Union[float, Sequence[float], np.ndarray]


# ---- arguments ------------------------------------------------------------------------------------
# Every argument is checked by type here (numbers, strings, flags, pairs) or in _core (whole numbers
# with their ranges, arrays), never laundered through int() / float() / bool() / str(): a bad one is a
# one-line TypeError or ValueError naming it, its value (short, never an array's contents) and what
# is valid.

# A value as an error message shows it: short, and never an array's or a container's contents (the
# same words as the bindings' own messages).
_describe = _core.describe


_REALS = (int, float, np.integer, np.floating)


def _real(value: Any, name: str) -> float:
    """One real number (not a bool); +-inf past a float's range, for the range check that follows."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value[()]
    if isinstance(value, _REALS) and not isinstance(value, (bool, np.bool_)):
        try:
            return float(value)
        except OverflowError:
            return math.inf if value > 0 else -math.inf
    raise TypeError(f"{name}: expected a number, got {_describe(value)}")


def _opt_real(value: Any, name: str) -> Optional[float]:
    return None if value is None else _real(value, name)


def _complex(value: Any, name: str) -> complex:
    """One complex number (a real one too)."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iufc":
        value = value[()]
    if isinstance(value, _REALS + (complex, np.complexfloating)) and not isinstance(value, (bool, np.bool_)):
        try:
            return complex(value)
        except OverflowError:
            raise ValueError(f"{name}: {_describe(value)} is beyond what a double holds (about 1e308)") from None
    raise TypeError(f"{name}: expected one complex number such as 1.333+1e-8j, got {_describe(value)}")


def _reals(value: Any, name: str) -> np.ndarray:
    """Numbers of any shape: an ndarray as it is (_core checks its dtype and copies it, MemoryError
    when the copy cannot be made), anything else through numpy as float64. Text is never a number
    here (``["10"]`` is a TypeError, as ``"10"`` is)."""
    if isinstance(value, np.ndarray):
        return value
    expected = f"{name}: expected a number or an array of numbers, got {_describe(value)}"
    if value is None or isinstance(value, (str, bytes, complex, np.complexfloating)):
        raise TypeError(expected)
    try:
        a = np.asarray(value)
    except OverflowError:
        raise ValueError(f"{name}: holds a number beyond what a double holds (about 1e308)") from None
    except (TypeError, ValueError):
        raise TypeError(expected) from None
    if a.dtype.kind in "USO" and any(isinstance(v, (str, bytes, np.str_, np.bytes_)) for v in a.flat):
        raise TypeError(f"{expected} holding text")
    if a.dtype.kind not in "biufO":
        raise TypeError(f"{expected} of {a.dtype}")
    try:
        return np.asarray(value, dtype=np.float64)
    except OverflowError:
        raise ValueError(f"{name}: holds a number beyond what a double holds (about 1e308)") from None
    except (TypeError, ValueError):
        raise TypeError(expected) from None


def _rgb(value: Any, name: str) -> list:
    """Three finite non-negative real numbers (linear R, G, B): a list, a tuple or a 1-D array of 3.
    Text, a set, a bool or a number is a TypeError; a sequence or array of numbers of another length
    or shape ((3, 1)), or a negative or non-finite value, a ValueError: each naming the argument."""
    what = "three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, 0.85)"
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "iuf":
            raise TypeError(f"{name}: expected {what}, got {_describe(value)}")
        if value.shape != (3,):  # numbers, but not three of them
            raise ValueError(f"{name}: expected {what}, got {_describe(value)}")
        items = list(value)
    elif isinstance(value, (list, tuple)):
        if len(value) != 3:
            raise ValueError(f"{name}: expected {what}, got a {type(value).__name__} of {len(value)}")
        items = list(value)
    else:
        raise TypeError(f"{name}: expected {what}, got {_describe(value)}")
    out = []
    for k, v in enumerate(items):
        x = _real(v, f"{name}[{k}]")
        if not (math.isfinite(x) and x >= 0):
            raise ValueError(f"{name}[{k}] = {x:g} is not a finite value >= 0 (linear light); expected {what}")
        out.append(x)
    return out


def _text(value: Any, name: str, valid: str) -> str:
    if not isinstance(value, str):
        raise TypeError(f"{name}: expected a string ({valid}), got {_describe(value)}")
    return value


def _flag(value: Any, name: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name}: expected True or False, got {_describe(value)}")
    return bool(value)


def _pair(value: Any, name: str, what: str) -> tuple:
    """Two values, (A, B) or [A, B] or a 1-D array of two; their own checks follow."""
    if isinstance(value, (tuple, list)) and len(value) == 2:
        return (value[0], value[1])
    if isinstance(value, np.ndarray) and value.shape == (2,):
        return (value[0], value[1])
    raise TypeError(f"{name}: expected {what}, got {_describe(value)}")


def _history(function: str, arguments: dict) -> str:
    """A CF history line for a call of ``hydrolux.<function>`` with these arguments (those that
    differ from the signature's defaults), as a labelled form's ``history`` attribute states it."""
    defaults = {name: p.default for name, p in inspect.signature(globals()[function]).parameters.items()
                if p.default is not inspect.Parameter.empty}
    return _xarray.history(_xarray.call_text(function, arguments, defaults))


def _path(value: Any, name: str) -> bytes:
    """A file path as the file system's bytes: str, bytes or os.PathLike, so that a name that is not
    UTF-8 (os.listdir gives it as surrogate escapes, os.fsencode back) reaches the file as the CLI's
    would."""
    if isinstance(value, (str, bytes)) or isinstance(value, os.PathLike):
        path = os.fspath(value)
        if isinstance(path, (str, bytes)):
            return os.fsencode(path)
    raise TypeError(f"{name}: expected a file path (str, bytes or pathlib.Path), got {_describe(value)}")


def _array_arg(value: Any, name: str) -> np.ndarray:
    """An image argument as an ndarray (_core checks its shape and dtype, naming it)."""
    if isinstance(value, np.ndarray):
        return value
    try:
        return np.asarray(value)
    except OverflowError:
        raise ValueError(f"{name}: holds a number beyond what a double holds (about 1e308)") from None
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected an array (height, width[, channels]), got {_describe(value)}") from None


_MEDIUM = "a name from media() or 'const:1.49'"


def simd_target() -> str:
    """The SIMD instruction set the Mie kernels run on this CPU (e.g. "AVX2", "AVX3").

    Example:

    >>> import hydrolux
    >>> target = hydrolux.simd_target()   # Highway's name for it: "AVX3" is AVX-512
    >>> isinstance(target, str) and len(target) > 0
    True
    """
    return _core.simd_target()


def set_threads(threads: int) -> None:
    """Use at most ``threads`` threads for every parallel loop of this process (0: every core).

    Example:

    >>> import hydrolux
    >>> hydrolux.set_threads(2)   # two threads from now on
    >>> hydrolux.set_threads(0)   # every core again
    """
    _core.set_threads(threads)


# ---- interface optics ----------------------------------------------------------------------------

def fresnel(theta_deg: ArrayLike, n1: float = 1.0, n2: float = 1.333, k2: float = 0.0) -> dict:
    """Fresnel reflectance and transmittance of a plane interface (``hydrolux fresnel``).

    Light goes from a transparent medium of index ``n1`` into a dielectric ``n2`` or, with ``k2 > 0``,
    an absorbing medium ``n2 + i k2``. ``theta_deg``: angles of incidence in [0, 90] degrees (any
    shape). Returns a dict of float64 arrays of that shape: ``rs``, ``rp``, ``r`` (unpolarised),
    ``t`` (NaN for an absorbing medium), ``theta_t_deg`` (NaN under total internal reflection or for
    an absorbing medium), and ``tir`` (bool). Indices in [1e-3, 1000], k2 in [0, 1000].

    Example:

    >>> import hydrolux
    >>> f = hydrolux.fresnel([0, 45, 89])   # air into water
    >>> print(f["r"].round(4), f["t"].round(4), f["theta_t_deg"].round(2))
    [0.0204 0.0279 0.8963] [0.9796 0.9721 0.1037] [ 0.   32.04 48.6 ]
    >>> bool(hydrolux.fresnel(60, n1=1.333, n2=1.0)["tir"])   # water into air, past the critical angle
    True
    >>> print(hydrolux.fresnel(45, n2=0.18, k2=3.4)["r"].round(3))   # an absorbing medium: a metal
    0.943
    """
    return _core.fresnel(_reals(theta_deg, "theta_deg"), _real(n1, "n1"), _real(n2, "n2"), _real(k2, "k2"))


def media() -> list:
    """The built-in media with their valid wavelength and temperature ranges and sources (``hydrolux ior --list``).

    Example:

    >>> import hydrolux
    >>> [m["medium"] for m in hydrolux.media()][:4]
    ['water', 'ice', 'pmma', 'bk7']
    >>> water = hydrolux.media()[0]
    >>> water["wavelength_nm"], water["temperature_c"], water["temperature_dependent"]
    ((200.0, 1100.0), (0.0, 100.0), True)
    """
    return _core.media()


def refractive_index(medium: str, wavelength_nm: ArrayLike, temperature_c: Optional[float] = None) -> np.ndarray:
    """Complex refractive index n + ik of a medium (``hydrolux ior``) at vacuum wavelengths (nm).

    ``medium``: a name from :func:`media` or ``"const:1.49"``. ``temperature_c``: for media with a
    temperature model (water: 0 to 100 C); None takes the medium's default. Returns complex128 of
    the shape of ``wavelength_nm``.

    Example:

    >>> import hydrolux
    >>> n = hydrolux.refractive_index("water", [450, 550, 650])
    >>> print(n.real.round(4))
    [1.3396 1.3347 1.3317]
    >>> print(hydrolux.refractive_index("water", 550, temperature_c=80).real.round(4))
    1.3247
    >>> print(hydrolux.refractive_index("const:1.49", 550))
    (1.49+0j)
    """
    return _core.refractive_index(_text(medium, "medium", _MEDIUM), _reals(wavelength_nm, "wavelength_nm"),
                                  _opt_real(temperature_c, "temperature_c"))


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
            "history": _history("mie", arguments)}
    return MieResult(d["qext"], d["qsca"], d["qabs"], d["qback"], d["g"], d["n_terms"], d.get("s1"), d.get("s2"),
                     d.get("s11"), d.get("s12"), d.get("s33"), d.get("s34"), info)


def mie_terms(x: float) -> int:
    """The number of partial waves hydrolux sums for size parameter x: max(3, x + 7 x^(1/3) + 2).

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
                    "history": _history("bulk_optics", dict(m=m, wavelength_nm=wavelength_nm,
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
        index as attributes, ``history`` naming the call.

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
        if info.get("notes"):
            attrs["comment"] = "; ".join(info["notes"])
        return xr.Dataset(data_vars=data_vars, coords=coords, attrs=attrs)


# The phase function's declared parameters (scatter/params.hpp): phase()'s defaults, ranges and checks
# (in _core, as the CLI's flags).
_PHASE = {p["name"]: p["default"] for p in _core.params("phase")}


def phase(radius_um: Optional[float], wavelength_nm: float, theory: str = "mie", size_distribution: str = "mono",
          medium: str = "water", surrounding: str = "air", angles_deg: Union[ArrayLike, str] = _DEFAULT_ANGLES,
          nodes: int = _PHASE["nodes"], temperature_c: Optional[float] = _PHASE["temperature_c"],
          threads: int = _PHASE["threads"], mueller: bool = _PHASE["mueller"]) -> PhaseResult:
    """The scattered intensity against angle of one drop or a size distribution (``hydrolux phase``):
    the same job, checks and numbers as the CLI, as a :class:`PhaseResult` of arrays.

    ``radius_um``: the drop's radius in micrometres, or the mean radius of a gamma or lognormal
    distribution (ignored, and may be None, for Marshall-Palmer rain). ``wavelength_nm``: in vacuum.
    ``theory``: "mie", "debye:P" (one Debye order: 0 diffraction + reflection, 2 primary rainbow, 3
    secondary), "airy" ("airy:P"; near the rainbow angle only) or "geometric" ("geometric:P").
    ``size_distribution``: "mono", "gamma:W" or "lognormal:W" (relative width W in [0.0001, 1]) or
    "marshall-palmer:H" (H mm/h, radii 50-3000 um), averaged over ``nodes`` radii.
    ``medium``, ``surrounding``: names as :func:`media` (or "const:1.49"). ``angles_deg``: scattering
    angles in [0, 180] degrees (0 = forward), an array or the CLI's text "A:B:N" or "0,10,90" (read
    by the CLI's parser: the same angles). ``temperature_c``: of the media that model it (water).
    ``threads``: 0 = all cores. ``mueller``: also the size-averaged Mueller elements and pol.
    Declared parameters (``nodes``, ``temperature_c``, ``threads``, ``mueller``) take the ranges of
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
    d = _core.phase(theory, radius, wavelength, size_distribution, medium, surrounding, angles_deg, options)
    pol = None
    if "s11" in d:
        with np.errstate(divide="ignore", invalid="ignore"):
            pol = -d["s12"] / d["s11"]
        undefined = int(np.count_nonzero(~np.isfinite(pol)))
        if undefined:  # S11 = 0: no light scattered there, so no degree of polarisation (NaN, not 0)
            warnings.warn(f"pol: NaN at {undefined} of {pol.size} angles, where S11 = 0 (no light is scattered there, "
                          "so -S12/S11 is undefined)", RuntimeWarning, stacklevel=2)
    d["info"]["history"] = _history("phase", arguments)
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
    Henyey-Greenstein), ``normalisation``.

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
                    surrounding: str = "air", nodes: int = _RENDERER_MEDIUM["nodes"],
                    temperature_c: Optional[float] = _RENDERER_MEDIUM["temperature_c"],
                    phase_wavelength_nm: float = _RENDERER_MEDIUM["phase_wavelength_nm"],
                    values: Optional[int] = None, max_error: float = _RENDERER_MEDIUM["max_error"],
                    forward_cut_deg: Optional[float] = None,
                    scene_unit_m: float = _RENDERER_MEDIUM["scene_unit_m"],
                    threads: int = _RENDERER_MEDIUM["threads"]) -> RendererMedium:
    """A population of drops as a renderer's participating medium (``hydrolux medium``): the same job,
    checks and file text as the CLI, as a :class:`RendererMedium`.

    ``radius_um``: the drop's radius, or the mean radius of gamma and lognormal (None for
    Marshall-Palmer rain). ``size_distribution``: "mono", "gamma:W", "lognormal:W" or
    "marshall-palmer:H". ``number_per_cm3`` or ``lwc_g_m3``: the count (one of them; neither for rain,
    whose count follows from its rate). ``format``: "mitsuba3" (homogeneous medium with a tabphase)
    or "pbrt-v4" (homogeneous medium with Henyey-Greenstein, its error stated). ``name``: the medium's
    id. The declared parameters (``nodes``, ``temperature_c``, ``phase_wavelength_nm``, ``values``,
    ``max_error``, ``forward_cut_deg``, ``scene_unit_m``, ``threads``) take the ranges of the CLI's
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
    in (0, 1e30] m^-3; rain rates in (0, 1000] mm/h.

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
    def marshall_palmer(cls, rain_rate_mm_per_h: float, n0_per_m4: float = 8e6) -> "SizeDistribution":
        """Marshall & Palmer (1948): n(r) = N0' exp(-Lambda r), N0 = 8e6 m^-4 per metre of diameter.

        Example:

        >>> import hydrolux
        >>> d = hydrolux.SizeDistribution.marshall_palmer(5.0)   # 5 mm/h
        >>> print(f"{d.number_concentration:.0f} drops per m^3, mean radius {d.mean_radius * 1e3:.3f} mm")
        1368 drops per m^3, mean radius 0.171 mm
        """
        args = (_real(rain_rate_mm_per_h, "rain_rate_mm_per_h"), _real(n0_per_m4, "n0_per_m4"))
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


# ---- Lee tables -----------------------------------------------------------------------------------

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
    evaluations, the drops' shape, and for :meth:`to_xarray` the labelled description
    (``dataset``, whose arrays are these) and the call's ``history`` line.

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


def lee(table: str = "rainbow", theory: str = "mie", radius_um=None, angle_deg=None,
        size: Optional[Tuple[int, int]] = None, radius_scale: str = "log", axis: str = "angle",
        sun_disk_deg: float = _LEE["sun_disk_deg"]["default"], limb_darkening: bool = _LEE["limb_darkening"]["default"],
        size_spread: float = _LEE["size_spread"]["default"], wavelengths_nm: Tuple[float, float] = (380.0, 780.0),
        wavelengths: int = 0, temperature_c: Optional[float] = _LEE["temperature_c"]["default"],
        medium: str = "water", sun: str = "astm-g173-direct", color_space: str = "rec709",
        sampling: float = _LEE["sampling"]["default"], seed: int = _LEE["seed"]["default"],
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
    flags of the same names. ``stokes``: also the Stokes Q (``q_xyz``) and ``dolp`` (docs/lee.md,
    "Polarisation"). Long: the GIL is released and Ctrl-C stops it.

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
    table = _text(table, "table", "rainbow, corona or glory")
    theory = _text(theory, "theory", "mie, debye:P, airy, airy:3 or geometric[:P]")
    radius_um, angle_deg = _span(radius_um, "radius_um"), _span(angle_deg, "angle_deg")
    size = None if size is None else _pair(size, "size", "(columns, rows), two whole numbers")
    radius_scale, axis = _text(radius_scale, "radius_scale", "log or linear"), _text(axis, "axis", "angle or cos")
    options = {"sun_disk_deg": _real(sun_disk_deg, "sun_disk_deg"),
               "limb_darkening": _flag(limb_darkening, "limb_darkening"),
               "size_spread": _real(size_spread, "size_spread")}
    wavelengths_nm = _span(wavelengths_nm, "wavelengths_nm")
    options["temperature_c"] = _opt_real(temperature_c, "temperature_c")
    medium, sun = _text(medium, "medium", _MEDIUM), _text(sun, "sun", "a spectrum name as the CLI's --sun")
    color_space = _text(color_space, "color_space", "an RGB space as the CLI's --color-space")
    options.update(sampling=_real(sampling, "sampling"), seed=seed, threads=threads)
    # The drops' shape and the bow's point: last in the signature, so positional calls keep working.
    shape = _text(shape, "shape", "sphere, spheroid:Q or beard-chuang")
    options.update(sun_elevation_deg=_real(sun_elevation_deg, "sun_elevation_deg"),
                   position_deg=_real(position_deg, "position_deg"), canting_deg=_real(canting_deg, "canting_deg"))
    options["stokes"] = _flag(stokes, "stokes")
    d = _core.lee(table, theory, radius_um, angle_deg, size, radius_scale, axis, wavelengths_nm, wavelengths, shape,
                  medium, sun, color_space, options)
    info = {k: d[k] for k in ("theory", "color_space", "exposure", "white", "evaluations", "drop_shape", "dataset")}
    info["history"] = _history("lee", arguments)
    return LeeTable(d["rgb"], d["xyz"], d["display"], d["radius_um"], d["angle_deg"], d["cos_angle"],
                    d["wavelengths_nm"], info, d.get("q_xyz"), d.get("dolp"))


# ---- the drop -------------------------------------------------------------------------------------

# The drop render's declared defaults (drop/params.hpp): the same as hydrolux drop render's flags.
_DROP = {p["name"]: p["default"] for p in _core.params("drop_render")}


def drop_render(env: Optional[np.ndarray] = None, radius_mm: float = _DROP["radius_mm"],
                distance_m: float = _DROP["distance_m"], focal_mm: float = _DROP["focal_mm"],
                f_number: float = _DROP["f_number"], frame_mm: Optional[float] = _DROP["frame_mm"],
                size: int = _DROP["size"], samples: int = _DROP["samples"], internal: int = _DROP["internal"],
                medium: str = "water", temperature_c: Optional[float] = _DROP["temperature_c"],
                wavelength_nm: float = _DROP["wavelength_nm"], dispersion: bool = _DROP["dispersion"],
                background_blur: bool = _DROP["background_blur"], background: bool = _DROP["background"],
                exposure_ev: float = _DROP["exposure_ev"], method: str = "model", shape: str = "sphere",
                depth: int = _DROP["depth"]) -> np.ndarray:
    """A rain drop rendered from an environment (``hydrolux drop render``; Garg & Nayar's Figure 8).

    ``env``: an equirectangular environment map (H, W, 3) linear float, or None for the built-in
    sky. ``frame_mm``: width of the field at the drop (default 5 x radius). ``method``: "model"
    (Garg & Nayar eq. 19) or "exact" (the Fresnel-split ray tracer to ``depth`` interactions;
    ``shape`` "sphere" or "beard-chuang"). ``background=False``: black background with the drop's
    coverage in alpha. Returns (size, size, 4) float32, linear RGBA.

    Example:

    >>> import hydrolux
    >>> img = hydrolux.drop_render(size=32, samples=1)   # the built-in sky through a 1 mm drop, 2 m away
    >>> img.shape, img.dtype, float(img[16, 16, 3])   # alpha 1: the drop covers the centre
    ((32, 32, 4), dtype('float32'), 1.0)
    >>> exact = hydrolux.drop_render(size=16, samples=1, method="exact", shape="beard-chuang", radius_mm=2.0)
    >>> exact.shape
    (16, 16, 4)
    """
    env = None if env is None else _array_arg(env, "env")
    options = dict(radius_mm=_real(radius_mm, "radius_mm"), distance_m=_real(distance_m, "distance_m"),
                   focal_mm=_real(focal_mm, "focal_mm"), f_number=_real(f_number, "f_number"),
                   frame_mm=_opt_real(frame_mm, "frame_mm"), size=size, samples=samples, internal=internal)
    medium = _text(medium, "medium", _MEDIUM)
    options.update(temperature_c=_opt_real(temperature_c, "temperature_c"),
                   wavelength_nm=_real(wavelength_nm, "wavelength_nm"), dispersion=_flag(dispersion, "dispersion"),
                   background_blur=_flag(background_blur, "background_blur"),
                   background=_flag(background, "background"), exposure_ev=_real(exposure_ev, "exposure_ev"),
                   depth=depth)
    return _core.drop_render(env, medium, _text(method, "method", "model or exact"),
                             _text(shape, "shape", "sphere or beard-chuang"), options)


def drop_undistort(image: np.ndarray, drop_center: Tuple[float, float], drop_radius_px: float,
                   fov_deg: float = 60.0, yaw_deg: float = 0.0, pitch_deg: float = 0.0, mu: float = 1.333,
                   size: Tuple[int, int] = (512, 512), transmission_correction: bool = True) -> np.ndarray:
    """Undo a drop's distortion (``hydrolux drop undistort``; Garg & Nayar Figure 9): the perspective
    view (``size`` = (width, height), ``fov_deg`` horizontal, turned by ``yaw_deg``/``pitch_deg``) of a
    pinhole camera at the drop whose image, centred at ``drop_center`` (x, y pixels) with radius
    ``drop_radius_px``, is in ``image`` (linear). Returns (height, width, 4) float32 RGBA, alpha = 1
    where the drop resolves the direction.

    Example:

    >>> import hydrolux
    >>> drop = hydrolux.drop_render(size=64, samples=1)   # the drop fills 2/5 of the frame: radius 12.8 px
    >>> view = hydrolux.drop_undistort(drop, drop_center=(32, 32), drop_radius_px=12.8, size=(32, 16))
    >>> view.shape, float(view[8, 16, 3])   # (height, width, RGBA); the centre is resolved
    ((16, 32, 4), 1.0)
    """
    cx, cy = _pair(drop_center, "drop_center", "(x, y) in pixels")
    return _core.drop_undistort(_array_arg(image, "image"),
                                (_real(cx, "drop_center[0]"), _real(cy, "drop_center[1]")),
                                _real(drop_radius_px, "drop_radius_px"), _real(mu, "mu"), _real(fov_deg, "fov_deg"),
                                _real(yaw_deg, "yaw_deg"), _real(pitch_deg, "pitch_deg"),
                                _pair(size, "size", "(width, height), two whole numbers"),
                                _flag(transmission_correction, "transmission_correction"))


# ---- rain -----------------------------------------------------------------------------------------

class RainResult(NamedTuple):
    """A rainy frame: image (H, W, C) float32 linear; mask (H, W, 1) float32, the rain's coverage
    (image = clear (1 - mask) + layer); layer (H, W, 4) premultiplied RGBA or None; stats: a dict
    as ``hydrolux rain --stats-json`` writes per frame.

    Example:

    >>> import hydrolux
    >>> import numpy as np
    >>> clear = hydrolux.builtin_scene(64, 48)
    >>> r = hydrolux.rain(clear, seed=4, with_layer=True)
    >>> isinstance(r, hydrolux.RainResult), r.mask.shape, r.layer.shape
    (True, (48, 64, 1), (48, 64, 4))
    >>> bool(np.allclose(r.image, clear * (1 - r.mask) + r.layer[..., :3], atol=1e-5))
    True
    """
    image: np.ndarray
    mask: np.ndarray
    layer: Optional[np.ndarray]
    stats: dict


def _warn_negative(count: int, job: str, stacklevel: int = 3) -> None:
    """The one warning of rain, fog and lens_drops for negative light in their image (read as 0)."""
    if count:
        warnings.warn(f"image: {count} negative value{'s' if count != 1 else ''} read as 0 ({job} needs linear "
                      "light, >= 0)", RuntimeWarning, stacklevel=stacklevel)


def _declared(job: str, *groups: str) -> list:
    """A job's declared parameters (the library's one table, hydrolux/jobs.hpp) of the given groups."""
    return [p for p in _core.params(job) if p["group"] in groups]


_RAIN_PARAMS = _declared("rain", "rain", "camera", "fog")
_RAIN_OPTIONS = tuple(p["name"] for p in _RAIN_PARAMS)
_CAMERA_OPTIONS = tuple(p["name"] for p in _RAIN_PARAMS if p["group"] == "camera")


def _rain_options(kw: dict) -> dict:
    for k in kw:
        if k not in _RAIN_OPTIONS:
            raise TypeError(f"unknown rain option '{k}' (options: {', '.join(_RAIN_OPTIONS)})")
    return {k: v for k, v in kw.items() if v is not None}


def _options_doc(params: list) -> str:
    """The options' reference for a docstring, from the declared table: name, range, default, help."""
    lines = []
    for p in params:
        valid = "True or False" if p["kind"] == "flag" else p["range"]
        default = f"; default {p['default']!r}" if p["default"] is not None else ""
        # A switch's help is its CLI flag's, which turns the default around (--no-unresolved).
        what = f"{not p['default']}: {p['help']}" if p["kind"] == "flag" else p["help"]
        lines.append(f"    ``{p['name']}`` ({valid}{default}): {what}")
    return "\n".join(lines)


def _with_options(params: list, keep: int, positional: bool = False):
    """Gives a function taking ``**options`` the declared options as parameters in its signature
    (help(), IDEs and inspect show them) and their reference at the end of its docstring. The
    options are keyword-only, or with ``positional`` may also be given by position after the first
    ``keep`` parameters (for functions whose options always could be); either way the function
    receives only the options given, and the library fills in the rest from the same table."""
    def wrap(fn):
        sig = inspect.signature(fn)
        head = [q for q in sig.parameters.values() if q.kind != q.VAR_KEYWORD][:keep]
        # A parameter another replaces (focal_mm by fov_deg) shows None: either may be given.
        replaced = {p["excludes"] for p in params if p["excludes"]}
        kind = inspect.Parameter.POSITIONAL_OR_KEYWORD if positional else inspect.Parameter.KEYWORD_ONLY
        opts = [inspect.Parameter(p["name"], kind, default=None if p["name"] in replaced else p["default"],
                                  annotation={"real": float, "integer": int, "flag": bool}[p["kind"]])
                for p in params]
        full = sig.replace(parameters=head + opts)
        doc = (fn.__doc__ or "").rstrip() + "\n\n    Options (the CLI's flags of the same names):\n\n" + \
            _options_doc(params) + "\n"
        if not positional:
            fn.__signature__, fn.__doc__ = full, doc
            return fn
        names = [q.name for q in head]

        @functools.wraps(fn)
        def call(*args, **kw):
            bound = full.bind(*args, **kw)
            given = bound.arguments
            return fn(**{n: given[n] for n in names if n in given}, **{k: v for k, v in given.items() if k not in names})

        call.__signature__, call.__doc__ = full, doc
        return call
    return wrap


class RainRenderer:
    """One rain for one camera, for a sequence of frames (``hydrolux rain --input-dir``).

    The field of drops is made once (deterministic in the options and the seed); frame k is exposed
    from k / fps and any frame can be rendered alone, so chunks of a sequence rendered anywhere give
    the same bytes as one pass. ``width``, ``height``: the frames' size; ``ground_plane``: True when
    no depth maps will be given. Options as :func:`rain`.

    Example:

    >>> import hydrolux
    >>> renderer = hydrolux.RainRenderer(64, 48, rate_mmh=25, wind_mps=3, seed=4)
    >>> scene = hydrolux.builtin_scene(64, 48)
    >>> frames = [renderer.render(scene, frame_index=k).image for k in range(3)]
    >>> bool((renderer.render(scene, frame_index=1).image == frames[1]).all())   # any frame alone, the same
    True
    """

    @_with_options(_RAIN_PARAMS, 4)
    def __init__(self, width: int, height: int, ground_plane: bool = True, **options: Any):
        self._r = _core.RainRenderer(width, height, _flag(ground_plane, "ground_plane"), _rain_options(options))
        self._made_by = (width, height, ground_plane, dict(options))

    # Pickled as its arguments (Dask ships renderers between processes): the field is made again from
    # them, deterministic in the options and the seed, so the copy renders the same bytes.
    def __getstate__(self):
        return self._made_by

    def __setstate__(self, state):
        width, height, ground_plane, options = state
        RainRenderer.__init__(self, width, height, ground_plane, **options)

    def render(self, image: np.ndarray, depth: Optional[np.ndarray] = None, frame_index: int = 0,
               with_layer: bool = False) -> RainResult:
        """Frame ``frame_index`` over ``image`` (H, W, 3 or more) linear RGB: every value finite (a NaN
        or infinity is a ValueError naming the pixel); negative values, light that cannot be, are read
        as 0 with a warning, their count in stats["negative_values_clamped"].

        Example:

        >>> import hydrolux
        >>> renderer = hydrolux.RainRenderer(64, 48, seed=4)
        >>> frame = renderer.render(hydrolux.builtin_scene(64, 48), frame_index=7, with_layer=True)
        >>> frame.image.shape, frame.layer.shape, frame.stats["negative_values_clamped"]
        ((48, 64, 3), (48, 64, 4), 0)
        """
        return self._render(image, depth, frame_index, with_layer, 3)

    def _render(self, image, depth, frame_index, with_layer, stacklevel) -> RainResult:
        d = self._r.render(_array_arg(image, "image"), None if depth is None else _array_arg(depth, "depth"),
                           frame_index, _flag(with_layer, "with_layer"))
        _warn_negative(d["stats"]["negative_values_clamped"], "rain", stacklevel + 1)
        return RainResult(d["image"], d["mask"], d["layer"], d["stats"])

    def field_info(self) -> dict:
        """The rain field: its drops, total extinction (m^-1), frame size and focal length (px).

        Example:

        >>> import hydrolux
        >>> info = hydrolux.RainRenderer(64, 48, seed=4).field_info()
        >>> sorted(info), info["width"], info["height"]
        (['beta_total_per_m', 'drops', 'focal_px', 'height', 'width'], 64, 48)
        """
        return self._r.field_info()


@_with_options(_RAIN_PARAMS, 4)
def rain(image: np.ndarray, depth: Optional[np.ndarray] = None, frame_index: int = 0, with_layer: bool = False,
         **options: Any) -> RainResult:
    """Rain over one image (``hydrolux rain --image``; docs/rain.md): drops from Marshall-Palmer for
    ``rate_mmh``, falling at terminal velocity with the wind, each seen through Garg & Nayar's drop
    model lit by the image, smeared by the exposure into streaks, hidden behind ``depth`` (camera z
    in metres, (H, W)) or else a ground plane; unresolved rain as extinction and airlight.

    ``image``: (H, W, 3 or more) linear RGB. Camera: ``focal_mm`` (default 35) or ``fov_deg``,
    ``sensor_width_mm`` (default 36) or ``pixel_pitch_um``. Every option has the CLI flag's range
    and default; the same seed gives the same bytes. For a sequence use :class:`RainRenderer`.

    Example:

    >>> import hydrolux
    >>> scene = hydrolux.builtin_scene(64, 48)
    >>> out = hydrolux.rain(scene, rate_mmh=50, wind_mps=3, seed=4)
    >>> out.image.shape, out.mask.shape, out.layer is None
    ((48, 64, 3), (48, 64, 1), True)
    >>> again = hydrolux.rain(scene, rate_mmh=50, wind_mps=3, seed=4)
    >>> bool((again.image == out.image).all())   # the same seed, the same bytes
    True
    """
    img = _array_arg(image, "image")
    if img.ndim != 3 or img.shape[2] < 3:
        raise ValueError(f"image: expected (height, width, 3 or more channels) linear RGB, got {_describe(img)}")
    r = RainRenderer(img.shape[1], img.shape[0], depth is None, **options)
    return r._render(img, depth, frame_index, with_layer, 3)


@_with_options([p for p in _RAIN_PARAMS if p["group"] == "camera"], 2)
def builtin_scene(width: int = 1280, height: int = 720, **camera: Any) -> np.ndarray:
    """The built-in street scene (``hydrolux rain --image builtin``) as the camera sees it: (H, W, 3)
    float32 linear RGB. Camera options as :func:`rain` (focal_mm, fov_deg, pitch_deg, ...).

    Example:

    >>> import hydrolux
    >>> scene = hydrolux.builtin_scene(64, 48, fov_deg=90)
    >>> scene.shape, scene.dtype
    ((48, 64, 3), dtype('float32'))
    """
    for k in camera:
        if k not in _CAMERA_OPTIONS:
            raise TypeError(f"builtin_scene: '{k}' is not a camera option ({', '.join(_CAMERA_OPTIONS)})")
    return _core.builtin_scene(width, height, _rain_options(camera))


# ---- drops on the lens or windshield --------------------------------------------------------------

class LensDropsResult(NamedTuple):
    """Drops on the lens: image (H, W, C) float32 linear, mask (H, W, 1) float32 the drops' defocused
    coverage (image = clean (1 - mask) + the blurred drop layer; 0 away from the drops).

    Example:

    >>> import hydrolux
    >>> clean = hydrolux.builtin_scene(96, 64)
    >>> r = hydrolux.lens_drops(clean, seed=1, drops=20)
    >>> isinstance(r, hydrolux.LensDropsResult), r.mask.shape, bool(r.mask.max() <= 1)
    (True, (64, 96, 1), True)
    """
    image: np.ndarray
    mask: np.ndarray


_LENS_DROPS_PARAMS = _declared("lens_drops", "drops", "camera", "optics", "render")
_LENS_DROPS_OPTIONS = tuple(p["name"] for p in _LENS_DROPS_PARAMS)


@_with_options(_LENS_DROPS_PARAMS, 1)
def lens_drops(image: np.ndarray, **options: Any) -> LensDropsResult:
    """Water drops on the lens or windshield over one image (``hydrolux lens-drops --image``;
    docs/lens-drops.md): spherical caps on a glass plane ``glass_distance_m`` in front of a thin-lens
    camera, each refracting the scene behind it (Snell and Fresnel at the exact cap; the scene at
    infinity), blurred by the aperture's circle of confusion. ``image``: (H, W) or (H, W, C) linear.
    Every option has the CLI flag's range and default; the same seed gives the same bytes.

    Example:

    >>> import hydrolux
    >>> clean = hydrolux.builtin_scene(96, 64)
    >>> out, mask = hydrolux.lens_drops(clean, seed=3, coverage=0.2)
    >>> out.shape, mask.shape
    ((64, 96, 3), (64, 96, 1))
    >>> bool((hydrolux.lens_drops(clean, seed=3, coverage=0.2).image == out).all())
    True
    """
    for k in options:
        if k not in _LENS_DROPS_OPTIONS:
            raise TypeError(f"unknown lens_drops option '{k}' (options: {', '.join(_LENS_DROPS_OPTIONS)})")
    d = _core.lens_drops(_array_arg(image, "image"), {k: v for k, v in options.items() if v is not None})
    _warn_negative(d["negative_values_clamped"], "lens_drops")
    return LensDropsResult(d["image"], d["mask"])


# ---- fog, haze and mist ---------------------------------------------------------------------------

class FogResult(NamedTuple):
    """Fog over an image: image (H, W, C) float32 linear, mask (H, W, 1) float32 the fog's coverage
    1 - t (image = clear t + sky (1 - t) + glow), stats a dict (beta_per_m, visibility_m,
    transmittance_mean, sky_rgb, glow_luminance_mean, ...).

    Example:

    >>> import hydrolux
    >>> import numpy as np
    >>> clear = hydrolux.builtin_scene(64, 48)
    >>> r = hydrolux.fog(clear, visibility_m=200, glow=False)
    >>> isinstance(r, hydrolux.FogResult), r.mask.shape
    (True, (48, 64, 1))
    >>> t, sky = 1 - r.mask, np.array(r.stats["sky_rgb"])
    >>> bool(np.allclose(r.image, clear * t + sky * (1 - t), atol=1e-5))
    True
    """
    image: np.ndarray
    mask: np.ndarray
    stats: dict


_FOG_PARAMS = _declared("fog", "fog", "camera")
_FOG_OPTIONS = tuple(p["name"] for p in _FOG_PARAMS)


@_with_options(_FOG_PARAMS, 3)
def fog(image: np.ndarray, depth: Optional[np.ndarray] = None, sky_rgb: Optional[Sequence[float]] = None,
        **options: Any) -> FogResult:
    """Fog, haze or mist over one image (``hydrolux fog --image``; docs/fog.md): extinction from
    ``visibility_m`` (Koschmieder, 3.912 / V) or from Lorenz-Mie over the droplets for
    ``lwc_g_m3``; per pixel t = exp(-beta d) with d the range from ``depth`` ((H, W) camera z in
    metres; non-finite or <= 0 is sky) or, without it, a ground plane; the airlight the sky's colour
    estimated from the image (or ``sky_rgb``, three linear values: a sequence keeps one sky); the glow
    around lights brighter than the sky. ``image``: (H, W, 3 or more) linear RGB. Deterministic: the
    same input gives the same floats.

    Example:

    >>> import hydrolux
    >>> clear = hydrolux.builtin_scene(96, 64)
    >>> out, mask, stats = hydrolux.fog(clear, visibility_m=150)
    >>> out.shape, mask.shape, round(stats["beta_per_m"], 5)
    ((64, 96, 3), (64, 96, 1), 0.02608)
    """
    for k in options:
        if k not in _FOG_OPTIONS:
            raise TypeError(f"unknown fog option '{k}' (options: {', '.join(_FOG_OPTIONS)})")
    d = _core.fog(_array_arg(image, "image"), None if depth is None else _array_arg(depth, "depth"),
                  None if sky_rgb is None else _rgb(sky_rgb, "sky_rgb"),
                  {k: v for k, v in options.items() if v is not None})
    _warn_negative(d["stats"]["negative_values_clamped"], "fog")
    return FogResult(d["image"], d["mask"], d["stats"])


# ---- image files ----------------------------------------------------------------------------------

def _image_module():
    from . import _image  # loads OpenImageIO (~260 libraries) on first use only
    return _image


def read_image(path: str) -> np.ndarray:
    """An image file (PNG, JPEG, EXR, TIFF, HDR, PNM) as (H, W, C) float32 linear values, checked as
    the CLI checks its inputs: float files as they are; a PNG that declares linear codes (gAMA 1.0 and
    no sRGB chunk: the coverage masks hydrolux writes, and :func:`write_image` with ``linear=True``)
    as code / max; other 8/16-bit files through the sRGB curve. Every file hydrolux writes reads back
    as what it holds (a mask's alpha within half a code).

    Example:

    >>> import hydrolux, os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "street.png")
    >>> hydrolux.write_image(path, hydrolux.builtin_scene(64, 48))
    >>> img = hydrolux.read_image(path)
    >>> img.shape, img.dtype
    ((48, 64, 3), dtype('float32'))
    """
    return _image_module().read(_path(path, "path"))[0]


def write_image(path: str, image: np.ndarray, bits: int = 8, linear: bool = False) -> None:
    """Writes (H, W, C) linear float values as .png (``bits`` 8 or 16) or .exr (float), atomically:
    the file appears whole or not at all, never half-written. A PNG holds colour through the sRGB
    curve (with the sRGB chunk) or, with ``linear=True`` for data that is not colour (a mask, a depth
    map as codes), the values in [0, 1] as linear codes, declared by gAMA 1.0 and no sRGB chunk;
    :func:`read_image` and hydrolux's readers read either back as the values written.

    Example:

    >>> import hydrolux, os, tempfile
    >>> import numpy as np
    >>> folder = tempfile.mkdtemp()
    >>> scene = hydrolux.builtin_scene(64, 48)
    >>> hydrolux.write_image(os.path.join(folder, "street.png"), scene, bits=16)
    >>> hydrolux.write_image(os.path.join(folder, "street.exr"), scene)   # float, linear
    >>> mask = np.full((48, 64, 1), 0.17, np.float32)
    >>> hydrolux.write_image(os.path.join(folder, "mask.png"), mask, bits=16, linear=True)
    >>> sorted(os.listdir(folder)), round(float(hydrolux.read_image(os.path.join(folder, "mask.png"))[0, 0, 0]), 5)
    (['mask.png', 'street.exr', 'street.png'], 0.17)
    """
    _image_module().write(_path(path, "path"), _array_arg(image, "image"), bits, _flag(linear, "linear"))
