"""`pico-studio render`: the page's layers drawn headless with OpenCV into a video or image."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.sources import open_source
from pico_studio.ui import style


def test_render_writes_one_video_frame_per_scan_in_the_window(recordings_dir: Path, tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    bag = recordings_dir / "pico_real_2019-05-07.bag"
    out = tmp_path / "replay.mp4"
    assert main(["render", "--source", f"bag:{bag}", "--from", "1", "--to", "2.5", "--width", "400", "--out", str(out)]) == 0
    times = open_source(f"bag:{bag}").frame_times
    rel = times - times[0]
    expected = int(((rel >= 1.0 - 1e-9) & (rel <= 2.5 + 1e-9)).sum())
    video = cv2.VideoCapture(str(out))
    frames = 0
    while video.read()[0]:
        frames += 1
    assert frames == expected > 20
    assert f"({expected} frames" in capsys.readouterr().out


def test_render_a_simulated_run_to_png_and_gif(tmp_path: Path) -> None:
    png, gif = tmp_path / "last.png", tmp_path / "run.gif"
    maps = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps" / "hospital_2019.json"
    assert main(["render", "--map", str(maps), "--to", "1", "--seed", "1", "--width", "500", "--out", str(png)]) == 0
    img = cv2.imread(str(png))[:, :, ::-1]
    walls = (np.abs(img.astype(int) - np.array(style.MAP_WALL)).max(axis=-1) < 20).sum()
    laser = (np.abs(img.astype(int) - np.array(style.LASER)).max(axis=-1) < 20).sum()
    assert img.shape[1] == 500 and walls > 500 and laser > 20
    assert main(["render", "--map", str(maps), "--to", "0.5", "--seed", "1", "--width", "300", "--out", str(gif)]) == 0
    assert gif.read_bytes()[:6] == b"GIF89a"


def test_render_bad_arguments_are_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["render", "--out", str(tmp_path / "x.mp4")]) == 2
    assert "--map" in capsys.readouterr().err
    assert main(["render", "--source", "bag:nothing.bag", "--out", str(tmp_path / "x.avi")]) == 2
    assert ".mp4" in capsys.readouterr().err
    assert main(["render", "--source", "bag:nothing.bag", "--from", "3", "--to", "1", "--out", str(tmp_path / "x.png")]) == 2
    assert "--to" in capsys.readouterr().err


def test_the_map_layer_draws_the_maps_door_openings(maps_dir: Path, tmp_path: Path) -> None:
    """The global-map layer carries the map's door openings (`GlobalMap.openings`, what the
    combined map confirms a door against and the truth scores), restaurant_2024's T-opening by
    the block at x = 4.7 among them; no map, none."""
    from pico_studio.json_map import load_map
    from pico_studio.ui.scene_data import map_prims

    m = load_map(maps_dir / "restaurant_2024.json")
    prims = map_prims(m)
    assert np.array_equal(prims["map_openings"].data, m.openings()) and len(m.openings()) >= 2
    assert any(np.allclose(o, [4.7, 1.2, 4.7, 0.2], atol=0.05) or np.allclose(o, [4.7, 0.2, 4.7, 1.2], atol=0.05)
               for o in m.openings())
    assert map_prims(None)["map_openings"].data.shape == (0, 4)
