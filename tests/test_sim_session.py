"""The headless session loop over the simulator."""

from __future__ import annotations

import numpy as np
import pytest
from sim_helpers import box_map, door_map

from pico_studio.core.io import BaseReference, Command, Frame, LaserData, OdometryData
from pico_studio.session import Session
from pico_studio.sim import Simulator


class NearestRange:
    """A tiny real perceptor: the nearest valid range of each scan."""

    def __init__(self) -> None:
        self.calls = 0

    def step(self, laser: LaserData, odometry: OdometryData | None) -> float:
        self.calls += 1
        r = laser.ranges
        return float(r[(r >= laser.range_min) & (r <= laser.range_max)].min())


class Steps:
    """A behaviour from a function of (time, world model), speaking the `step` protocol."""

    def __init__(self, fn) -> None:  # noqa: ANN001
        self.fn = fn

    def step(self, world_model, laser, odometry, now, *, ok=True):  # noqa: ANN001, ANN201
        return self.fn(now, world_model)


class ListRecorder:
    def __init__(self) -> None:
        self.rows: list[tuple[Frame, Command | None]] = []

    def record(self, frame: Frame, command: Command | None) -> None:
        self.rows.append((frame, command))


def test_session_perceives_behaves_records() -> None:
    sim = Simulator(box_map(), initial_pose=(2.0, 5.0, 0.0))
    perceptor, recorder = NearestRange(), ListRecorder()

    def stop_near_wall(now: float, nearest: float | None) -> Command:
        return Command(0.5 if nearest is None or nearest > 1.0 else 0.0)

    session = Session(sim, perceptor=perceptor, behaviour=Steps(stop_near_wall), recorder=recorder, history=50)
    session.run(30.0, 0.05)
    assert session.ticks == 600 and len(session.history) == 50  # bounded timeline
    assert perceptor.calls == 600  # a scan every 20 Hz tick
    x = sim.truth.pose[0]
    assert 8.9 < x < 9.05 and sim.truth.collisions == 0  # stopped by its own perception
    last = session.history[-1]
    assert last.world_model == pytest.approx(10.0 - x, abs=0.02)
    assert last.frame.truth["pose"] == sim.truth.pose
    assert len(recorder.rows) == 600 and recorder.rows[0][1] == Command(0.5)


def test_session_accepts_tuples_and_base_references_and_opens_doors() -> None:
    sim = Simulator(door_map(), initial_pose=(4.1, 4.5, 0.0))
    commands = iter([(0.0, 0.0, 0.5), BaseReference(0.0, 0.0, -0.5), Command(open_door=True)])
    session = Session(sim, behaviour=Steps(lambda now, wm: next(commands, None)))
    for _ in range(3):
        session.tick(0.1)
    session.tick(4.0)
    assert sim.truth.pose[2] == pytest.approx(0.0, abs=1e-12)  # +0.5 then -0.5 rad/s for 0.1 s each
    assert sim.world.doors[0].offset == pytest.approx(1.0)


def test_session_rejects_a_bad_command() -> None:
    session = Session(Simulator(box_map(), initial_pose=(5, 5, 0)), behaviour=Steps(lambda now, wm: "forward"))
    with pytest.raises(TypeError, match="behaviour must return"):
        session.tick(0.05)


def test_history_frames_keep_laser_and_odometry() -> None:
    session = Session(Simulator(box_map(), initial_pose=(5, 5, 0)))
    f = session.tick(0.05)
    assert f.frame.laser is not None and f.frame.odometry is not None
    assert np.isfinite(f.frame.laser.ranges).all()


def test_session_run_stops_when_the_source_closes() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    calls = []

    def close_after_ten(now: float, wm: object) -> None:
        calls.append(now)
        if len(calls) == 10:
            sim.close()

    assert Session(sim, behaviour=Steps(close_after_ten)).run(60.0, 0.05) == 10
    assert not sim.ok()
