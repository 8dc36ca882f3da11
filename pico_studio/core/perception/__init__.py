"""The perceptor's stages (one module each) and `perceive` / `Perceptor` (perceptor.py)."""

from __future__ import annotations

from pico_studio.core.perception.perceptor import STAGES, Perceptor, PerceptorState, perceive

__all__ = ["STAGES", "Perceptor", "PerceptorState", "perceive"]
