"""Interface optics and media: Fresnel's equations and refractive indices (``hydrolux fresnel``,
``hydrolux ior``). Their names are hydrolux's: ``hydrolux.fresnel``, ``hydrolux.refractive_index``.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from hydrolux import _core
from hydrolux._args import _MEDIUM, ArrayLike, _opt_real, _real, _reals, _text


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
