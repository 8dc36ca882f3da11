"""The segmenter registry: one entry-point shape, names checked, a plugin's segmenter used."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from perception_scenes import SQUARE, scan_of

from pico_studio.config import Config
from pico_studio.config.spec import params
from pico_studio.core.perception.scan import process_scan
from pico_studio.core.perception.segment import (
    SEGMENTERS,
    register_segmenter,
    segment_scan,
    unregister_segmenter,
)
from pico_studio.errors import ConfigError

P = Config().perception


def _scan():
    scan, _ = process_scan(scan_of(SQUARE, (0.3, -0.2, 0.4), noise=0.0, seed=0), P.scan, P.proximity)
    return scan


def _with_segmenter(name: str):
    # dataclasses.replace skips the config's choice check, as a hand-built params object would
    return dataclasses.replace(P, scan=dataclasses.replace(P.scan, segmenter=name))


def test_the_config_offers_exactly_the_registered_builtins() -> None:
    spec = next(p.spec for p in params(Config()) if p.path == "perception.scan.segmenter")
    assert spec.choices is not None
    assert set(spec.choices) == set(SEGMENTERS)


@pytest.mark.parametrize("name", sorted(SEGMENTERS))
def test_every_builtin_returns_inclusive_pieces_inside_one_cluster(name: str) -> None:
    scan = _scan()
    pieces = SEGMENTERS[name](scan.points, scan.clusters, P)
    assert pieces.ndim == 2 and pieces.shape[1] == 2 and len(pieces) >= 3
    assert (pieces[:, 0] <= pieces[:, 1]).all()
    cid = np.searchsorted(scan.clusters[:, 0], pieces[:, 0], side="right") - 1
    assert (pieces[:, 1] < scan.clusters[cid, 1]).all()


def test_an_unknown_segmenter_is_a_config_error_naming_the_field() -> None:
    with pytest.raises(ConfigError) as err:
        segment_scan(_scan(), _with_segmenter("no_such_segmenter"))
    assert err.value.field == "perception.scan.segmenter"
    assert "split_merge" in str(err.value)


def test_a_registered_segmenter_is_the_one_that_runs() -> None:
    def longest_only(points: np.ndarray, clusters: np.ndarray, params) -> np.ndarray:
        # split-and-merge's pieces, of which only the one with most points: easy to spot
        pieces = SEGMENTERS["split_merge"](points, clusters, params)
        return pieces[np.argmax(pieces[:, 1] - pieces[:, 0])][None, :]

    register_segmenter("longest_only", longest_only)
    try:
        with pytest.raises(ValueError):
            register_segmenter("longest_only", longest_only)
        segs = segment_scan(_scan(), _with_segmenter("longest_only"))
    finally:
        unregister_segmenter("longest_only")
    assert len(segs.segments) == 1
    assert len(segment_scan(_scan(), P).segments) >= 3  # the three walls in view
