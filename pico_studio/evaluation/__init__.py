"""Everything that scores perception, localisation and behaviour against ground truth.

One package, one scorer: the session loop (`pico_studio.session.Session.frames`) yields
frames, the observers here judge them.

- `frame_score`: one world model against the simulator's truth (`score_frame`, `Tolerances`).
- `run_score`: running sums over a run (`RunScore`, `PoseScore`) and their observers
  (`TruthScorer`, `PoseErrorScorer`).
- `judges`: behaviour outcomes (`EscapeJudge`, `CabinetsVisited`, `RoomsCounted`).
- `metrics`: flat dotted metric names (`METRICS`, `flatten`) and the default objective
  `perception_score`.
- `poses`: random free poses of a map (the eval method's starts).
- `worlds`: seeded generated worlds (`escape:SEED`, `rooms:SEED`; furnished, with people:
  `hall:SEED`, `cafe:SEED`, `ward:SEED`, `suite:SEED` from `furnished_worlds`).
- `scenarios` / `runner`: scenario-set YAML files and running them (`evaluate_scenarios`).
"""

from __future__ import annotations
