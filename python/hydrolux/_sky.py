"""hydrolux.sky: a rainbow in a daylight scene, per pixel on the CPU (``hydrolux sky``; docs/sky.md).

The scene's checks, tables and compositor are the library's, the same as the CLI's job
(io/sky_job.hpp); the declared options (scene/sky_params.cpp) are keywords of the flags' names.
"""
from __future__ import annotations

from typing import Any, NamedTuple, Optional, Sequence

import numpy as np

from hydrolux import _core
from hydrolux._args import _array_arg, _with_options

# The sky's declared parameters (the library's one table): sky()'s keyword options, defaults and ranges.
_SKY_PARAMS = _core.params("sky")
_SKY_OPTIONS = tuple(p["name"] for p in _SKY_PARAMS)
# sky()'s first argument is the table's size (its default too); the others are keyword options.
_SIZE_DEFAULT = next(p["default"] for p in _SKY_PARAMS if p["name"] == "size")


class SkyResult(NamedTuple):
    """What :func:`sky` renders: ``image`` the frame's radiance, (H, W, 3) float32 linear Rec.709 in
    cd/m^2 (what ``hydrolux sky -o frame.exr`` writes; with ``stokes=True`` 9 channels: I, Q and U,
    each R, G, B, in each pixel's image basis); ``display`` the tone-mapped linear display values
    (what ``-o frame.png`` encodes through the sRGB curve; None with ``stokes``); ``stats`` the
    exposure's reference luminance ``l_ref`` (cd/m^2; halved with a polariser), the sun's
    illuminance ``sun_illuminance_lux``, the curtain's ``optical_depth``, the drops' ``shape``, the
    bow's ``positions`` (position angles computed; 1 for spheres) and ``profile_error``, the bow
    profiles' largest estimated error (relative RMS in luminance, from their even against their odd
    wavelengths; docs/lee.md, "The table's error"), with ``notes`` saying when it is above 1% and the
    ``sampling`` that would meet it, and ``sampling`` as :func:`hydrolux.lee`'s ``info["sampling"]``:
    the profiles' largest ``multiplier``, ``automatic`` (no ``sampling`` given: each profile at 1, and
    once more at up to 4 where its estimate is above 1%) and ``first_pass`` (``multiplier`` 1 and the
    largest ``luminance_rms`` of the profiles computed twice; None where none was)."""
    image: np.ndarray
    display: Optional[np.ndarray]
    stats: dict


@_with_options([p for p in _SKY_PARAMS if p["name"] != "size"], 4)
def sky(size: Sequence[int] = _SIZE_DEFAULT, shape: str = "sphere", *, environment: Optional[np.ndarray] = None,
        moisture: Optional[np.ndarray] = None, **options: Any) -> SkyResult:
    """A rainbow in a daylight scene, per pixel on the CPU (``hydrolux sky``; docs/sky.md): the view
    ray's angle to the sun looked up in the Lee tables computed for ``radius_um`` (Mie for spheres;
    for ``shape`` ``spheroid:Q`` or ``beard-chuang`` the bow by Airy theory of the drops' plane section
    at 19 position angles), times the sun's light and the rain curtain's scattering, over Preetham's
    sky and a ground plane (or ``environment``, an equirectangular (H, W, 3) map in cd/m^2); ``size``
    (width, height) in pixels; ``moisture`` (H, W) or (H, W, C) in [0, 1], its first channel scaling
    the rain per pixel; ``curtain_distance_m`` (near, far) metres; ``light_color`` three multipliers on
    the sun's light in the bow; ``blend`` physical or whitepaper; ``mode`` per-pixel, cube-map or
    half-dome. A polariser (``polarizer_deg``) or the Stokes images (``stokes``) as the CLI has them.
    The same values as the CLI's EXR, float for float; a bad value raises ValueError with the CLI's
    range. Computing the tables takes seconds (about 12 s for 500 um drops at ``sampling`` 1 on two
    cores; ``sampling`` 0.25 is 16 times faster; without ``sampling``, automatic as above).

    Example:

    >>> import hydrolux
    >>> frame = hydrolux.sky((64, 36), radius_um=10, sampling=0.25)
    >>> frame.image.shape, frame.display.shape
    ((36, 64, 3), (36, 64, 3))
    """
    for k in options:
        if k not in _SKY_OPTIONS or k == "size":
            raise TypeError(f"unknown sky option '{k}' (options: {', '.join(o for o in _SKY_OPTIONS if o != 'size')})")
    if not isinstance(shape, str):
        raise TypeError(f"shape: expected a str, got {type(shape).__name__}")
    d = _core.sky(shape, None if environment is None else _array_arg(environment, "environment"),
                  None if moisture is None else _array_arg(moisture, "moisture"),
                  {"size": size, **{k: v for k, v in options.items() if v is not None}})
    return SkyResult(d["image"], d["display"], d["stats"])
