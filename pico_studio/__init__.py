"""pico_studio: an interactive debugger for the PICO robot's laser perception and world model."""

from __future__ import annotations

__version__ = "0.1.0"
