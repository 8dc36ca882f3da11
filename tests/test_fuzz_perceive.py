"""Hypothesis fuzzing of `perceive()`: scans with any ranges (NaN, inf, negative, huge),
any beam count, inconsistent angle fields and odometry that jumps or is not finite give a
valid world model — and never reach the "perceptor failed on this frame" safety net, which
is for bugs. Seeded (`derandomize=True`) and bounded."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pico_studio.config.perception_params import PerceptionParams
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.perception import PerceptorState, perceive
from pico_studio.core.world_model import WorldModel

FUZZ = settings(derandomize=True, max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
PARAMS = PerceptionParams()

odd = st.floats(allow_nan=True, allow_infinity=True)
ranges = st.one_of(
    st.lists(st.one_of(st.floats(0.0, 12.0), odd), min_size=0, max_size=60).map(np.array),
    st.integers(0, 1000).map(lambda n: np.full(n, 3.0)),
    st.integers(1, 1000).map(lambda n: 2.0 + np.sin(np.arange(n) / 7.0)),
)


@st.composite
def scans(draw: st.DrawFn) -> LaserData | None:
    if draw(st.integers(0, 9)) == 0:
        return None
    r = draw(ranges).astype(float)
    n = max(len(r), 1)
    a0 = draw(st.one_of(st.just(-2.0), odd))
    inc = draw(st.one_of(st.just(4.0 / n), st.floats(-0.1, 0.1), odd))
    a1 = draw(st.one_of(st.just(a0 + (n - 1) * inc if np.isfinite(a0 + (n - 1) * inc) else 2.0), odd))
    return LaserData(
        range_min=draw(st.one_of(st.just(0.01), odd)), range_max=draw(st.one_of(st.just(10.0), odd)),
        angle_min=a0, angle_max=a1, angle_increment=inc, timestamp=draw(st.one_of(st.floats(0, 100), odd)),
        ranges=r,
    )


odometry = st.one_of(
    st.none(),
    st.builds(OdometryData, st.floats(-5, 5), st.floats(-5, 5), st.floats(-4, 4), st.floats(0, 100)),
    st.builds(OdometryData, odd, odd, odd, odd),
)


@FUZZ
@given(st.lists(st.tuples(scans(), odometry), min_size=1, max_size=6))
def test_perceive_survives_any_frames(frames: list[tuple[LaserData | None, OdometryData | None]]) -> None:
    state = PerceptorState.initial()
    for laser, odom in frames:
        wm, state = perceive(state, laser, odom, PARAMS)
        assert isinstance(wm, WorldModel)
        failed = [w for w in wm.warnings if "perceptor failed" in w]
        assert not failed, failed
