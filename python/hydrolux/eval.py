"""Scores of rain detection and removal against the exact answer (``hydrolux rain-eval``;
docs/rain-detection.md): predicted masks against the rain's true alpha, and derained frames against the
clean ones.

Example:

>>> import hydrolux
>>> import numpy as np
>>> hydrolux.eval.score(np.ones((1, 2, 2), np.uint8), np.full((1, 2, 2), 0.5, np.float32))["overall"]["f1"]
1.0
"""
from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

from hydrolux import _core
from hydrolux._args import _declared, _with_options

_EVAL_PARAMS = _declared("rain_eval", "truth")
_EVAL_OPTIONS = tuple(p["name"] for p in _EVAL_PARAMS)


@_with_options(_EVAL_PARAMS, 4)
def score(predicted: Sequence[np.ndarray], truth_alpha: Sequence[np.ndarray],
          clean: Optional[Sequence[np.ndarray]] = None, derained: Optional[Sequence[np.ndarray]] = None,
          **options: Any) -> dict:
    """Predicted rain masks (nonzero = rain) against the true rain alpha (the renderer's mask), frame by
    frame: ``{"overall": {...}, "frames": [{...}, ...]}`` with precision, recall, f1, iou (None where
    undefined) and the counts, as ``hydrolux rain-eval --json``; with ``clean`` and ``derained`` (linear
    frames) also psnr_in_mask and psnr_out_mask (dB on the sRGB codes 0-255).

    Example:

    >>> import hydrolux
    >>> import numpy as np
    >>> truth = np.array([[[0.5, 0.0], [0.02, 0.0]]], dtype=np.float32)
    >>> pred = np.array([[[1, 1], [1, 0]]], dtype=np.uint8)
    >>> s = hydrolux.eval.score(pred, truth)
    >>> s["overall"]["precision"], s["overall"]["recall"], s["overall"]["ignored"]
    (0.5, 1.0, 1)
    """
    for k in options:
        if k not in _EVAL_OPTIONS:
            raise TypeError(f"unknown score option '{k}' (options: {', '.join(_EVAL_OPTIONS)})")
    return _core.score_rain(predicted, truth_alpha, clean, derained,
                            {k: v for k, v in options.items() if v is not None})
