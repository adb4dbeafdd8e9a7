"""hydrolux: physically based light transport through water drops, with numpy in and out.

The same physics, defaults, units and validation as the ``hydrolux`` command line tool:

- :func:`fresnel`, :func:`refractive_index`, :func:`media` -- interface optics and media
- :func:`mie`, :func:`sphere`, :func:`bulk_optics` -- Lorenz-Mie scattering, vectorised over sizes
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

import math
import os
import warnings
from typing import Any, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core

__version__: str = _core.__version__
__all__ = [
    "fresnel", "media", "refractive_index", "sphere", "mie", "mie_terms", "bulk_optics", "SizeDistribution",
    "lee", "LeeTable", "drop_render", "drop_undistort", "rain", "RainResult", "RainRenderer", "builtin_scene",
    "read_image", "write_image", "simd_target", "set_threads", "MieResult",
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
    when the copy cannot be made), anything else through numpy as float64."""
    if isinstance(value, np.ndarray):
        return value
    if value is None or isinstance(value, (str, bytes, complex, np.complexfloating)):
        raise TypeError(f"{name}: expected a number or an array of numbers, got {_describe(value)}")
    try:
        return np.asarray(value, dtype=np.float64)
    except OverflowError:
        raise ValueError(f"{name}: holds a number beyond what a double holds (about 1e308)") from None
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected a number or an array of numbers, got {_describe(value)}") from None


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


def _path(value: Any, name: str) -> str:
    if isinstance(value, str) or (isinstance(value, os.PathLike) and isinstance(os.fspath(value), str)):
        return os.fspath(value)
    raise TypeError(f"{name}: expected a file path (str or pathlib.Path), got {_describe(value)}")


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
    """The SIMD instruction set the Mie kernels run on this CPU (e.g. "AVX2", "AVX3")."""
    return _core.simd_target()


def set_threads(threads: int) -> None:
    """Use at most ``threads`` threads for every parallel loop of this process (0: every core)."""
    _core.set_threads(threads)


# ---- interface optics ----------------------------------------------------------------------------

def fresnel(theta_deg: ArrayLike, n1: float = 1.0, n2: float = 1.333, k2: float = 0.0) -> dict:
    """Fresnel reflectance and transmittance of a plane interface (``hydrolux fresnel``).

    Light goes from a transparent medium of index ``n1`` into a dielectric ``n2`` or, with ``k2 > 0``,
    an absorbing medium ``n2 + i k2``. ``theta_deg``: angles of incidence in [0, 90] degrees (any
    shape). Returns a dict of float64 arrays of that shape: ``rs``, ``rp``, ``r`` (unpolarised),
    ``t`` (NaN for an absorbing medium), ``theta_t_deg`` (NaN under total internal reflection or for
    an absorbing medium), and ``tir`` (bool). Indices in [1e-3, 1000], k2 in [0, 1000].
    """
    return _core.fresnel(_reals(theta_deg, "theta_deg"), _real(n1, "n1"), _real(n2, "n2"), _real(k2, "k2"))


def media() -> list:
    """The built-in media with their valid wavelength and temperature ranges and sources (``hydrolux ior --list``)."""
    return _core.media()


def refractive_index(medium: str, wavelength_nm: ArrayLike, temperature_c: Optional[float] = None) -> np.ndarray:
    """Complex refractive index n + ik of a medium (``hydrolux ior``) at vacuum wavelengths (nm).

    ``medium``: a name from :func:`media` or ``"const:1.49"``. ``temperature_c``: for media with a
    temperature model (water: 0 to 100 C); None takes the medium's default. Returns complex128 of
    the shape of ``wavelength_nm``.
    """
    return _core.refractive_index(_text(medium, "medium", _MEDIUM), _reals(wavelength_nm, "wavelength_nm"),
                                  _opt_real(temperature_c, "temperature_c"))


# ---- Mie ------------------------------------------------------------------------------------------

class MieResult(NamedTuple):
    """Lorenz-Mie results per size parameter (Bohren & Huffman conventions).

    qext, qsca, qabs, qback, g: float64 arrays of x's shape; n_terms: int32, the partial waves summed;
    s1, s2: complex128 of shape x.shape + (angles,), or None when no angles were asked for.
    """
    qext: np.ndarray
    qsca: np.ndarray
    qabs: np.ndarray
    qback: np.ndarray
    g: np.ndarray
    n_terms: np.ndarray
    s1: Optional[np.ndarray]
    s2: Optional[np.ndarray]


_DEFAULT_ANGLES = "0:180:181"


def mie(m: complex, x: ArrayLike, angles_deg: Union[ArrayLike, str, None] = _DEFAULT_ANGLES,
        threads: int = 0) -> MieResult:
    """Lorenz-Mie scattering by homogeneous spheres (``hydrolux mie``), vectorised over sizes.

    ``m``: relative complex index n + ik (k >= 0 absorbs; n, k up to 1000, |m| >= 1e-3), e.g.
    ``1.333 + 1e-8j``. ``x``: size parameters 2 pi r / lambda in [1e-6, 1e6], any shape.
    ``angles_deg``: scattering angles in [0, 180] degrees (0 = forward) for S1 and S2: an array, or
    ``"A:B:N"`` for N angles from A to B; the default is the CLI's 0:180:181. ``None`` computes the
    efficiencies alone (the fast path for size sweeps, ``--no-angles``). ``threads``: 0 = all cores.
    """
    m = _complex(m, "m")
    x_arr = _reals(x, "x")
    angles = None
    if angles_deg is not None:
        if isinstance(angles_deg, str):
            angles = _parse_angles(angles_deg)
        else:
            angles = np.atleast_1d(_reals(angles_deg, "angles_deg"))
    d = _core.mie(m, x_arr, angles, threads)
    return MieResult(d["qext"], d["qsca"], d["qabs"], d["qback"], d["g"], d["n_terms"], d.get("s1"), d.get("s2"))


def _parse_angles(text: str) -> np.ndarray:
    parts = text.split(":")
    try:
        if len(parts) == 3:
            a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
            if not (1 <= n <= 1000000):
                raise ValueError
            return np.linspace(a, b, n) if n > 1 else np.array([a])
        return np.array([float(v) for v in text.split(",")])
    except ValueError:
        raise ValueError(f"angles_deg '{text}': expected A:B:N (N angles from A to B, N in [1, 1000000]) "
                         "or a list 0,10,90, angles in [0, 180] deg") from None


def mie_terms(x: float) -> int:
    """The number of partial waves hydrolux sums for size parameter x: max(3, x + 7 x^(1/3) + 2)."""
    return _core.mie_terms(_real(x, "x"))


def sphere(radius_um: ArrayLike, wavelength_nm: float, medium: str = "water", surrounding: str = "air",
           temperature_c: Optional[float] = None) -> Tuple[complex, np.ndarray]:
    """The relative index m and size parameters x of spheres of ``radius_um`` (micrometres) of
    ``medium`` in ``surrounding`` at vacuum wavelength ``wavelength_nm`` (``hydrolux mie --radius-um``).
    Returns (m, x) with x of the shape of ``radius_um``."""
    return _core.sphere_problem(_reals(radius_um, "radius_um"), _real(wavelength_nm, "wavelength_nm"),
                                _text(medium, "medium", _MEDIUM), _text(surrounding, "surrounding", _MEDIUM),
                                _opt_real(temperature_c, "temperature_c"))


def bulk_optics(m: complex, wavelength_nm: float, distribution: "SizeDistribution", nodes: int = 64,
                medium_index: float = 1.0, threads: int = 0) -> dict:
    """Extinction, scattering, absorption and backscatter coefficients (m^-1) and the asymmetry
    parameter g of a population of spheres of index ``m`` (relative to the surrounding medium of
    real index ``medium_index``) at vacuum ``wavelength_nm``, by ``nodes``-point quadrature of the
    distribution (``scatter::mie_bulk_optics``)."""
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
    return _core.bulk_optics(m, k, r, w, threads)


class SizeDistribution:
    """A distribution of drop radii n(r) (m^-4): monodisperse, gamma, log-normal or Marshall-Palmer.

    Make one with :meth:`monodisperse`, :meth:`gamma`, :meth:`log_normal` or :meth:`marshall_palmer`.
    Radii in metres in (0, 1]; relative widths sigma_r / <r> in [1e-4, 1]; number concentrations
    in (0, 1e30] m^-3; rain rates in (0, 1000] mm/h.
    """

    def __init__(self, native: Any):
        self._d = native

    @classmethod
    def monodisperse(cls, radius_m: float, number_per_m3: float = 1.0) -> "SizeDistribution":
        return cls(_core.SizeDistribution.monodisperse(_real(radius_m, "radius_m"),
                                                       _real(number_per_m3, "number_per_m3")))

    @classmethod
    def gamma(cls, mean_radius_m: float, relative_width: float, number_per_m3: float = 1.0) -> "SizeDistribution":
        return cls(_core.SizeDistribution.gamma(_real(mean_radius_m, "mean_radius_m"),
                                                _real(relative_width, "relative_width"),
                                                _real(number_per_m3, "number_per_m3")))

    @classmethod
    def log_normal(cls, mean_radius_m: float, relative_width: float,
                   number_per_m3: float = 1.0) -> "SizeDistribution":
        return cls(_core.SizeDistribution.log_normal(_real(mean_radius_m, "mean_radius_m"),
                                                     _real(relative_width, "relative_width"),
                                                     _real(number_per_m3, "number_per_m3")))

    @classmethod
    def marshall_palmer(cls, rain_rate_mm_per_h: float, n0_per_m4: float = 8e6) -> "SizeDistribution":
        """Marshall & Palmer (1948): n(r) = N0' exp(-Lambda r), N0 = 8e6 m^-4 per metre of diameter."""
        return cls(_core.SizeDistribution.marshall_palmer(_real(rain_rate_mm_per_h, "rain_rate_mm_per_h"),
                                                          _real(n0_per_m4, "n0_per_m4")))

    @property
    def kind(self) -> str:
        return self._d.kind

    def number_density(self, radius_m: ArrayLike) -> np.ndarray:
        """n(r) in m^-4 at the given radii (m); float64 of their shape."""
        return self._d.number_density(_reals(radius_m, "radius_m"))

    def moment(self, k: float) -> float:
        """M_k = integral of r^k n(r) dr (m^(k-3))."""
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
        r_max_m: over that range (log_spaced: Gauss-Legendre in ln r)."""
        return self._d.quadrature(nodes, _opt_real(r_min_m, "r_min_m"), _opt_real(r_max_m, "r_max_m"),
                                  _flag(log_spaced, "log_spaced"))

    def __repr__(self) -> str:
        return f"SizeDistribution.{self.kind}(mean_radius={self.mean_radius:.4g} m, N={self.number_concentration:.4g} m^-3)"


# ---- Lee tables -----------------------------------------------------------------------------------

class LeeTable(NamedTuple):
    """A Lee diagram (``hydrolux lee``): rows are scattering angles, columns drop radii.

    rgb: (rows, columns, 3) float64, gamut-mapped linear RGB in sr^-1 relative to the sun;
    xyz: (rows, columns, 3) float64, CIE XYZ (unmapped); display: (rows, columns, 3) float32, the
    tone-mapped display values in [0, 1] (linear; apply the sRGB curve to show them);
    radius_um: (columns,), angle_deg and cos_angle: (rows,), wavelengths_nm: (K,).
    """
    rgb: np.ndarray
    xyz: np.ndarray
    display: np.ndarray
    radius_um: np.ndarray
    angle_deg: np.ndarray
    cos_angle: np.ndarray
    wavelengths_nm: np.ndarray
    info: dict


def _span(value, name):
    """One value, (A, B), or the CLI's text "A:B" / "A"."""
    if value is None:
        return None
    if isinstance(value, str):
        try:
            parts = [float(v) for v in value.split(":")]
        except ValueError:
            parts = []
        if len(parts) not in (1, 2):
            raise ValueError(f"{name} '{value}': expected A:B or one value (numbers)")
        return (parts[0], parts[-1])
    if isinstance(value, (tuple, list, np.ndarray)) and np.ndim(value) == 1:
        a, b = _pair(value, name, "one value or (A, B)")
        return (_real(a, f"{name}[0]"), _real(b, f"{name}[1]"))
    v = _real(value, name)
    return (v, v)


def lee(table: str = "rainbow", theory: str = "mie", radius_um=None, angle_deg=None,
        size: Optional[Tuple[int, int]] = None, radius_scale: str = "log", axis: str = "angle",
        sun_disk_deg: float = 0.53, limb_darkening: bool = False, size_spread: float = 0.1,
        wavelengths_nm: Tuple[float, float] = (380.0, 780.0), wavelengths: int = 0,
        temperature_c: Optional[float] = None, medium: str = "water", sun: str = "astm-g173-direct",
        color_space: str = "rec709", sampling: float = 1.0, seed: int = 1, threads: int = 0) -> LeeTable:
    """A Lee diagram, corona or glory table, computed spectrally (``hydrolux lee``; docs/lee.md).

    ``table``: "rainbow" (90-180 deg, 5-800 um), "corona" (0-20 deg, 1-50 um) or "glory"
    (160-180 deg, 1-50 um). ``theory``: "mie", "debye:P", "airy" ("airy:3" secondary) or
    "geometric[:P]". ``radius_um``: (A, B) in [0.1, 5000] um or one radius; ``angle_deg``: (A, B) in
    [0, 180]; ``size``: (columns, rows), default (512, 1024), (1, rows) for one radius.
    ``wavelengths``: samples over ``wavelengths_nm`` (0: one every 10 nm / sampling). Other
    arguments as the CLI's flags of the same names. Long: the GIL is released and Ctrl-C stops it.
    """
    d = _core.lee(_text(table, "table", "rainbow, corona or glory"),
                  _text(theory, "theory", "mie, debye:P, airy, airy:3 or geometric[:P]"),
                  _span(radius_um, "radius_um"), _span(angle_deg, "angle_deg"),
                  None if size is None else _pair(size, "size", "(columns, rows), two whole numbers"),
                  _text(radius_scale, "radius_scale", "log or linear"), _text(axis, "axis", "angle or cos"),
                  _real(sun_disk_deg, "sun_disk_deg"), _flag(limb_darkening, "limb_darkening"),
                  _real(size_spread, "size_spread"), _span(wavelengths_nm, "wavelengths_nm"), wavelengths,
                  _opt_real(temperature_c, "temperature_c"), _text(medium, "medium", _MEDIUM),
                  _text(sun, "sun", "a spectrum name as the CLI's --sun"),
                  _text(color_space, "color_space", "an RGB space as the CLI's --color-space"),
                  _real(sampling, "sampling"), seed, threads)
    info = {k: d[k] for k in ("theory", "color_space", "exposure", "white", "evaluations")}
    return LeeTable(d["rgb"], d["xyz"], d["display"], d["radius_um"], d["angle_deg"], d["cos_angle"],
                    d["wavelengths_nm"], info)


# ---- the drop -------------------------------------------------------------------------------------

def drop_render(env: Optional[np.ndarray] = None, radius_mm: float = 1.0, distance_m: float = 2.0,
                focal_mm: float = 50.0, f_number: float = 2.8, frame_mm: Optional[float] = None, size: int = 512,
                samples: int = 4, internal: int = 2, medium: str = "water", temperature_c: Optional[float] = None,
                wavelength_nm: float = 589.3, dispersion: bool = False, background_blur: bool = False,
                background: bool = True, exposure_ev: float = 0.0, method: str = "model", shape: str = "sphere",
                depth: int = 8) -> np.ndarray:
    """A rain drop rendered from an environment (``hydrolux drop render``; Garg & Nayar's Figure 8).

    ``env``: an equirectangular environment map (H, W, 3) linear float, or None for the built-in
    sky. ``frame_mm``: width of the field at the drop (default 5 x radius). ``method``: "model"
    (Garg & Nayar eq. 19) or "exact" (the Fresnel-split ray tracer to ``depth`` interactions;
    ``shape`` "sphere" or "beard-chuang"). ``background=False``: black background with the drop's
    coverage in alpha. Returns (size, size, 4) float32, linear RGBA.
    """
    return _core.drop_render(None if env is None else _array_arg(env, "env"), _real(radius_mm, "radius_mm"),
                             _real(distance_m, "distance_m"), _real(focal_mm, "focal_mm"),
                             _real(f_number, "f_number"), _opt_real(frame_mm, "frame_mm"), size, samples, internal,
                             _text(medium, "medium", _MEDIUM), _opt_real(temperature_c, "temperature_c"),
                             _real(wavelength_nm, "wavelength_nm"), _flag(dispersion, "dispersion"),
                             _flag(background_blur, "background_blur"), _flag(background, "background"),
                             _real(exposure_ev, "exposure_ev"), _text(method, "method", "model or exact"),
                             _text(shape, "shape", "sphere or beard-chuang"), depth)


def drop_undistort(image: np.ndarray, drop_center: Tuple[float, float], drop_radius_px: float,
                   fov_deg: float = 60.0, yaw_deg: float = 0.0, pitch_deg: float = 0.0, mu: float = 1.333,
                   size: Tuple[int, int] = (512, 512), transmission_correction: bool = True) -> np.ndarray:
    """Undo a drop's distortion (``hydrolux drop undistort``; Garg & Nayar Figure 9): the perspective
    view (``size`` = (width, height), ``fov_deg`` horizontal, turned by ``yaw_deg``/``pitch_deg``) of a
    pinhole camera at the drop whose image, centred at ``drop_center`` (x, y pixels) with radius
    ``drop_radius_px``, is in ``image`` (linear). Returns (height, width, 4) float32 RGBA, alpha = 1
    where the drop resolves the direction."""
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
    as ``hydrolux rain --stats-json`` writes per frame."""
    image: np.ndarray
    mask: np.ndarray
    layer: Optional[np.ndarray]
    stats: dict


_RAIN_OPTIONS = ("rate_mmh", "wind_mps", "wind_dir_deg", "exposure_s", "focal_mm", "fov_deg", "sensor_width_mm",
                 "pixel_pitch_um", "f_number", "focus_m", "fps", "camera_height_m", "pitch_deg", "near_m", "far_m",
                 "min_radius_mm", "max_radius_mm", "min_alpha", "extent_m", "backdrop_m", "oscillation", "seed",
                 "unresolved")


def _rain_options(kw: dict) -> dict:
    for k in kw:
        if k not in _RAIN_OPTIONS:
            raise TypeError(f"unknown rain option '{k}' (options: {', '.join(_RAIN_OPTIONS)})")
    if kw.get("fov_deg") is not None and kw.get("focal_mm") is not None:
        raise ValueError("fov_deg: give focal_mm or fov_deg, not both")
    if kw.get("pixel_pitch_um") is not None and kw.get("sensor_width_mm") is not None:
        raise ValueError("pixel_pitch_um: give sensor_width_mm or pixel_pitch_um, not both")
    return {k: v for k, v in kw.items() if v is not None}


class RainRenderer:
    """One rain for one camera, for a sequence of frames (``hydrolux rain --input-dir``).

    The field of drops is made once (deterministic in the options and the seed); frame k is exposed
    from k / fps and any frame can be rendered alone, so chunks of a sequence rendered anywhere give
    the same bytes as one pass. ``width``, ``height``: the frames' size; ``ground_plane``: True when
    no depth maps will be given. Options as :func:`rain`.
    """

    def __init__(self, width: int, height: int, ground_plane: bool = True, **options: Any):
        self._r = _core.RainRenderer(width, height, _flag(ground_plane, "ground_plane"), _rain_options(options))

    def render(self, image: np.ndarray, depth: Optional[np.ndarray] = None, frame_index: int = 0,
               with_layer: bool = False) -> RainResult:
        """Frame ``frame_index`` over ``image`` (H, W, 3 or more) linear RGB: every value finite (a NaN
        or infinity is a ValueError naming the pixel); negative values, light that cannot be, are read
        as 0 with a warning, their count in stats["negative_values_clamped"]."""
        return self._render(image, depth, frame_index, with_layer, 3)

    def _render(self, image, depth, frame_index, with_layer, stacklevel) -> RainResult:
        d = self._r.render(_array_arg(image, "image"), None if depth is None else _array_arg(depth, "depth"),
                           frame_index, _flag(with_layer, "with_layer"))
        n = d["stats"]["negative_values_clamped"]
        if n:
            warnings.warn(f"image: {n} negative value{'s' if n != 1 else ''} read as 0 (rain needs linear light, "
                          ">= 0)", RuntimeWarning, stacklevel=stacklevel)
        return RainResult(d["image"], d["mask"], d["layer"], d["stats"])

    def field_info(self) -> dict:
        return self._r.field_info()


def rain(image: np.ndarray, depth: Optional[np.ndarray] = None, frame_index: int = 0, with_layer: bool = False,
         *, rate_mmh: float = 25.0, wind_mps: float = 0.0, wind_dir_deg: float = 90.0, exposure_s: float = 0.008,
         focal_mm: Optional[float] = None, fov_deg: Optional[float] = None, sensor_width_mm: Optional[float] = None,
         pixel_pitch_um: Optional[float] = None, f_number: float = 0.0, focus_m: float = 10.0, fps: float = 25.0,
         camera_height_m: float = 1.7, pitch_deg: float = 0.0, near_m: float = 0.5, far_m: float = 100.0,
         min_radius_mm: float = 0.1, max_radius_mm: float = 2.9, min_alpha: float = 0.01, extent_m: float = 1000.0,
         backdrop_m: float = 100.0, oscillation: float = 0.0, seed: int = 1, unresolved: bool = True) -> RainResult:
    """Rain over one image (``hydrolux rain --image``; docs/rain.md): drops from Marshall-Palmer for
    ``rate_mmh``, falling at terminal velocity with the wind, each seen through Garg & Nayar's drop
    model lit by the image, smeared by the exposure into streaks, hidden behind ``depth`` (camera z
    in metres, (H, W)) or else a ground plane; unresolved rain as extinction and airlight.

    ``image``: (H, W, 3 or more) linear RGB. Camera: ``focal_mm`` (default 35) or ``fov_deg``,
    ``sensor_width_mm`` (default 36) or ``pixel_pitch_um``. Every option has the CLI flag's range
    and default; the same seed gives the same bytes. For a sequence use :class:`RainRenderer`.
    """
    opts = dict(rate_mmh=rate_mmh, wind_mps=wind_mps, wind_dir_deg=wind_dir_deg, exposure_s=exposure_s,
                f_number=f_number, focus_m=focus_m, fps=fps, camera_height_m=camera_height_m, pitch_deg=pitch_deg,
                near_m=near_m, far_m=far_m, min_radius_mm=min_radius_mm, max_radius_mm=max_radius_mm,
                min_alpha=min_alpha, extent_m=extent_m, backdrop_m=backdrop_m, oscillation=oscillation, seed=seed,
                unresolved=unresolved)
    for k, v in (("focal_mm", focal_mm), ("fov_deg", fov_deg), ("sensor_width_mm", sensor_width_mm),
                 ("pixel_pitch_um", pixel_pitch_um)):
        if v is not None:
            opts[k] = v
    img = _array_arg(image, "image")
    if img.ndim != 3 or img.shape[2] < 3:
        raise ValueError(f"image: expected (height, width, 3 or more channels) linear RGB, got {_describe(img)}")
    r = RainRenderer(img.shape[1], img.shape[0], depth is None, **opts)
    return r._render(img, depth, frame_index, with_layer, 3)


_CAMERA_OPTIONS = ("focal_mm", "fov_deg", "sensor_width_mm", "pixel_pitch_um", "f_number", "focus_m", "exposure_s",
                   "fps", "camera_height_m", "pitch_deg")


def builtin_scene(width: int = 1280, height: int = 720, **camera: Any) -> np.ndarray:
    """The built-in street scene (``hydrolux rain --image builtin``) as the camera sees it: (H, W, 3)
    float32 linear RGB. Camera options as :func:`rain` (focal_mm, fov_deg, pitch_deg, ...)."""
    for k in camera:
        if k not in _CAMERA_OPTIONS:
            raise TypeError(f"builtin_scene: '{k}' is not a camera option ({', '.join(_CAMERA_OPTIONS)})")
    return _core.builtin_scene(width, height, _rain_options(camera))


# ---- image files ----------------------------------------------------------------------------------

def _image_module():
    from . import _image  # loads OpenImageIO (~260 libraries) on first use only
    return _image


def read_image(path: str) -> np.ndarray:
    """An image file (PNG, JPEG, EXR, TIFF, HDR, PNM) as (H, W, C) float32 linear values (8/16-bit
    files through the sRGB curve), checked as the CLI checks its inputs."""
    return _image_module().read(_path(path, "path"))[0]


def write_image(path: str, image: np.ndarray, bits: int = 8) -> None:
    """Writes (H, W, C) linear float values as .png (sRGB, ``bits`` 8 or 16) or .exr (float),
    atomically: the file appears whole or not at all, never half-written."""
    _image_module().write(_path(path, "path"), _array_arg(image, "image"), bits)
