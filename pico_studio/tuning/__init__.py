"""Auto-tuning against ground truth with Optuna: search space from the config declaration,
objective from the evaluation's metrics, a journal file or a database as the study's storage,
local worker processes, and a report.

    space = search_space(cfg, "perception.merge.*")
    spec = StudySpec(storage_url(None, out), "hospital", space, parse_objective(None), scenarios, cfg, trials=50)
    study = prepare(spec); run_workers(spec, 2); report = summarise(study, spec, out)
"""

from __future__ import annotations
