"""The PICO simulator: world, raycasting laser, holonomic base, odometry, doors, moving objects,
collisions and ground truth, behind the emc-IO shaped `RobotIO` interface.

    from pico_studio.sim import Simulator
    sim = Simulator.from_files("examples/maps/hospital_2019.json", seed=1)   # or a heightmap
    sim.send_base_reference(0.3, 0.0, 0.0); sim.advance(0.05)
    scan, odom = sim.read_laser(), sim.read_odometry()
    sim.truth.pose, sim.truth.visible_walls(), sim.truth.visible_corners(), sim.truth.visible_doors()

Modules: `world` (solid segments, doors, moving objects, free start place), `raycast` (the
laser fan), `laser`, `base` (kinematics, collisions), `odometry`, `doors`, `moving_objects`,
`sim_config` (the official simulator's config JSON), `map_features` (corners, door openings),
`truth`, `simulator`; `pico_studio.evaluation` compares a perceptor's world model with the truth.
"""

from __future__ import annotations

from pico_studio.sim.sim_config import (
    MovingObjectSpec,
    SimConfigFile,
    load_sim_config,
    sim_config_from_dict,
)
from pico_studio.sim.simulator import Simulator

__all__ = [
    "MovingObjectSpec",
    "SimConfigFile",
    "Simulator",
    "load_sim_config",
    "sim_config_from_dict",
]
