"""The reference map of a replay with true poses (the Intel corrected log) on the page's core,
without a browser: drawn where the scans end at their true poses, the local map's agreement
with it per frame and over the run, and nothing for a source without truth."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from pico_studio.config import Config
from pico_studio.core.geometry import transform_points
from pico_studio.json_map import load_json_map
from pico_studio.ui.reference_layer import agreement_text
from pico_studio.ui.replay import ReplayDriver
from pico_studio.ui.runtime import Studio
from pico_studio.ui.scene_data import frame_prims
from pico_studio.ui.sources import DEFAULT_MAP, make_source_factory


def test_the_reference_map_is_drawn_where_the_scans_end_and_the_local_map_agrees(recordings_dir: Path) -> None:
    studio = Studio(Config(), None, make_source_factory(f"carmen:{recordings_dir / 'intel-corrected.log.gz'}", None),
                    behaviour="stop", map_name="intel")
    assert studio.reference is not None and studio.reference.ready(timeout=120)
    driver = ReplayDriver(studio, every=10)
    studio.playing = True
    for _ in range(40):
        driver.step()
    frame = studio.shown()
    assert frame is not None and frame.wm is not None and frame.truth_pose is not None

    ref = frame_prims(studio, frame)["reference_map"].data
    assert len(ref) > 5000  # the building, not one room
    # this scan's returns at its true pose lie on the drawn reference (5 cm cells)
    ends = transform_points(frame.laser.points, frame.truth_pose)
    nearest = np.min(np.hypot(*(ends[:, None, :] - ref[None, ::1, :]).transpose(2, 0, 1)), axis=1)
    assert np.median(nearest) < 0.05

    figures = studio.metrics()["agreement"]
    # drift makes it well below 1 (the CLI reports 0.51 over the whole log), but most agrees early on
    assert figures["frame"] > 0.5 and figures["run"] > 0.5 and figures["frames"] >= 40
    assert "this frame 0." in agreement_text(figures) and "run so far" in agreement_text(figures)

    # the same local map placed 1 m off the true pose is judged off the reference
    moved = replace(frame, truth_pose=(frame.truth_pose[0] + 1.0, frame.truth_pose[1], frame.truth_pose[2]))
    assert studio.reference.frame_agreement(moved) < figures["frame"] - 0.3


def test_a_source_without_truth_has_no_reference_map() -> None:
    studio = Studio(Config(), load_json_map(DEFAULT_MAP), make_source_factory("sim", None, 2), map_name=DEFAULT_MAP.name)
    studio.tick(0.05)
    assert studio.reference is None
    assert len(frame_prims(studio, studio.shown())["reference_map"]) == 0
    assert studio.metrics()["agreement"] == {} and agreement_text({}) == ""
