"""The root of the config tree: one section per area, each declared in its own module.

Adding an area = declaring its section dataclass in a module of this package and adding one
`section(...)` line here. Sliders, YAML and validation pick it up from there.
"""

from __future__ import annotations

from dataclasses import dataclass

from pico_studio.config.behaviour_params import BehaviourParams
from pico_studio.config.localisation_params import LocalisationParams
from pico_studio.config.map_params import MapParams
from pico_studio.config.perception_params import PerceptionParams
from pico_studio.config.sim_params import SimParams
from pico_studio.config.sources_params import SourcesParams
from pico_studio.config.spec import section
from pico_studio.config.ui_params import UiParams


@dataclass(frozen=True)
class Config:
    map: MapParams = section(MapParams, "Map loading")
    sim: SimParams = section(SimParams, "The simulator")
    perception: PerceptionParams = section(PerceptionParams, "Perceptor: laser + odometry to world model")
    localisation: LocalisationParams = section(LocalisationParams, "Localisation in the global map and the combined map")
    sources: SourcesParams = section(SourcesParams, "Data sources: recordings and the live robot")
    ui: UiParams = section(UiParams, "The web UI (pico-studio serve)")
    behaviour: BehaviourParams = section(BehaviourParams, "Reference behaviours: escape room, room finder, hospital")
