"""Image files: linear float32 arrays in and out, written atomically. Their names are hydrolux's:
``hydrolux.read_image``, ``hydrolux.write_image``. OpenImageIO (``hydrolux._image``) loads on first use.
"""
from __future__ import annotations

import numpy as np

from hydrolux._args import _array_arg, _flag, _path


def _image_module():
    from hydrolux import _image  # loads OpenImageIO (~260 libraries) on first use only
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
