"""The package's names: what ``import hydrolux`` gave when the package was one file
(python/hydrolux/__init__.py, 1,526 lines, before its split into optics, scatter, atmos, drop, rain and
io) it still gives, each the same kind of thing; pickles made then still load; the module named
``rain`` does not hide the function ``hydrolux.rain`` nor the batch job ``hydrolux.batch.rain``."""
import inspect
import pickle
import subprocess
import sys
from typing import Sequence, Union

import numpy as np

import hydrolux as h

# dir(hydrolux)'s public names before the split, as they were.
BEFORE = ['Any', 'ArrayLike', 'BulkOptics', 'FogResult', 'LeeTable', 'LensDropsResult', 'MieResult', 'NamedTuple',
          'Optional', 'PhaseResult', 'RainRenderer', 'RainResult', 'RendererMedium', 'Sequence', 'SizeDistribution',
          'Tuple', 'Union', 'annotations', 'builtin_scene', 'bulk_optics', 'drop_render', 'drop_undistort', 'fog',
          'fresnel', 'functools', 'inspect', 'lee', 'lens_drops', 'math', 'media', 'mie', 'mie_terms', 'np', 'os',
          'phase', 'rain', 'read_image', 'refractive_index', 'renderer_medium', 'set_threads', 'simd_target',
          'sphere', 'warnings', 'write_image']
# Of those, the one file's own imports (PEP 8: "imported names should always be considered an
# implementation detail"): each module now imports what it uses.
IMPORTED = {'Any', 'NamedTuple', 'Optional', 'Sequence', 'Tuple', 'Union', 'annotations', 'functools', 'inspect',
            'math', 'np', 'os', 'warnings'}
# __all__ before the split, in its order (the documentation's check and `from hydrolux import *` read it).
ALL = ["fresnel", "media", "refractive_index", "sphere", "mie", "mie_terms", "bulk_optics", "SizeDistribution",
       "lee", "LeeTable", "drop_render", "drop_undistort", "rain", "RainResult", "RainRenderer", "builtin_scene",
       "lens_drops", "LensDropsResult", "fog", "FogResult", "renderer_medium", "RendererMedium",
       "read_image", "write_image", "simd_target", "set_threads", "MieResult", "phase", "PhaseResult", "BulkOptics"]
CLASSES = {"SizeDistribution", "LeeTable", "RainResult", "RainRenderer", "LensDropsResult", "FogResult",
           "RendererMedium", "MieResult", "PhaseResult", "BulkOptics"}


def test_every_public_name_of_the_one_file_package_is_still_there():
    missing = [n for n in BEFORE if n not in IMPORTED and not hasattr(h, n)]
    assert not missing, f"hydrolux lost {missing}"
    assert [n for n in h.__all__ if n in ALL] == ALL  # later names (hydrolux.sky) may join it
    for n in ALL:
        obj = getattr(h, n)
        assert inspect.isclass(obj) == (n in CLASSES), n
        assert n in CLASSES or inspect.isfunction(obj), n
        assert obj.__name__ == n and obj.__qualname__ == n, n
    assert isinstance(h.__version__, str) and h.__version__.count(".") == 2
    assert h.ArrayLike == Union[float, Sequence[float], np.ndarray]


def test_the_private_names_others_use_are_still_there():
    assert inspect.ismodule(h._core) and inspect.ismodule(h._xarray)
    assert callable(h._image_module)  # the tests map OpenImageIO's libraries through it
    assert callable(h._remake_distribution)  # what a SizeDistribution pickled before the split names


def test_star_import_gives_all():
    scope = {}
    exec("from hydrolux import *", scope)
    assert sorted(k for k in scope if k != "__builtins__") == sorted(h.__all__)


def test_rain_is_the_function_and_its_module_is_found():
    import hydrolux.batch.rain as batch_rain
    assert inspect.isfunction(h.rain) and h.rain.__module__ == "hydrolux.rain"
    assert sys.modules["hydrolux.rain"].rain is h.rain
    from hydrolux.rain import RainRenderer
    assert RainRenderer is h.RainRenderer
    assert inspect.ismodule(batch_rain) and batch_rain.__name__ == "hydrolux.batch.rain"
    help_text = subprocess.run([sys.executable, "-m", "hydrolux.batch", "rain", "--help"], capture_output=True,
                               text=True)
    assert help_text.returncode == 0 and "--rain-rate-mmh" in help_text.stdout, help_text.stderr


def test_the_io_module_leaves_the_standard_io_alone():
    import io
    assert io.StringIO and h.io.read_image is h.read_image and h.io is not io


# Pickles made by the one-file package (protocol 4): the classes and the distribution's remaker by
# the names they had then (hydrolux.SizeDistribution's hydrolux._remake_distribution, hydrolux.BulkOptics,
# hydrolux.RainRenderer, hydrolux.MieResult).
OLD_PICKLES = {
    "gamma": "8004954e000000000000008c08687964726f6c7578948c145f72656d616b655f646973747269627574696f6e9493948c05"
             "67616d6d6194473ee4f8b588e368f1473fc999999999999a474197d784000000008794869452942e",
    "bulk": "8004957b010000000000008c08687964726f6c7578948c0a42756c6b4f7074696373949394298194288c10657874696e6374"
            "696f6e5f7065725f6d94473fb15e1404cb507e8c1073636174746572696e675f7065725f6d94473fb15e1404cb507e8c10616273"
            "6f727074696f6e5f7065725f6d944700000000000000008c116261636b736361747465725f7065725f6d94473f99caa4838593"
            "3e8c016794473febeaf4ff01962a757d948c057365747570947d94288c016d948c086275696c74696e73948c07636f6d706c65"
            "78949394473ff553f7ced91687470000000000000000869452948c0d776176656c656e6774685f6e6d944740813000000000008c"
            "0c646973747269627574696f6e9468008c145f72656d616b655f646973747269627574696f6e9493948c0567616d6d6194473ee4"
            "f8b588e368f1473fc999999999999a474197d784000000008794869452948c056e6f646573944b088c0c6d656469756d5f696e"
            "64657894473ff00000000000008c07686973746f7279948c0178947573622e",
    "renderer": "80049550000000000000008c08687964726f6c7578948c0c5261696e52656e6465726572949394298194284b404b30887d94"
                "288c08726174655f6d6d68944b198c0877696e645f6d7073944b038c0473656564944b04757494622e",
    "mie": "80049555000000000000008c08687964726f6c7578948c094d6965526573756c7494939428473ff00000000000004740000000"
           "000000004740080000000000004740100000000000004740140000000000004b064e4e4e4e4e4e4e749481942e",
}


def test_pickles_made_before_the_split_load():
    old = {k: pickle.loads(bytes.fromhex(v)) for k, v in OLD_PICKLES.items()}
    fog = h.SizeDistribution.gamma(1e-5, 0.2, 1e8)
    assert isinstance(old["gamma"], h.SizeDistribution) and old["gamma"].parameters == fog.parameters
    for a, b in zip(old["gamma"].quadrature(16), fog.quadrature(16)):
        assert a.tobytes() == b.tobytes()
    bulk = h.bulk_optics(1.333, 550, fog, nodes=8)
    assert isinstance(old["bulk"], h.BulkOptics) and old["bulk"] == bulk
    assert old["bulk"].setup["distribution"].parameters == fog.parameters
    renderer = h.RainRenderer(64, 48, rain_rate_mmh=25, wind_mps=3, seed=4)
    assert isinstance(old["renderer"], h.RainRenderer) and old["renderer"].field_info() == renderer.field_info()
    scene = h.builtin_scene(64, 48)
    np.testing.assert_array_equal(old["renderer"].render(scene, frame_index=2).image,
                                  renderer.render(scene, frame_index=2).image)
    assert old["mie"] == h.MieResult(1.0, 2.0, 3.0, 4.0, 5.0, 6, None, None)
    assert type(old["mie"]) is h.MieResult


def test_pickles_made_now_load_as_the_same_objects():
    for obj in (h.SizeDistribution.marshall_palmer(5.0), h.RainRenderer(32, 24, seed=1),
                h.mie(1.333, [1.0], angles_deg=[0, 90])):
        copy = pickle.loads(pickle.dumps(obj))
        assert type(copy) is type(obj)
