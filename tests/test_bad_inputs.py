"""A table of bad inputs through the CLI: every format and every number argument, each with
its expected outcome — refused (exit 2, one line naming the file/field, a fragment of it
checked) or accepted with a warning — and each bounded: 5 s and an address-space limit.

The bad files are generated into a temporary directory. The table runs in worker
processes (tests/bad_inputs_worker.py, a chunk of cases each, under `RLIMIT_AS`), every
case under its own timers: 5 s of CPU, and 60 s of wall time for a case that would block
(the machine is shared: wall time under load says little about the work a case does). The
worst cases of issue 18 also run one by one as real `python -m pico_studio` subprocesses
with the same bounds (their CPU time read from `wait4`, start-up included).
"""

from __future__ import annotations

import gzip
import json
import os
import resource
import socket
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
MAPS = ROOT / "examples" / "maps"
REC = ROOT / "tests" / "data" / "recordings"
HOSPITAL = str(MAPS / "hospital_2019.json")
TIMEOUT_S = 5.0  # CPU seconds a case may take (what it costs, whatever the machine's load)
WALL_TIMEOUT_S = 60.0  # and wall seconds: a case that blocks (a FIFO opened) costs no CPU
MEMORY_LIMIT = 3 << 30  # address space: numpy, OpenCV and rosbags take ~1 GB of it idle
CHUNK = 20  # cases per worker process


@dataclass(frozen=True)
class Case:
    id: str
    argv: list[str]  # "{d}" is the directory of the generated files
    refused: str | None = None  # a fragment of the one-line error (exit 2)
    warning: str | None = None  # accepted (exit 0) with this fragment in the output
    env: dict[str, str] = field(default_factory=dict)


def refuse(id: str, argv: list[str], fragment: str, **kw: Any) -> Case:
    return Case(id, argv, refused=fragment, **kw)


def warn(id: str, argv: list[str], fragment: str, **kw: Any) -> Case:
    return Case(id, argv, warning=fragment, **kw)


# ----- the bad files ---------------------------------------------------------------------------
def _png_chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png(width: int, height: int, idat: bytes | None = None, *, colour: int = 0) -> bytes:
    """A PNG claiming width x height 8-bit pixels; its data is a small zlib stream unless
    given (the header is the attack: decoders allocate from it)."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, colour, 0, 0, 0)
    idat = zlib.compress(b"\0" * 1000) if idat is None else idat
    return b"\x89PNG\r\n\x1a\n" + _png_chunk(b"IHDR", ihdr) + _png_chunk(b"IDAT", idat) + _png_chunk(b"IEND", b"")


def png_image(pixels: np.ndarray) -> bytes:
    import cv2

    ok, buf = cv2.imencode(".png", pixels)
    assert ok
    return buf.tobytes()


def jmap(points: list[tuple[Any, Any]], walls: list[list[Any]], **extra: Any) -> str:
    return json.dumps({"points": [{"x": x, "y": y} for x, y in points], "walls": walls, **extra})


SQUARE = [(0, 0), (4, 0), (4, 4), (0, 4)]
SQUARE_WALLS = [[0, 1], [1, 2], [2, 3], [3, 0]]
BIG_INT = "9" * 400  # valid JSON/YAML, but too large for a float
HUGE_INT = "9" * 5000  # beyond Python's 4300-digit int parsing limit


def laughs() -> str:
    """A YAML alias bomb as one value: 9^9 strings once expanded (printed in full, never ends)."""
    levels = ['&a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for prev, name in zip("abcdefgh", "bcdefghi", strict=True):
        levels.append(f"&{name} [" + ",".join(f"*{prev}" for _ in range(9)) + "]")
    return "sim:\n  seed: [" + ", ".join(levels) + "]\n"


def make_files(d: Path) -> None:
    """Every bad file the table names, written into `d`."""
    def text(name: str, body: str) -> None:
        (d / name).write_text(body, encoding="utf-8")

    def raw(name: str, body: bytes) -> None:
        (d / name).write_bytes(body)

    os.mkfifo(d / "fifo.json")
    os.mkfifo(d / "fifo.yaml")
    os.mkfifo(d / "fifo.png")
    os.mkfifo(d / "fifo.bag")
    os.mkfifo(d / "fifo.log")
    os.mkfifo(d / "out_fifo.png")
    os.mkfifo(d / "sibling.yaml")
    (d / "dir.json").mkdir()
    (d / "dir.yaml").mkdir()
    (d / "dir.png").mkdir()
    (d / "dir.bag").mkdir()
    (d / "dir.log").mkdir()
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    sock.bind(str(d / "sock.json"))
    sock.close()
    for ext in ("json", "yaml", "png", "pgm", "bag", "log"):
        raw(f"empty.{ext}", b"")
        raw(f"junk.{ext}", bytes(np.random.default_rng(1).integers(0, 256, 4096, dtype=np.uint8)))
    raw("latin1.json", "{\"points\": \"\xe9\"}".encode("latin-1"))
    raw("latin1.yaml", "sim:\n  seed: \xe9\n".encode("latin-1"))
    raw("big.json", b" " * (2 << 20))  # 2 MB: over a 1 MB cap set through the environment
    raw("big.yaml", b"#" * (2 << 20))

    # JSON maps
    text("deep.json", "[" * 100_000 + "]" * 100_000)
    text("deep_ok_prefix.json", '{"points": ' + "[" * 70 + "]" * 70 + ', "walls": []}')
    text("top_list.json", "[1, 2, 3]")
    text("top_string.json", '"a map"')
    text("truncated.json", jmap(SQUARE, SQUARE_WALLS)[:-10])
    text("trailing.json", jmap(SQUARE, SQUARE_WALLS) + " trailing")
    text("bom.json", "\ufeff" + jmap(SQUARE, SQUARE_WALLS))
    text("no_points.json", '{"walls": [[0, 1]]}')
    text("points_dict.json", '{"points": {"x": 1}, "walls": []}')
    text("point_list.json", '{"points": [[0, 0]], "walls": []}')
    text("point_no_x.json", '{"points": [{"y": 0}], "walls": []}')
    text("point_x_str.json", jmap([("1", 0), (1, 1)], [[0, 1]]))
    text("point_x_bool.json", jmap([(True, 0), (1, 1)], [[0, 1]]))
    text("point_x_nan.json", '{"points": [{"x": NaN, "y": 0}, {"x": 1, "y": 1}], "walls": [[0, 1]]}')
    text("point_x_inf.json", '{"points": [{"x": Infinity, "y": 0}, {"x": 1, "y": 1}], "walls": [[0, 1]]}')
    text("point_x_1e308.json", jmap([(1e308, 0), (0, 1), (1, 1)], [[0, 1], [1, 2]]))
    text("point_x_neg_far.json", jmap([(-20000.5, 0), (0, 1)], [[0, 1]]))
    text("point_x_bigint.json", '{"points": [{"x": ' + BIG_INT + ', "y": 0}, {"x": 1, "y": 1}], "walls": [[0, 1]]}')
    text("point_x_hugeint.json", '{"points": [{"x": ' + HUGE_INT + ', "y": 0}], "walls": []}')
    text("no_walls.json", '{"points": [{"x": 0, "y": 0}]}')
    text("walls_empty.json", jmap(SQUARE, []))
    text("walls_dict.json", jmap(SQUARE, {"a": 1}))  # type: ignore[arg-type]
    text("wall_index_range.json", jmap(SQUARE, [[0, 9]]))
    text("wall_index_negative.json", jmap(SQUARE, [[0, -1]]))
    text("wall_index_float.json", jmap(SQUARE, [[0, 1.5]]))
    text("wall_index_bigint.json", '{"points": [{"x": 0, "y": 0}], "walls": [[0, ' + BIG_INT + "]]}")
    text("wall_triple.json", jmap(SQUARE, [[0, 1, 2]]))
    text("wall_zero_length.json", jmap([(0, 0), (0, 0), (1, 1)], [[0, 1], [1, 2]]))
    text("cabinets_and_tables.json", jmap(SQUARE, SQUARE_WALLS, cabinets=[], tables=[]))
    text("polygon_open.json", jmap(SQUARE, SQUARE_WALLS, cabinets=[[[0, 1], [1, 2], [2, 3]]]))
    text("polygon_two.json", jmap(SQUARE, SQUARE_WALLS, doors=[[[0, 1], [1, 0]]]))
    text("polygon_not_list.json", jmap(SQUARE, SQUARE_WALLS, start_area="here"))
    text("dup_points.json", jmap([*SQUARE, (0, 0)], [*SQUARE_WALLS, [4, 1]]))
    text("unused_points.json", jmap([*SQUARE, (9, 9)], SQUARE_WALLS))
    text("dup_walls.json", jmap(SQUARE, [*SQUARE_WALLS, [1, 0]]))
    text("bowtie.json", jmap([(0, 0), (2, 2), (2, 0), (0, 2)], SQUARE_WALLS))
    text(
        "bowtie_cabinet.json",
        jmap([*SQUARE, (1, 1), (2, 2), (2, 1), (1, 2)], SQUARE_WALLS, cabinets=[[[4, 5], [5, 6], [6, 7], [7, 4]]]),
    )
    text("wide_point.json", '{"points": [' + ", ".join(["[1]"] * 100_000) + '], "walls": []}')

    # heightmap images and map_server YAMLs
    raw("png_20000.png", png(20000, 20000))
    raw("png_65535.png", png(65535, 65535))
    raw("png_zero.png", png(0, 10))
    raw("png_truncated.png", png(100, 100)[:20])
    raw("png_magic_only.png", b"\x89PNG\r\n\x1a\n")
    raw("png_bad_ihdr.png", b"\x89PNG\r\n\x1a\n" + _png_chunk(b"IHDX", b"\0" * 13))
    good = png_image(np.pad(np.full((30, 30), 255, np.uint8), 5))
    raw("png_bad_crc.png", good[:-20] + b"\0" * 20)
    raw("png_cut_idat.png", good[: len(good) // 2])
    raw("png_white.png", png_image(np.full((50, 50), 255, np.uint8)))
    raw("png_specks.png", png_image(np.where(np.random.default_rng(2).random((60, 60)) < 0.01, 0, 255).astype(np.uint8)))
    raw("png_text.png", b"this is not an image\n")
    raw("pgm_2e9.pgm", b"P5\n2000000000 2000000000\n255\n" + b"\0" * 100)
    raw("pgm_comment.pgm", b"P5\n# made by hand\n30000 30000\n255\n" + b"\0" * 100)
    raw("pgm_zero.pgm", b"P5\n0 0\n255\n")
    raw("pgm_no_size.pgm", b"P5\n")
    raw("pgm_short.pgm", b"P5\n100 100\n255\n" + b"\0" * 10)
    raw("pgm_ok.pgm", b"P5\n40 40\n255\n" + np.pad(np.full((30, 30), 255, np.uint8), 5).tobytes())
    raw("ok.png", good)

    def ms(name: str, body: str) -> None:
        text(name, body)

    ms("ms_no_image.yaml", "resolution: 0.05\norigin: [0, 0, 0]\n")
    ms("ms_missing_image.yaml", "image: nothere.png\nresolution: 0.05\n")
    ms("ms_res_zero.yaml", "image: ok.png\nresolution: 0\n")
    ms("ms_res_negative.yaml", "image: ok.png\nresolution: -0.05\n")
    ms("ms_res_text.yaml", "image: ok.png\nresolution: abc\n")
    ms("ms_res_huge.yaml", "image: ok.png\nresolution: 1.0e+9\n")
    ms("ms_res_nan.yaml", "image: ok.png\nresolution: .nan\n")
    ms("ms_origin_short.yaml", "image: ok.png\nresolution: 0.05\norigin: [0]\n")
    ms("ms_origin_nan.yaml", "image: ok.png\nresolution: 0.05\norigin: [.nan, 0, 0]\n")
    ms("ms_origin_far.yaml", "image: ok.png\nresolution: 0.05\norigin: [0, 1.0e+12, 0]\n")
    ms("ms_negate.yaml", "image: ok.png\nresolution: 0.05\nnegate: 2\n")
    ms("ms_thresholds.yaml", "image: ok.png\nresolution: 0.05\noccupied_thresh: 0.1\nfree_thresh: 0.5\n")
    ms("ms_duplicate.yaml", "image: ok.png\nresolution: 0.05\nresolution: 0.1\n")
    ms("ms_deep.yaml", "image: " + "[" * 5000 + "]" * 5000 + "\n")
    ms("ms_list.yaml", "- image\n- ok.png\n")
    ms("ms_image_dir.yaml", "image: dir.png\nresolution: 0.05\n")
    ms("ms_image_fifo.yaml", "image: fifo.png\nresolution: 0.05\n")
    ms("ms_image_dev.yaml", "image: /dev/zero\nresolution: 0.05\n")
    ms("ms_image_huge.yaml", "image: png_20000.png\nresolution: 0.05\n")
    ms("ms_syntax.yaml", "image: [ok.png\nresolution: 0.05\n")

    # config YAMLs
    text("cfg_duplicate.yaml", "sim:\n  seed: 1\n  seed: 2\n")
    text("cfg_dup_section.yaml", "sim:\n  seed: 1\nmap: {}\nsim:\n  seed: 2\n")
    text("cfg_deep.yaml", "sim: " + "[" * 100_000 + "]" * 100_000 + "\n")
    text("cfg_deep_block.yaml", "".join("  " * i + f"k{i}:\n" for i in range(200)))
    text("cfg_seed_huge.yaml", f"sim:\n  seed: {HUGE_INT}\n")
    text("cfg_seed_400.yaml", f"sim:\n  seed: {BIG_INT}\n")
    text("cfg_seed_90.yaml", "sim:\n  seed: " + "9" * 90 + "\n")
    text("cfg_seed_negative.yaml", "sim:\n  seed: -1\n")
    text("cfg_seed_float.yaml", "sim:\n  seed: 1.5\n")
    text("cfg_seed_text.yaml", "sim:\n  seed: abc\n")
    text("cfg_seed_bool.yaml", "sim:\n  seed: true\n")
    text("cfg_seed_list.yaml", "sim:\n  seed: [1, 2]\n")
    text("cfg_seed_long_text.yaml", "sim:\n  seed: " + "x" * 100_000 + "\n")
    text("cfg_laughs.yaml", laughs())
    text("cfg_unknown_key.yaml", "sim:\n  sead: 1\n")
    text("cfg_unknown_section.yaml", "simulation:\n  seed: 1\n")
    text("cfg_section_scalar.yaml", "sim: 3\n")
    text("cfg_top_list.yaml", "- sim\n- map\n")
    text("cfg_nan.yaml", "map:\n  heightmap:\n    resolution: .nan\n")
    text("cfg_inf.yaml", "map:\n  heightmap:\n    resolution: .inf\n")
    text("cfg_range.yaml", "map:\n  heightmap:\n    resolution: 1000\n")
    text("cfg_tab.yaml", "sim:\n\tseed: 1\n")
    text("cfg_syntax.yaml", "sim: {seed: 1\n")
    text("cfg_python_tag.yaml", "sim: !!python/object/apply:os.system ['true']\n")
    text("cfg_comments.yaml", "# nothing but a comment\n")
    text("cfg_key_list.yaml", "? [a, b]\n: 1\n")

    # simulator config JSONs (with hospital_2019: x 0..~7, y 0..~7)
    def sim(name: str, body: Any) -> None:
        text(name, body if isinstance(body, str) else json.dumps(body))

    obj = {"length": 1.0, "width": 0.5, "init_pose": [1, 1, 0], "final_pose": [2, 1, 0],
           "velocity": 0.5, "trigger_radius": 1.0}
    sim("sim_list.json", [1])
    sim("sim_deep.json", "[" * 100_000 + "]" * 100_000)
    sim("sim_pose_short.json", {"initial_pose": [1, 2]})
    sim("sim_pose_text.json", {"initial_pose": "here"})
    sim("sim_pose_nan.json", '{"initial_pose": [NaN, 0, 0]}')
    sim("sim_pose_1e308.json", {"initial_pose": [1e308, 0, 0]})
    sim("sim_pose_bigint.json", '{"initial_pose": [' + BIG_INT + ", 0, 0]}")
    sim("sim_pose_far.json", {"initial_pose": [500.0, 500.0, 0.0]})
    sim("sim_pose_angle.json", {"initial_pose": [1.0, 1.0, 1e300]})
    sim("sim_pose_wall.json", {"initial_pose": [0.0, 0.0, 0.0]})
    sim("sim_odom_int.json", {"uncertain_odom": 1})
    sim("sim_objects_dict.json", {"objects": {"a": 1}})
    sim("sim_object_missing.json", {"objects": [{"length": 1.0}]})
    sim("sim_object_velocity_huge.json", {"objects": [{**obj, "velocity": 1e12}]})
    sim("sim_object_velocity_zero.json", {"objects": [{**obj, "velocity": 0}]})
    sim("sim_object_velocity_negative.json", {"objects": [{**obj, "velocity": -1}]})
    sim("sim_object_length_huge.json", {"objects": [{**obj, "length": 1e9}]})
    sim("sim_object_trigger_negative.json", {"objects": [{**obj, "trigger_radius": -1}]})
    sim("sim_object_repeat_text.json", {"objects": [{**obj, "repeat": "yes"}]})
    sim("sim_object_pose_far.json", {"objects": [{**obj, "final_pose": [1e6, 0, 0]}]})
    sim("sim_unknown_keys.json", {"show_full_map": True, "initial_pose": [1.0, 1.0, 0.0]})

    # CARMEN logs
    member = gzip.compress(b"\0" * (1 << 20), compresslevel=9)
    raw("bomb.log.gz", member * 1024)  # 1 GiB of zeros in ~1 MB: 1024 gzip members
    real = (REC / "intel-corrected.log.gz").read_bytes()
    raw("carmen_cut.log.gz", real[: len(real) // 3])
    raw("carmen_plain_gz.log.gz", b"FLASER not gzip at all\n")
    text("carmen_junk_lines.log", "hello\nFLASER x y z\nODOM 1 2\n" * 50)
    scan = " ".join(["1.0"] * 180)
    ok_line = f"FLASER 180 {scan} 1 1 0 1 1 0 {{t}} host 0\n"
    text("carmen_nan.log", "".join(ok_line.format(t=i * 0.1) for i in range(5))
         + f"FLASER 180 {' '.join(['nan'] * 180)} 1 1 0 1 1 0 0.6 host 0\n")
    text("carmen_long_line.log", ok_line.format(t=0) + "FLASER " + "1 " * (3 << 20) + "\n" + ok_line.format(t=0.1))
    text("carmen_count_huge.log", ok_line.format(t=0) + "FLASER 1e9 1 1 1\n" + ok_line.format(t=0.1))
    text("carmen_stamp_far.log", "".join(ok_line.format(t=i * 0.1) for i in range(5)) + ok_line.format(t=1e12)
         + "".join(ok_line.format(t=0.5 + i * 0.1) for i in range(5)))
    text("carmen_binary_nul.log", "\0" * 10_000)

    # bags
    bag = (REC / "pico_real_2019-05-07.bag").read_bytes()
    b = bytearray(bag)
    i = b.find(b"time=", 5000)
    b[i : i + 4] = b"tyme"
    b[-200:] = b"\xff" * 200
    raw("bag_no_time.bag", bytes(b))
    b = bytearray(bag)
    i = b.find(b"conn=", 5000)
    b[i : i + 4] = b"conx"
    b[-200:] = b"\xff" * 200
    raw("bag_no_conn.bag", bytes(b))
    b = bytearray(bag)
    j = b.find(b"\x04\x00\x00\x00op=\x05", 100_000)
    b[j - 4 : j] = b"\xff\xff\xff\x7f"
    b[-200:] = b"\xff" * 200
    raw("bag_bad_chunk_header.bag", bytes(b))
    b = bytearray(bag)
    j = b.find(b"\x04\x00\x00\x00op=\x05", 100_000)
    b[j + 40 : j + 2040] = b"\xaa" * 2000  # inside the chunk: a record's length is now junk
    b[-200:] = b"\xff" * 200
    raw("bag_junk_in_chunk.bag", bytes(b))
    raw("bag_truncated.bag", bag[: len(bag) // 2])
    raw("bag_magic_only.bag", b"#ROSBAG V2.0\n")
    raw("bag_magic_zeros.bag", b"#ROSBAG V2.0\n" + b"\0" * 100_000)
    raw("bag_magic_ff.bag", b"#ROSBAG V2.0\n" + b"\xff" * 100_000)
    raw("bag_old_version.bag", b"#ROSBAG V1.2\n" + b"\0" * 100)


# ----- the table -----------------------------------------------------------------------------
def _run(*args: str) -> list[str]:
    return ["run", "--no-perceptor", "--seconds", "0.5", *args]


def _file_cases() -> list[Case]:
    """Files that are not regular, empty, junk or too big, for every reader."""
    readers = [
        ("map-json", lambda f: ["map", "info", f], "json"),
        ("map-png", lambda f: ["map", "info", f], "png"),
        ("map-yaml", lambda f: ["map", "info", f], "yaml"),
        ("config", lambda f: ["config", "check", f], "yaml"),
        ("sim-config", lambda f: _run("--map", HOSPITAL, "--sim-config", f), "json"),
        ("run-config", lambda f: _run("--map", HOSPITAL, "--config", f), "yaml"),
        ("bag", lambda f: _run("--source", f"bag:{f}"), "bag"),
        ("carmen", lambda f: _run("--source", f"carmen:{f}"), "log"),
    ]
    # `run --source` checks the file exists (cli/run_sources.py) before a reader sees it
    not_found = {"bag": "no such bag file", "carmen": "no such carmen file"}
    empty = {"map-json": "not valid JSON at line 1, column 1", "map-png": "not a PNG/PGM image",
             "map-yaml": "must be a mapping", "sim-config": "not valid JSON", "bag": "not a ROS 1 bag",
             "carmen": "holds no FLASER"}
    junk = {"map-json": "not a text file", "map-png": "not a PNG/PGM image", "map-yaml": "not a text file",
            "config": "not a text file", "sim-config": "not a text file", "run-config": "not a text file",
            "bag": "not a ROS 1 bag", "carmen": "holds no FLASER"}
    cases: list[Case] = []
    for name, argv, ext in readers:
        cases += [
            refuse(f"{name}-missing", argv(f"{{d}}/absent.{ext}"), "no such"),
            refuse(f"{name}-directory", argv(f"{{d}}/dir.{ext}"), not_found.get(name, "is a directory")),
            refuse(f"{name}-fifo", argv(f"{{d}}/fifo.{ext}"), not_found.get(name, "is a FIFO")),
            refuse(f"{name}-junk", argv(f"{{d}}/junk.{ext}"), junk[name]),
        ]
        if name in empty:
            cases.append(refuse(f"{name}-empty", argv(f"{{d}}/empty.{ext}"), empty[name]))
        else:  # an empty config YAML is the defaults
            cases.append(Case(f"{name}-empty", argv(f"{{d}}/empty.{ext}")))
    # devices: /dev/zero grew config check to 4 GB; /dev/null reads as empty
    for name, argv in [
        ("config", lambda f: ["config", "check", f]),
        ("map-json", lambda f: ["map", "info", f]),
        ("sim-config", lambda f: _run("--map", HOSPITAL, "--sim-config", f)),
        ("run-map", lambda f: _run("--map", f)),
        ("bag", lambda f: _run("--source", f"bag:{f}")),
        ("carmen", lambda f: _run("--source", f"carmen:{f}")),
    ]:
        fragment = {"map-json": "unknown map format", "run-map": "unknown map format"}.get(name, "is a device")
        cases.append(refuse(f"{name}-dev-zero", argv("/dev/zero"), not_found.get(name, fragment)))
    cases += [
        refuse("map-json-dev-null", ["map", "info", "/dev/null"], "unknown map format"),
        refuse("config-dev-null", ["config", "check", "/dev/null"], "is a device"),
        refuse("map-json-socket", ["map", "info", "{d}/sock.json"], "is a socket"),
        refuse("map-json-latin1", ["map", "info", "{d}/latin1.json"], "not a text file"),
        refuse("config-latin1", ["config", "check", "{d}/latin1.yaml"], "not a text file"),
        refuse("map-json-over-cap", ["map", "info", "{d}/big.json"], "over the 1.0 MB limit",
               env={"PICO_STUDIO_MAX_MAP_MB": "1"}),
        refuse("config-over-cap", ["config", "check", "{d}/big.yaml"], "over the 1.0 MB limit",
               env={"PICO_STUDIO_MAX_CONFIG_MB": "1"}),
        refuse("bag-over-cap", _run("--source", f"bag:{REC / 'pico_real_2019-05-07.bag'}"), "over the 1.0 MB limit",
               env={"PICO_STUDIO_MAX_RECORDING_MB": "1"}),
        refuse("limit-env-junk", ["config", "check", "{d}/cfg_comments.yaml"], "PICO_STUDIO_MAX_CONFIG_MB",
               env={"PICO_STUDIO_MAX_CONFIG_MB": "lots"}),
    ]
    return cases


def _map_cases() -> list[Case]:
    def info(name: str) -> list[str]:
        return ["map", "info", "{d}/" + name]

    return [
        refuse("json-deep", info("deep.json"), "nested deeper than 64 levels at line 1"),
        refuse("json-deep-inside", info("deep_ok_prefix.json"), "nested deeper than 64"),
        refuse("json-top-list", info("top_list.json"), "top level must be an object"),
        refuse("json-top-string", info("top_string.json"), "top level must be an object"),
        refuse("json-truncated", info("truncated.json"), "not valid JSON at line 1"),
        refuse("json-trailing", info("trailing.json"), "Extra data"),
        refuse("json-bom", info("bom.json"), "not valid JSON"),
        refuse("json-no-points", info("no_points.json"), "points: missing key"),
        refuse("json-points-dict", info("points_dict.json"), "points: must be a list"),
        refuse("json-point-list", info("point_list.json"), "points[0]: must be an object"),
        refuse("json-point-no-x", info("point_no_x.json"), "points[0].x: missing coordinate"),
        refuse("json-point-x-str", info("point_x_str.json"), "points[0].x: must be a number"),
        refuse("json-point-x-bool", info("point_x_bool.json"), "points[0].x: must be a number"),
        refuse("json-point-x-nan", info("point_x_nan.json"), "points[0].x: must be finite"),
        refuse("json-point-x-inf", info("point_x_inf.json"), "points[0].x: must be finite"),
        refuse("json-point-x-1e308", info("point_x_1e308.json"), "points[0].x: 1e+308 m is beyond the 10 km"),
        refuse("json-convert-x-1e308", ["map", "convert", "{d}/point_x_1e308.json", "{d}/out_1e308.png"], "beyond the 10 km"),
        refuse("json-run-x-1e308", _run("--map", "{d}/point_x_1e308.json"), "beyond the 10 km"),
        refuse("json-point-x-far", info("point_x_neg_far.json"), "-20000.5 m is beyond"),
        refuse("json-point-x-bigint", info("point_x_bigint.json"), "is beyond the 10 km"),
        refuse("json-point-x-hugeint", info("point_x_hugeint.json"), "not usable JSON"),
        refuse("json-no-walls", info("no_walls.json"), "walls: missing key"),
        refuse("json-walls-empty", info("walls_empty.json"), "walls: is empty"),
        refuse("json-walls-dict", info("walls_dict.json"), "walls: must be a list"),
        refuse("json-wall-index-range", info("wall_index_range.json"), "walls[0][1]: point index 9 out of range"),
        refuse("json-wall-index-negative", info("wall_index_negative.json"), "point index -1 out of range"),
        refuse("json-wall-index-float", info("wall_index_float.json"), "walls[0][1]: must be a point index"),
        refuse("json-wall-index-bigint", info("wall_index_bigint.json"), "out of range"),
        refuse("json-wall-triple", info("wall_triple.json"), "walls[0]: must be a pair"),
        refuse("json-wall-zero-length", info("wall_zero_length.json"), "zero-length segment"),
        refuse("json-cabinets-and-tables", info("cabinets_and_tables.json"), "has both 'cabinets' and 'tables'"),
        refuse("json-polygon-open", info("polygon_open.json"), "cabinets[0]: polygon is not closed"),
        refuse("json-polygon-two", info("polygon_two.json"), "doors[0]: a polygon needs at least 3"),
        refuse("json-polygon-not-list", info("polygon_not_list.json"), "start_area: must be a list"),
        refuse("json-wide-point-list", info("wide_point.json"), "points[0]: must be an object"),
        warn("json-dup-points", info("dup_points.json"), "points[4] duplicates points[0]"),
        warn("json-unused-points", info("unused_points.json"), "unused points: points[4]"),
        warn("json-dup-walls", info("dup_walls.json"), "walls[4] duplicates walls[0]"),
        warn("json-self-intersecting-loop", info("bowtie.json"), "the loop intersects itself"),
        warn("json-self-intersecting-cabinet", info("bowtie_cabinet.json"), "cabinets[0]: segments"),
        refuse("json-unknown-suffix", ["map", "info", "{d}/junk.bag"], "unknown map format"),
        # where the results go: writing to a FIFO blocks for ever, to a directory fails late
        refuse("out-convert-fifo", ["map", "convert", HOSPITAL, "{d}/out_fifo.png"], "cannot write: is a FIFO"),
        refuse("out-convert-yaml-sibling-fifo", ["map", "convert", HOSPITAL, "{d}/sibling.png"],
               "sibling.yaml: cannot write: is a FIFO"),
        refuse("out-convert-directory", ["map", "convert", HOSPITAL, "{d}/dir.png"], "cannot write: is a directory"),
        refuse("out-convert-json-directory", ["map", "convert", "{d}/ok.png", "{d}/dir.json"], "is a directory"),
        refuse("out-info-png-fifo", ["map", "info", HOSPITAL, "--png", "{d}/out_fifo.png"], "cannot write: is a FIFO"),
        refuse("out-convert-suffix", ["map", "convert", HOSPITAL, "{d}/out.txt"], "unknown output format"),
        refuse("out-convert-onto-input", ["map", "convert", "{d}/ok.png", "{d}/ok.png"], "would overwrite the input"),
        # heightmaps
        refuse("png-20000", info("png_20000.png"), "20000 x 20000 px = 400 Mpx, over the 25 Mpx limit"),
        refuse("png-20000-convert", ["map", "convert", "{d}/png_20000.png", "{d}/out.json"], "over the 25 Mpx limit"),
        refuse("png-20000-run", _run("--map", "{d}/png_20000.png"), "over the 25 Mpx limit"),
        refuse("png-65535", info("png_65535.png"), "65535 x 65535 px"),
        refuse("png-pixel-cap-env", info("ok.png"), "over the 0 Mpx limit", env={"PICO_STUDIO_MAX_IMAGE_PIXELS": "100"}),
        refuse("png-zero-width", info("png_zero.png"), "0 x 10 px: it has no pixels"),
        refuse("png-truncated-header", info("png_truncated.png"), "without its IHDR"),
        refuse("png-magic-only", info("png_magic_only.png"), "without its IHDR"),
        refuse("png-bad-ihdr", info("png_bad_ihdr.png"), "without its IHDR"),
        refuse("png-bad-crc", info("png_bad_crc.png"), "not a PNG/PGM image, or corrupt"),
        refuse("png-cut-idat", info("png_cut_idat.png"), "not a PNG/PGM image, or corrupt"),
        refuse("png-white", info("png_white.png"), "no walls"),
        refuse("png-specks", info("png_specks.png"), "only specks"),
        refuse("png-text", info("png_text.png"), "not a PNG/PGM image"),
        refuse("png-empty", info("empty.png"), "not a PNG/PGM image"),
        refuse("pgm-2e9", info("pgm_2e9.pgm"), "2000000000 x 2000000000 px"),
        refuse("pgm-comment-30000", info("pgm_comment.pgm"), "30000 x 30000 px"),
        refuse("pgm-zero", info("pgm_zero.pgm"), "it has no pixels"),
        refuse("pgm-no-size", info("pgm_no_size.pgm"), "PGM header without a width and height"),
        refuse("pgm-short", info("pgm_short.pgm"), "not a PNG/PGM image, or corrupt"),
        Case("pgm-ok", info("pgm_ok.pgm")),
        refuse("resolution-image-zero", info("ok.png") + ["--resolution", "0"], "argument --resolution"),
        refuse("ms-no-image", info("ms_no_image.yaml"), "image: missing key"),
        refuse("ms-missing-image", info("ms_missing_image.yaml"), "does not exist"),
        refuse("ms-resolution-zero", info("ms_res_zero.yaml"), "resolution: 0 is out of range"),
        refuse("ms-resolution-negative", info("ms_res_negative.yaml"), "resolution: -0.05 is out of range"),
        refuse("ms-resolution-text", info("ms_res_text.yaml"), "resolution: must be a finite number"),
        refuse("ms-resolution-huge", info("ms_res_huge.yaml"), "resolution: 1e+09 is out of range"),
        refuse("ms-resolution-nan", info("ms_res_nan.yaml"), "resolution: must be a finite number"),
        refuse("ms-origin-short", info("ms_origin_short.yaml"), "origin: must be [x, y, yaw]"),
        refuse("ms-origin-nan", info("ms_origin_nan.yaml"), "origin: must be [x, y, yaw]"),
        refuse("ms-origin-far", info("ms_origin_far.yaml"), "origin: x, y must lie within 10000 m"),
        refuse("ms-negate", info("ms_negate.yaml"), "negate: must be 0 or 1"),
        refuse("ms-thresholds", info("ms_thresholds.yaml"), "free_thresh: 0.5 must be below"),
        refuse("ms-duplicate-key", info("ms_duplicate.yaml"), "duplicate key 'resolution' (first at line 2)"),
        refuse("ms-deep", info("ms_deep.yaml"), "nested deeper than 64 levels"),
        refuse("ms-list", info("ms_list.yaml"), "must be a mapping"),
        refuse("ms-image-dir", info("ms_image_dir.yaml"), "does not exist"),
        refuse("ms-image-fifo", info("ms_image_fifo.yaml"), "does not exist"),
        refuse("ms-image-device", info("ms_image_dev.yaml"), "does not exist"),
        refuse("ms-image-huge", info("ms_image_huge.yaml"), "over the 25 Mpx limit"),
        refuse("ms-syntax", info("ms_syntax.yaml"), "not valid YAML at line"),
    ]


def _config_cases() -> list[Case]:
    def check(name: str) -> list[str]:
        return ["config", "check", "{d}/" + name]

    return [
        refuse("cfg-duplicate-key", check("cfg_duplicate.yaml"), "line 3, column 3: duplicate key 'seed' (first at line 2)"),
        refuse("cfg-duplicate-section", check("cfg_dup_section.yaml"), "duplicate key 'sim' (first at line 1)"),
        refuse("cfg-deep-flow", check("cfg_deep.yaml"), "nested deeper than 64 levels"),
        refuse("cfg-deep-block", check("cfg_deep_block.yaml"), "nested deeper than 64 levels"),
        refuse("cfg-seed-5000-digits", check("cfg_seed_huge.yaml"), "an integer of 5000 digits is too long"),
        refuse("cfg-seed-400-digits", check("cfg_seed_400.yaml"), "an integer of 400 digits is too long"),
        refuse("cfg-seed-90-digits", check("cfg_seed_90.yaml"), "sim.seed: a 90-digit number is out of range"),
        refuse("cfg-seed-negative", check("cfg_seed_negative.yaml"), "sim.seed: -1 is out of range"),
        refuse("cfg-seed-float", check("cfg_seed_float.yaml"), "sim.seed: must be a whole number"),
        refuse("cfg-seed-text", check("cfg_seed_text.yaml"), "sim.seed: must be a number"),
        refuse("cfg-seed-bool", check("cfg_seed_bool.yaml"), "sim.seed: must be a number"),
        refuse("cfg-seed-list", check("cfg_seed_list.yaml"), "sim.seed: must be a number, got [1, 2]"),
        refuse("cfg-seed-long-text", check("cfg_seed_long_text.yaml"), "sim.seed: must be a number, got 'xxx"),
        refuse("cfg-alias-bomb", check("cfg_laughs.yaml"), "sim.seed: must be a number, got [['lol', 'lol'"),
        refuse("cfg-unknown-key", check("cfg_unknown_key.yaml"), "sim.sead: unknown key; did you mean 'seed'?"),
        refuse("cfg-unknown-section", check("cfg_unknown_section.yaml"), "simulation: unknown key"),
        refuse("cfg-section-scalar", check("cfg_section_scalar.yaml"), "sim: must be a mapping"),
        refuse("cfg-top-list", check("cfg_top_list.yaml"), "(top level): must be a mapping"),
        refuse("cfg-nan", check("cfg_nan.yaml"), "map.heightmap.resolution: must be a finite number"),
        refuse("cfg-inf", check("cfg_inf.yaml"), "map.heightmap.resolution: must be a finite number"),
        refuse("cfg-out-of-range", check("cfg_range.yaml"), "map.heightmap.resolution: 1000 is out of range"),
        refuse("cfg-tab", check("cfg_tab.yaml"), "not valid YAML at line 2"),
        refuse("cfg-syntax", check("cfg_syntax.yaml"), "not valid YAML"),
        refuse("cfg-python-tag", check("cfg_python_tag.yaml"), "could not determine a constructor"),
        refuse("cfg-key-list", check("cfg_key_list.yaml"), "unhashable"),
        Case("cfg-only-comments", check("cfg_comments.yaml")),
        refuse("cfg-run-duplicate", _run("--map", HOSPITAL, "--config", "{d}/cfg_duplicate.yaml"), "duplicate key 'seed'"),
        refuse("cfg-convert-deep", ["map", "convert", HOSPITAL, "{d}/o.png", "--config", "{d}/cfg_deep.yaml"], "nested deeper"),
    ]


def _sim_config_cases() -> list[Case]:
    def run(name: str) -> list[str]:
        return _run("--map", HOSPITAL, "--sim-config", "{d}/" + name)

    return [
        refuse("sim-top-list", run("sim_list.json"), "the top level must be a JSON object"),
        refuse("sim-deep", run("sim_deep.json"), "nested deeper than 64"),
        refuse("sim-pose-short", run("sim_pose_short.json"), "initial_pose: must be a list [x, y, a]"),
        refuse("sim-pose-text", run("sim_pose_text.json"), "initial_pose: must be a list"),
        refuse("sim-pose-nan", run("sim_pose_nan.json"), "initial_pose[0]: must be a finite number"),
        refuse("sim-pose-1e308", run("sim_pose_1e308.json"), "initial_pose[0]: must be at most 10000 m"),
        refuse("sim-pose-bigint", run("sim_pose_bigint.json"), "initial_pose[0]: must be a finite number"),
        refuse("sim-pose-outside-map", run("sim_pose_far.json"), "m outside the map"),
        refuse("sim-pose-angle", run("sim_pose_angle.json"), "initial_pose[2]: must be at most 1000 rad"),
        refuse("sim-pose-in-wall", run("sim_pose_wall.json"), "inside a wall or obstacle"),
        refuse("sim-odom-int", run("sim_odom_int.json"), "uncertain_odom: must be true or false"),
        refuse("sim-objects-dict", run("sim_objects_dict.json"), "objects: must be a list"),
        refuse("sim-object-missing", run("sim_object_missing.json"), "objects[0].width: missing key"),
        refuse("sim-object-velocity-1e12", run("sim_object_velocity_huge.json"), "objects[0].velocity: must be at most 10 m/s"),
        refuse("sim-object-velocity-zero", run("sim_object_velocity_zero.json"), "objects[0].velocity: must be > 0"),
        refuse("sim-object-velocity-negative", run("sim_object_velocity_negative.json"), "velocity: must be > 0"),
        refuse("sim-object-length-huge", run("sim_object_length_huge.json"), "objects[0].length: must be at most 100 m"),
        refuse("sim-object-trigger-negative", run("sim_object_trigger_negative.json"), "trigger_radius: must be >= 0"),
        refuse("sim-object-repeat-text", run("sim_object_repeat_text.json"), "objects[0].repeat: must be true or false"),
        refuse("sim-object-pose-far", run("sim_object_pose_far.json"), "objects[0].final_pose[0]: must be at most"),
        Case("sim-unknown-keys", run("sim_unknown_keys.json")),
    ]


def _argument_cases() -> list[Case]:
    cases: list[Case] = []
    for value, fragment in [("0", "got 0"), ("-1", "got -1"), ("nan", "got nan"), ("inf", "got inf"),
                            ("1e-9", "got 1e-9"), ("abc", "must be a number"), ("11", "got 11"), ("", "must be a number")]:
        cases.append(refuse(f"arg-dt-{value or 'empty'}", ["run", "--map", HOSPITAL, "--dt", value], f"argument --dt: {fragment}"
                            if fragment.startswith("must") else fragment))
    for value, fragment in [("-1", "got -1"), ("nan", "got nan"), ("inf", "got inf"), ("1e7", "got 1e7"),
                            ("abc", "must be a number"), ("2e6", "got 2e6")]:
        cases.append(refuse(f"arg-seconds-{value}", ["run", "--map", HOSPITAL, "--seconds", value], fragment))
    cases += [
        refuse("arg-steps-dt-first", ["run", "--map", HOSPITAL, "--dt", "1e-4", "--seconds", "2000"], "step limit"),
        refuse("arg-steps-seconds-first", ["run", "--map", HOSPITAL, "--seconds", "2000", "--dt", "1e-4"], "step limit"),
        refuse("arg-steps-default-dt", ["run", "--map", HOSPITAL, "--seconds", "900000"], "1.8e+07 steps"),
        refuse("arg-steps-replay", ["run", "--source", f"bag:{REC / 'pico_real_2019-05-07.bag'}", "--dt", "1e-4",
                                    "--seconds", "5000"], "step limit"),
    ]
    for value, fragment in [("-1", "got -1"), (str(2**32), f"got {2**32}"), ("1.5", "must be a seed"),
                            ("abc", "must be a seed"), (HUGE_INT, "must be a seed"), ("1e3", "must be a seed"),
                            ("", "must be a seed"), ("٣", "must be a seed")]:
        cases.append(refuse(f"arg-seed-{value[:8] or 'empty'}", ["run", "--map", HOSPITAL, "--seed", value],
                            f"argument --seed: {fragment}" if fragment.startswith("must") else fragment))
    cases.append(refuse("arg-eval-seed-negative", ["eval", "--map", HOSPITAL, "--seed", "-1"], "argument --seed"))
    for value, fragment in [("0", "got 0"), ("nan", "got nan"), ("inf", "got inf"), ("-1", "got -1"),
                            ("1e-6", "got 1e-6"), ("abc", "must be a number"), ("1e3", "got 1e3")]:
        cases.append(refuse(f"arg-resolution-{value}", ["map", "convert", HOSPITAL, "{d}/o.png", "--resolution", value],
                            fragment))
    cases += [
        refuse("arg-resolution-pixel-cap", ["map", "convert", HOSPITAL, "{d}/o.png", "--resolution", "0.001"],
               "over the 25 Mpx limit"),
        refuse("arg-resolution-info", ["map", "info", "{d}/ok.png", "--resolution", "nan"], "argument --resolution"),
    ]
    for flag, value in [("--poses", "0"), ("--poses", "-5"), ("--poses", "1e9"), ("--poses", "abc"),
                        ("--poses", "100000"), ("--frames", "0"), ("--frames", "1.5"), ("--turn", "nan"),
                        ("--turn", "1e9"), ("--clearance", "-1"), ("--clearance", "inf")]:
        cases.append(refuse(f"arg-eval{flag}-{value}", ["eval", "--map", HOSPITAL, flag, value], f"argument {flag}"))
    # the later commands take their numbers through the same validators (cli/limits.py)
    for name, argv, flag in [
        ("compare-seconds-nan", ["compare", "defaults", "defaults", "--map", HOSPITAL, "--seconds", "nan"], "--seconds"),
        ("compare-steps", ["compare", "defaults", "defaults", "--map", HOSPITAL, "--dt", "1e-4", "--seconds", "5000"],
         "step limit"),
        ("compare-seed", ["compare", "defaults", "defaults", "--map", HOSPITAL, "--seed", "-1"], "--seed"),
        ("compare-workers", ["compare", "defaults", "defaults", "--map", HOSPITAL, "--workers", "0"], "--workers"),
        ("compare-tolerance", ["compare", "defaults", "defaults", "--map", HOSPITAL, "--tolerance", "inf"],
         "--tolerance"),
        ("eval-workers", ["eval", "--scenarios", "x.yaml", "--workers", "1e9"], "--workers"),
        ("tune-trials", ["tune", "--map", HOSPITAL, "--trials", "0"], "--trials"),
        ("tune-workers", ["tune", "--map", HOSPITAL, "--workers", "-2"], "--workers"),
        ("tune-max-ms", ["tune", "--map", HOSPITAL, "--max-ms", "nan"], "--max-ms"),
        ("render-width", ["render", "--map", HOSPITAL, "--out", "{d}/o.png", "--width", "100000"], "--width"),
        ("render-fps", ["render", "--map", HOSPITAL, "--out", "{d}/o.png", "--fps", "0"], "--fps"),
        ("render-from", ["render", "--map", HOSPITAL, "--out", "{d}/o.png", "--from", "-3"], "--from"),
        ("serve-port", ["serve", "--port", "70000"], "--port"),
        ("serve-workers", ["serve", "--workers", "0"], "--workers"),
    ]:
        cases.append(refuse(f"arg-{name}", argv, f"argument {flag}" if flag.startswith("--") else flag))
    cases += [
        refuse("arg-behaviour-nan", ["run", "--map", HOSPITAL, "--behaviour", "drive:nan,0,0"], "--behaviour"),
        refuse("arg-behaviour-short", ["run", "--map", HOSPITAL, "--behaviour", "drive:1"], "three numbers"),
        refuse("arg-behaviour-unknown", ["run", "--map", HOSPITAL, "--behaviour", "fly"], "unknown behaviour"),
        refuse("arg-source-kind", ["run", "--source", "tape:x"], "unknown source kind"),
        refuse("arg-source-empty-file", ["run", "--source", "bag:"], "needs a file"),
        refuse("arg-source-guess", ["run", "--source", "{d}/nothing.xyz"], "unknown source"),
        refuse("arg-map-suffix", _run("--map", "{d}/junk.bag"), "unknown map format"),
    ]
    return cases


def _recording_cases() -> list[Case]:
    return [
        refuse("carmen-gzip-bomb", _run("--source", "carmen:{d}/bomb.log.gz"), "decompressed beyond"),
        warn("carmen-truncated-gzip", _run("--source", "carmen:{d}/carmen_cut.log.gz"), "the file is damaged after line"),
        refuse("carmen-not-gzip", _run("--source", "carmen:{d}/carmen_plain_gz.log.gz"), "no usable laser scan"),
        refuse("carmen-junk-lines", _run("--source", "carmen:{d}/carmen_junk_lines.log"),
               "line 2: FLASER num_readings: must be a number, got 'x'"),
        warn("carmen-nan-ranges", _run("--source", "carmen:{d}/carmen_nan.log"), "line 6: FLASER range[0]: must be finite"),
        warn("carmen-long-line", _run("--source", "carmen:{d}/carmen_long_line.log"), "line 2: longer than 4 MB"),
        warn("carmen-count-huge", _run("--source", "carmen:{d}/carmen_count_huge.log"), "line 2: FLASER fields"),
        warn("carmen-stamp-far", _run("--source", "carmen:{d}/carmen_stamp_far.log"), "scans 5 (1e+12 s)"),
        refuse("carmen-nul", _run("--source", "carmen:{d}/carmen_binary_nul.log"), "no FLASER"),
        warn("bag-no-time-field", _run("--source", "bag:{d}/bag_no_time.bag"), "header has no 'time' field; skipped"),
        warn("bag-no-conn-field", _run("--source", "bag:{d}/bag_no_conn.bag"), "header has no 'conn' field"),
        warn("bag-bad-chunk-header", _run("--source", "bag:{d}/bag_bad_chunk_header.bag"), "chunk skipped"),
        warn("bag-junk-in-chunk", _run("--source", "bag:{d}/bag_junk_in_chunk.bag"), "of the chunk at byte"),
        warn("bag-truncated", _run("--source", "bag:{d}/bag_truncated.bag"), "file ends inside the record"),
        refuse("bag-magic-only", _run("--source", "bag:{d}/bag_magic_only.bag"), "no laser topic"),
        refuse("bag-magic-zeros", _run("--source", "bag:{d}/bag_magic_zeros.bag"), "no laser topic"),
        refuse("bag-magic-ff", _run("--source", "bag:{d}/bag_magic_ff.bag"), "no laser topic"),
        refuse("bag-old-version", _run("--source", "bag:{d}/bag_old_version.bag"), "not a ROS 1 bag (format 2.0)"),
        refuse("bag-empty-file", _run("--source", "bag:{d}/empty.bag"), "not a ROS 1 bag"),
    ]


CASES = _file_cases() + _map_cases() + _config_cases() + _sim_config_cases() + _argument_cases() + _recording_cases()
BY_ID = {c.id: c for c in CASES}
assert len(BY_ID) == len(CASES), sorted({c.id for c in CASES if [d.id for d in CASES].count(c.id) > 1})


# ----- running it --------------------------------------------------------------------------------
def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


class _Runner:
    """Runs the table's cases in worker processes, a chunk at a time, on first demand."""

    def __init__(self, d: Path):
        self.d = d
        self.results: dict[str, dict[str, Any]] = {}

    def result(self, case: Case) -> dict[str, Any]:
        if case.id not in self.results:
            k = CASES.index(case) // CHUNK
            self._run_chunk(CASES[k * CHUNK : (k + 1) * CHUNK])
        return self.results[case.id]

    def _run_chunk(self, chunk: list[Case]) -> None:
        lines = "".join(
            json.dumps({"id": c.id, "argv": [a.replace("{d}", str(self.d)) for a in c.argv], "env": c.env,
                        "timeout": TIMEOUT_S, "wall_timeout": WALL_TIMEOUT_S}) + "\n"
            for c in chunk
        )
        env = {**os.environ, "PYTHONPATH": str(ROOT)}
        p = subprocess.run(
            [sys.executable, str(ROOT / "tests" / "bad_inputs_worker.py")], input=lines, capture_output=True,
            text=True, preexec_fn=_limit_memory, env=env, cwd=str(self.d),
            timeout=WALL_TIMEOUT_S * len(chunk) + 60,
        )
        for line in p.stdout.splitlines():
            r = json.loads(line)
            self.results[r["id"]] = r
        for c in chunk:  # a case that killed the worker
            self.results.setdefault(c.id, {"code": "worker died", "out": "", "err": p.stderr[-2000:], "seconds": 0})


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("bad")
    make_files(d)
    return d


@pytest.fixture(scope="module")
def runner(files: Path) -> _Runner:
    return _Runner(files)


def test_the_table_is_big_enough() -> None:
    assert len(CASES) >= 150
    assert sum(c.warning is not None for c in CASES) >= 10


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input(case: Case, runner: _Runner) -> None:
    r = runner.result(case)
    where = f"{case.id}: code {r['code']}, {r['seconds']:.2f} s\nstdout: {r['out'][-800:]}\nstderr: {r['err'][-1500:]}"
    assert r["code"] not in ("timeout", "traceback", "worker died"), where
    assert "Traceback" not in r["err"], where
    if case.refused is not None:
        assert r["code"] == 2, where
        last = r["err"].strip().splitlines()[-1]
        assert last.startswith("pico-studio"), where
        assert case.refused in last, where
    else:
        assert r["code"] == 0, where
        if case.warning is not None:
            assert case.warning in r["out"] + r["err"], where


# The worst cases, each in its own `python -m pico_studio` under the same bounds.
WORST = [
    ("config-dev-zero", ["config", "check", "/dev/zero"], "is a device"),
    ("png-20000", ["map", "info", "{d}/png_20000.png"], "over the 25 Mpx limit"),
    ("png-20000-convert", ["map", "convert", "{d}/png_20000.png", "{d}/o.json"], "over the 25 Mpx limit"),
    ("fifo-json", ["map", "info", "{d}/fifo.json"], "is a FIFO"),
    ("dt-1e-9", ["run", "--map", HOSPITAL, "--dt", "1e-9", "--seconds", "1"], "argument --dt"),
    ("gzip-bomb", ["run", "--source", "carmen:{d}/bomb.log.gz"], "decompressed beyond"),
    ("resolution-0", ["map", "convert", HOSPITAL, "{d}/o.png", "--resolution", "0"], "argument --resolution"),
    ("resolution-nan", ["map", "convert", HOSPITAL, "{d}/o.png", "--resolution", "nan"], "argument --resolution"),
    ("resolution-1e-6", ["map", "convert", HOSPITAL, "{d}/o.png", "--resolution", "1e-6"], "argument --resolution"),
    ("x-1e308-convert", ["map", "convert", "{d}/point_x_1e308.json", "{d}/o.png"], "beyond the 10 km"),
    ("x-1e308-run", ["run", "--map", "{d}/point_x_1e308.json"], "beyond the 10 km"),
    ("deep-json", ["map", "info", "{d}/deep.json"], "nested deeper"),
    ("deep-yaml", ["config", "check", "{d}/cfg_deep.yaml"], "nested deeper"),
    ("bag-damaged-chunk", ["run", "--no-perceptor", "--seconds", "0.5", "--source", "bag:{d}/bag_no_time.bag"], None),
    ("seed-minus-1", ["run", "--map", HOSPITAL, "--seed", "-1"], "argument --seed"),
    ("seed-5000-digits", ["config", "check", "{d}/cfg_seed_huge.yaml"], "5000 digits"),
    ("pgm-2e9", ["map", "info", "{d}/pgm_2e9.pgm"], "over the 25 Mpx limit"),
    ("png-65535", ["map", "info", "{d}/png_65535.png"], "over the 25 Mpx limit"),
    ("yaml-duplicate", ["config", "check", "{d}/cfg_duplicate.yaml"], "duplicate key"),
    ("start-outside-map", ["run", "--map", HOSPITAL, "--sim-config", "{d}/sim_pose_far.json"], "outside the map"),
    ("velocity-1e12", ["run", "--map", HOSPITAL, "--sim-config", "{d}/sim_object_velocity_huge.json"], "velocity"),
    ("self-intersecting", ["map", "info", "{d}/bowtie.json"], None),
]


@pytest.mark.parametrize(("name", "argv", "fragment"), WORST, ids=[w[0] for w in WORST])
def test_worst_case_in_its_own_process(name: str, argv: list[str], fragment: str | None, files: Path) -> None:
    args = [a.replace("{d}", str(files)) for a in argv]
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        p = subprocess.Popen(
            [sys.executable, "-m", "pico_studio", *args], stdout=out, stderr=err,
            preexec_fn=_limit_memory, env={**os.environ, "PYTHONPATH": str(ROOT)}, cwd=str(files),
        )
        deadline = time.monotonic() + WALL_TIMEOUT_S
        while True:  # wait4, not wait: it also says how much CPU the process used
            pid, status, usage = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() > deadline:
                p.kill()
                pid, status, usage = os.wait4(p.pid, 0)
                break
            time.sleep(0.02)
        p.returncode = code = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read().decode(errors="replace"), err.read().decode(errors="replace")
    cpu = usage.ru_utime + usage.ru_stime
    assert code >= 0, f"killed after {WALL_TIMEOUT_S:g} s: {stderr}"
    assert cpu <= TIMEOUT_S, f"{cpu:.1f} s of CPU (start-up included)"
    assert "Traceback" not in stderr, stderr
    if fragment is None:
        assert code == 0 and "warning" in stdout, stdout + stderr
    else:
        assert code == 2 and fragment in stderr.strip().splitlines()[-1], stderr
