"""The headless core: perceptor, world model, localisation, behaviours and the config tree.

Imports neither `pico_studio.sim` nor `pico_studio.ui`: data flows source -> perceptor ->
world model -> behaviour / UI / recorder.
"""

from __future__ import annotations
