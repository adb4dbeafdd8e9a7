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

# The package by domain, as the library's src/ is; the API is hydrolux.X, each name re-exported here:
#   optics   fresnel, media, refractive_index                 scatter  mie, phase, SizeDistribution, ...
#   atmos    lee, LeeTable                                    drop     drop_render, drop_undistort
#   rain     rain, RainRenderer, fog, lens_drops, ...         io       read_image, write_image
#   scene    sky
#   _args    the argument checks and the declared options' machinery they all share
# (hydrolux.rain is the function; its module is sys.modules["hydrolux.rain"], as `from hydrolux.rain import`
# and pickles find it.)
from hydrolux import _core, _xarray
from hydrolux._args import ArrayLike
from hydrolux.atmos import LeeTable, lee
from hydrolux.drop import drop_render, drop_undistort
from hydrolux.io import _image_module, read_image, write_image  # noqa: F401 (_image_module: the tests')
from hydrolux.optics import fresnel, media, refractive_index
from hydrolux.rain import (FogResult, LensDropsResult, RainDetection, RainRenderer, RainResult, builtin_scene,
                           detect_rain, fog, lens_drops, rain, remove_rain)
from hydrolux.scatter import (BulkOptics, MieResult, PhaseResult, RendererMedium, SizeDistribution, bulk_optics, mie,
                              mie_terms, phase, renderer_medium, sphere)
# A SizeDistribution pickled while the package was one file names hydrolux._remake_distribution: it still loads.
from hydrolux.scatter import _remake_distribution  # noqa: F401
from hydrolux.scene import sky
from hydrolux import eval  # noqa: E402 (hydrolux.eval.score: a module, as hydrolux.batch)

__version__: str = _core.__version__
__all__ = [
    "fresnel", "media", "refractive_index", "sphere", "mie", "mie_terms", "bulk_optics", "SizeDistribution",
    "lee", "LeeTable", "drop_render", "drop_undistort", "rain", "RainResult", "RainRenderer", "builtin_scene",
    "lens_drops", "LensDropsResult", "detect_rain", "RainDetection", "remove_rain", "eval",
    "fog", "FogResult",
    "renderer_medium", "RendererMedium",
    "read_image", "write_image", "simd_target", "set_threads", "MieResult", "phase", "PhaseResult", "BulkOptics",
]


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

