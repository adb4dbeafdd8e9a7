"""One rain drop seen by a camera, and its view undone (``hydrolux drop render``, ``drop undistort``;
Garg & Nayar). Their names are hydrolux's: ``hydrolux.drop_render``, ``hydrolux.drop_undistort``.
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from hydrolux import _core
from hydrolux._args import _MEDIUM, _array_arg, _flag, _opt_real, _pair, _real, _text


# The drop render's declared defaults (drop/params.hpp): the same as hydrolux drop render's flags.
_DROP = {p["name"]: p["default"] for p in _core.params("drop_render")}
_UNDISTORT = {p["name"]: p["default"] for p in _core.params("drop_undistort")}


def drop_render(env: Optional[np.ndarray] = None, radius_mm: float = _DROP["radius_mm"],
                distance_m: float = _DROP["distance_m"], focal_mm: float = _DROP["focal_mm"],
                f_number: float = _DROP["f_number"], frame_mm: Optional[float] = _DROP["frame_mm"],
                size: int = _DROP["size"], samples: int = _DROP["samples"], internal: int = _DROP["internal"],
                medium: str = "water", temperature_c: Optional[float] = _DROP["temperature_c"],
                wavelength_nm: float = _DROP["wavelength_nm"], dispersion: bool = _DROP["dispersion"],
                background_blur: bool = _DROP["background_blur"], background: bool = _DROP["background"],
                exposure_ev: float = _DROP["exposure_ev"], method: str = _DROP["method"], shape: str = _DROP["shape"],
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
                   method=method, shape=shape, depth=depth)
    return _core.drop_render(env, medium, options)


def drop_undistort(image: np.ndarray, drop_center: Tuple[float, float], drop_radius_px: float,
                   fov_deg: float = _UNDISTORT["fov_deg"], yaw_deg: float = _UNDISTORT["yaw_deg"],
                   pitch_deg: float = _UNDISTORT["pitch_deg"], mu: float = _UNDISTORT["mu"],
                   size: Tuple[int, int] = (512, 512),
                   transmission_correction: bool = _UNDISTORT["transmission_correction"]) -> np.ndarray:
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
