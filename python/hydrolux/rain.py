"""Weather over images and sequences: rain, fog and drops on the lens, and the built-in street scene
(``hydrolux rain``, ``fog``, ``lens-drops``). Their names are hydrolux's: ``hydrolux.rain``,
``hydrolux.RainRenderer`` (``hydrolux.rain`` is the function; this module is ``hydrolux.rain`` in
``sys.modules`` only). Each job's options come from its declared parameters (``_args._with_options``).
"""
from __future__ import annotations

import warnings
from typing import Any, NamedTuple, Optional, Sequence

import numpy as np

from hydrolux import _core
from hydrolux._args import _array_arg, _declared, _describe, _flag, _renamed, _rgb, _with_options


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


_RAIN_PARAMS = _declared("rain", "rain", "camera", "fog")
_RAIN_OPTIONS = tuple(p["name"] for p in _RAIN_PARAMS)
_CAMERA_OPTIONS = tuple(p["name"] for p in _RAIN_PARAMS if p["group"] == "camera")


def _rain_options(kw: dict) -> dict:
    for k in kw:
        if k not in _RAIN_OPTIONS:
            raise TypeError(f"unknown rain option '{k}' (options: {', '.join(_RAIN_OPTIONS)})")
    return {k: v for k, v in kw.items() if v is not None}


class RainRenderer:
    """One rain for one camera, for a sequence of frames (``hydrolux rain --input-dir``).

    The field of drops is made once (deterministic in the options and the seed); frame k is exposed
    from k / fps and any frame can be rendered alone, so chunks of a sequence rendered anywhere give
    the same bytes as one pass. ``width``, ``height``: the frames' size; ``ground_plane``: True when
    no depth maps will be given. Options as :func:`rain`.

    Example:

    >>> import hydrolux
    >>> renderer = hydrolux.RainRenderer(64, 48, rain_rate_mmh=25, wind_mps=3, seed=4)
    >>> scene = hydrolux.builtin_scene(64, 48)
    >>> frames = [renderer.render(scene, frame_index=k).image for k in range(3)]
    >>> bool((renderer.render(scene, frame_index=1).image == frames[1]).all())   # any frame alone, the same
    True
    """

    @_with_options(_RAIN_PARAMS, 4)
    def __init__(self, width: int, height: int, ground_plane: bool = True, **options: Any):
        options = _renamed(_RAIN_PARAMS, options)  # rate_mmh, deprecated: as rain_rate_mmh, with a warning
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
    ``rain_rate_mmh``, falling at terminal velocity with the wind, each seen through Garg & Nayar's drop
    model lit by the image, smeared by the exposure into streaks, hidden behind ``depth`` (camera z
    in metres, (H, W)) or else a ground plane; unresolved rain as extinction and airlight.

    ``image``: (H, W, 3 or more) linear RGB. Camera: ``focal_mm`` (default 35) or ``fov_deg``,
    ``sensor_width_mm`` (default 36) or ``pixel_pitch_um``. Every option has the CLI flag's range
    and default; the same seed gives the same bytes. For a sequence use :class:`RainRenderer`.

    Example:

    >>> import hydrolux
    >>> scene = hydrolux.builtin_scene(64, 48)
    >>> out = hydrolux.rain(scene, rain_rate_mmh=50, wind_mps=3, seed=4)
    >>> out.image.shape, out.mask.shape, out.layer is None
    ((48, 64, 3), (48, 64, 1), True)
    >>> again = hydrolux.rain(scene, rain_rate_mmh=50, wind_mps=3, seed=4)
    >>> bool((again.image == out.image).all())   # the same seed, the same bytes
    True
    """
    options = _renamed(_RAIN_PARAMS, options)  # rate_mmh, deprecated: as rain_rate_mmh, with a warning
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


# ---- rain detection and removal (hydrolux detect-rain, remove-rain; docs/rain-detection.md) ----------------

class RainDetection(NamedTuple):
    """Masks of the rain found in a sequence: masks (T, H, W) uint8, 1 where rain is detected (the
    method's); candidates, photometric and correlated the stages' masks (None where the method has
    none).

    Example:

    >>> import hydrolux
    >>> import numpy as np
    >>> clear = hydrolux.builtin_scene(160, 90)
    >>> r = hydrolux.RainRenderer(160, 90, seed=2, rain_rate_mmh=80, unresolved=False)
    >>> frames = [r.render(clear, frame_index=k).image for k in range(4)]
    >>> d = hydrolux.detect_rain(frames, exposure_s=0.008)
    >>> d.masks.shape, d.masks.dtype
    ((4, 90, 160), dtype('uint8'))
    >>> bool((d.masks <= d.candidates).all())
    True
    """
    masks: np.ndarray
    candidates: Optional[np.ndarray]
    photometric: Optional[np.ndarray]
    correlated: Optional[np.ndarray]


_DETECT_PARAMS = _declared("detect_rain", "detector")
_REMOVE_PARAMS = _declared("remove_rain", "removal")


def _known(options: dict, params: list, job: str) -> dict:
    names = tuple(p["name"] for p in params)
    for k in options:
        if k not in names:
            raise TypeError(f"unknown {job} option '{k}' (options: {', '.join(names)})")
    return {k: v for k, v in options.items() if v is not None}


@_with_options(_DETECT_PARAMS, 1)
def detect_rain(frames: Sequence[np.ndarray], **options: Any) -> RainDetection:
    """Rain found in a sequence of frames (``hydrolux detect-rain``; Garg & Nayar 2004): candidates
    brighter than both neighbouring frames by ``min_change_grey``, each streak's photometric test and the
    spatio-temporal correlation along the rain's direction. ``frames``: at least 3 linear images of one
    size ((H, W) or (H, W, C)), or one (T, H, W[, C]) array. The first and last frame get empty masks.

    Example:

    >>> import hydrolux
    >>> import numpy as np
    >>> frames = np.full((3, 8, 8, 3), 0.2, np.float32)
    >>> frames[1, 2:6, 4] = 0.3  # a short bright streak in the middle frame only
    >>> d = hydrolux.detect_rain(frames, method="candidates")
    >>> int(d.masks[1].sum()), int(d.masks[0].sum())
    (4, 0)
    """
    d = _core.detect_rain(frames, _known(options, _DETECT_PARAMS, "detect_rain"))
    return RainDetection(d["masks"], d["candidates"], d["photometric"], d["correlated"])


@_with_options(_REMOVE_PARAMS, 3)
def remove_rain(frames: Sequence[np.ndarray], masks: Optional[Sequence[np.ndarray]] = None,
                layers: Optional[Sequence[np.ndarray]] = None, **options: Any) -> np.ndarray:
    """Rain removed from a sequence (``hydrolux remove-rain``): ``method`` garg-nayar (the default) replaces
    each frame's masked pixels (``masks``, nonzero = rain, e.g. ``detect_rain``'s) by the mean of the
    neighbouring frames; median takes every pixel's temporal median; oracle inverts ``layers`` (the
    renderer's premultiplied RGBA rain layers, ``RainRenderer.render(..., with_layer=True).layer``).
    Returns (T, H, W, C) float32 linear.

    Example:

    >>> import hydrolux
    >>> import numpy as np
    >>> frames = np.full((3, 4, 4, 3), 0.25, np.float32)
    >>> frames[1, 1, 1] = 0.9
    >>> masks = np.zeros((3, 4, 4), np.uint8)
    >>> masks[1, 1, 1] = 1
    >>> float(hydrolux.remove_rain(frames, masks)[1, 1, 1, 0])
    0.25
    """
    return _core.remove_rain(frames, masks, layers, _known(options, _REMOVE_PARAMS, "remove_rain"))
