"""The search space comes from the config declaration: ranges, steps, choices, bools, log."""

from __future__ import annotations

import optuna
import pytest

from pico_studio.config import Config, params
from pico_studio.errors import ConfigError
from pico_studio.tuning.space import search_space


def test_every_dimension_is_a_declared_parameter_with_its_range():
    cfg = Config()
    declared = {p.path: p.spec for p in params(cfg)}
    space = search_space(cfg, "perception.*")
    assert len(space.dimensions) > 40
    for d in space.dimensions:
        spec = declared[d.path]
        if spec.kind in ("bool", "choice"):
            assert set(d.choices) == ({False, True} if spec.kind == "bool" else set(spec.choices))
        else:
            assert (d.lo, d.hi) == (spec.lo, spec.hi)
            assert d.log == (spec.lo > 0 and spec.hi / spec.lo >= 100)
            if not d.log and spec.kind == "float":
                assert d.step == spec.step


def test_kinds_and_log_scale():
    space = {d.path: d for d in search_space(Config(), "perception.*").dimensions}
    assert space["perception.scan.segmenter"].kind == "choice"
    assert space["perception.locate.laser_motion_without_odometry"].kind == "bool"
    assert space["perception.merge.max_walls"].kind == "int" and space["perception.merge.max_walls"].log
    assert not space["perception.merge.angle"].log  # 0 .. 1: no log scale through zero


def test_globs_union_without_repeats_and_suggested_values_validate():
    space = search_space(Config(), "perception.merge.*,perception.merge.angle,perception.identify.door_*")
    assert len(space.paths) == len(set(space.paths))
    assert "perception.merge.angle" in space.paths and "perception.identify.door_angle" in space.paths
    study = optuna.create_study(sampler=optuna.samplers.RandomSampler(seed=1))
    for _ in range(60):  # door_min_width is sampled below door_max_width: no trial is refused
        trial = study.ask()
        values = space.suggest(trial)
        cfg = space.apply(Config(), values)
        assert cfg.perception.merge.angle == values["perception.merge.angle"]
        assert cfg.perception.identify.door_min_width < cfg.perception.identify.door_max_width


@pytest.mark.parametrize("sampler", [optuna.samplers.RandomSampler(seed=3), optuna.samplers.TPESampler(seed=3)])
def test_an_ordered_chain_is_kept_and_a_fixed_sibling_bounds_its_partner(sampler):
    # quality_lost <= quality_found <= quality_confirm, all three searched
    space = search_space(Config(), "localisation.tracker.quality_*")
    study = optuna.create_study(sampler=sampler)
    for _ in range(40):
        trial = study.ask()
        t = space.apply(Config(), space.suggest(trial)).localisation.tracker
        assert t.quality_lost <= t.quality_found <= t.quality_confirm
        study.tell(trial, t.quality_found)
    # only the upper side searched: the lower side's base value bounds it
    only_max = search_space(Config(), "perception.identify.door_max_width")
    base = Config().perception.identify.door_min_width
    seen = [only_max.suggest(optuna.create_study().ask())["perception.identify.door_max_width"]
            for _ in range(30)]
    assert min(seen) > base


def test_every_declared_order_names_a_sibling_of_its_kind():
    cfg = Config()
    declared = {p.path: p for p in params(cfg)}
    orders = [(p, p.spec.upper) for p in declared.values() if p.spec.upper is not None]
    assert len(orders) >= 6
    for p, (other, _strict) in orders:
        sibling = declared[p.path.rsplit(".", 1)[0] + "." + other]
        assert sibling.spec.kind == p.spec.kind
        assert sibling.spec.upper is None or sibling.spec.upper[0] != p.name  # no two-cycle


def test_a_violated_order_names_the_field_and_its_sibling():
    from pico_studio.config import loads_yaml

    with pytest.raises(ConfigError, match=r"quality_lost.*at most quality_found"):
        loads_yaml(Config, "localisation:\n  tracker:\n    quality_lost: 0.9\n")


def test_the_start_config_is_the_first_point():
    cfg = space_cfg = Config()
    space = search_space(space_cfg, "perception.merge.*")
    assert space.start_params(cfg)["perception.merge.confirm_hits"] == cfg.perception.merge.confirm_hits
    assert space.apply(cfg, space.start_params(cfg)) == cfg


@pytest.mark.parametrize("glob", ["perception.nothing.*", "sim.*", "sources.bag.*"])
def test_a_glob_matching_nothing_tunable_names_it(glob):
    with pytest.raises(ConfigError, match=glob.replace(".", r"\.").replace("*", r"\*")):
        search_space(Config(), glob)


def test_fingerprint_changes_with_the_space():
    a = search_space(Config(), "perception.merge.*")
    assert a.fingerprint() == search_space(Config(), "perception.merge.*").fingerprint()
    assert a.fingerprint() != search_space(Config(), "perception.identify.*").fingerprint()
