"""The simulator's truth kept frame by frame, so a run's recorded frames can be scored again
later (another perceptor config over the same sensor stream, `sources.frames.FramesReplay`)
exactly as the live run was.

    keeper = TruthKeeper(sim)
    live = Session(sim, perceptor=p1, behaviour=b, observers=[keeper, TruthScorer(sim), keep])
    ...
    replay = FramesReplay([sf.frame for sf in keep.frames])
    scorer = TruthScorer(lambda: keeper.at(replay.index), vertices=keeper.vertices)
    Session(replay, perceptor=p2, observers=[scorer]).run(math.inf)

A `TruthSnapshot` answers the queries of `sim.truth` (`GroundTruth`) that scoring reads, from
arrays stored at that frame. When scoring reads a new query of the truth, add it here too
(and only then: the what-if sends every frame's snapshot to its scoring process; the scan's
own ray hits, 16 KB a frame, are not kept).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pico_studio.evaluation.frame_score import Pose, as_pose, static_vertices


class TruthSnapshot:
    def __init__(self, truth: Any, odometry_form: str):
        self.pose: Pose = as_pose(truth.pose)
        self.odometry_pose: Pose = as_pose(truth.odometry_pose)
        self.odometry_form = odometry_form
        self._segments = np.array(truth.segments())
        self._visible_walls = np.array(truth.visible_walls())
        self._visible_wall_sources = np.array(truth.visible_wall_sources())
        self._visible_corners = truth.visible_corners()
        self._door_openings = np.array(truth.door_openings())
        self._visible_doors = np.array(truth.visible_doors())
        self._dynamic_vertices = np.array(truth.dynamic_vertices())

    def segments(self) -> np.ndarray:
        return self._segments

    def visible_walls(self) -> np.ndarray:
        return self._visible_walls

    def visible_wall_sources(self) -> np.ndarray:
        return self._visible_wall_sources

    def visible_corners(self) -> Any:
        return self._visible_corners

    def door_openings(self) -> np.ndarray:
        return self._door_openings

    def visible_doors(self) -> np.ndarray:
        return self._visible_doors

    def dynamic_vertices(self) -> np.ndarray:
        return self._dynamic_vertices


class TruthKeeper:
    """A session observer keeping a `TruthSnapshot` of every frame with a new scan, by the
    frame's index; `vertices`: the static corners (for the end-point error)."""

    name = "kept_truth"

    def __init__(self, sim: Any):
        self.sim = sim
        self.vertices = static_vertices(sim)
        self.snapshots: dict[int, TruthSnapshot] = {}

    def on_frame(self, sf: Any) -> None:
        if sf.frame.laser is not None:
            self.snapshots[sf.index] = TruthSnapshot(self.sim.truth, self.sim.params.odometry.form)

    def at(self, index: int) -> TruthSnapshot:
        return self.snapshots[index]

    def summary(self) -> dict[str, Any]:
        return {"frames": len(self.snapshots)}
