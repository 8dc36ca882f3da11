"""Localisation as the last stage of a perceptor: what the session and the UI plug in.

    perceptor = LocalisingPerceptor(Perceptor(cfg.perception),
                                    Localiser(cfg.localisation, global_map, initial_pose))
    session = Session(sim, perceptor=perceptor, ...)   # wm.global_pose, lost, combined filled

Anything with `step(laser, odometry) -> WorldModel` can be wrapped; the wrapper keeps the
perceptor's interface (step, reset) so the session and the UI need not know it is there.
Scoring against a true pose is the session's observer `evaluation.PoseErrorScorer`.
"""

from __future__ import annotations

from typing import Any

from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.localisation import Localiser


class LocalisingPerceptor:
    def __init__(self, perceptor: Any, localiser: Localiser):
        self.perceptor = perceptor
        self.localiser = localiser

    def step(self, laser: LaserData | None, odometry: OdometryData | None) -> Any:
        wm = self.perceptor.step(laser, odometry)
        if wm is not None and laser is not None:
            self.localiser.fill(wm)
        return wm

    def reset(self) -> None:
        reset = getattr(self.perceptor, "reset", None)
        if reset is not None:
            reset()
        self.localiser.reset()

    def __getattr__(self, name: str) -> Any:
        # everything else (params, state, ...) is the wrapped perceptor's
        if name == "perceptor":
            raise AttributeError(name)
        return getattr(self.perceptor, name)
