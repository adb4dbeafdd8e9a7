"""The scene: a rainbow in a daylight sky, per pixel on the CPU (``hydrolux sky``; docs/sky.md). Its
name is hydrolux's: ``hydrolux.sky`` (made in ``hydrolux._sky``).
"""
from __future__ import annotations

from hydrolux._sky import sky

__all__ = ["sky"]
