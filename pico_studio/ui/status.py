"""The page's text: the status line at the top and the metrics under the run controls.

Plain functions of the studio and its `metrics()`, no viser; times are relative to the
start of the run or recording (`ui.clock`).
"""

from __future__ import annotations

import math
from typing import Any

from pico_studio.ui.clock import is_replay, relative_time
from pico_studio.ui.scene_data import room_text
from pico_studio.ui.timeline import FrameRecord


def source_status(studio: Any) -> str:
    """The source's own state: live robot or replay position; '' for the simulator."""
    source = studio.source
    status = getattr(source, "status", None)
    if callable(status):
        s = status()
        text = s.message
        return f"**{text}**" if (s.stale or not s.master_up) else text
    if is_replay(source):
        t0, t1 = source.time_span
        return (f"recording frame {max(source.frame_index, 0) + 1} / {source.frame_count} · "
                f"{source.now() - t0:.2f} / {t1 - t0:.2f} s")
    return ""


def status_text(studio: Any, frame: FrameRecord | None) -> str:
    s = studio
    state = "playing" if s.playing else "paused"
    if frame is None:
        return f"**{s.map_name}** · {state} · no frame yet"
    replay = is_replay(s.source)
    if replay:
        where = "" if s.cursor is None else f"scrubbed to frame {frame.index}"
    else:
        where = "live" if s.cursor is None else f"timeline frame {frame.index}"
    wm = frame.wm
    if wm is not None and wm.too_close:
        where += " · **too close!**"
    parts = [f"**{s.map_name}**", state]
    if where:
        parts.append(where.lstrip(" ·"))
    if not replay:  # a replay's own line below has its position and time
        parts.append(f"t = {relative_time(s.source, frame.time):.2f} s")
        parts.append(f"behaviour: {frame.behaviour_state or s.behaviour_name}")
    source = source_status(s)
    if source:
        parts.append(source)
    return " · ".join(parts)


def metrics_text(m: dict[str, Any]) -> str:
    lines = []
    ms = "–" if math.isnan(m["ms"]) else f"{m['ms']:.1f} ms"
    lines.append(f"**Perception** {m['hz']:.1f} Hz · last frame {ms}")
    if m["stages"]:
        lines.append("Stages: " + " · ".join(f"{k} {v:.2f} ms" for k, v in m["stages"].items()))
    if m["counts"]:
        counts = " · ".join(f"{k.replace('_', ' ')} {v}" for k, v in m["counts"].items())
        if m.get("fit_rms_mm") is not None:
            counts += f" · walls fitted to {m['fit_rms_mm']:.1f} mm"
        lines.append("Counts: " + counts)
    percept = []
    lm = m.get("laser_motion")
    if lm is not None:
        percept.append(f"laser motion ({lm[0]:+.3f} m, {lm[1]:+.3f} m, {lm[2]:+.3f} rad), {m['laser_motion_matches']} matches")
    if m.get("entrance") is not None:
        a, d = m["entrance"]
        percept.append(f"{'hallway' if m.get('hallway') else 'entrance'} at {d:.2f} m, {a:+.2f} rad")
    if m.get("room"):
        percept.append("side room: " + room_text(m["room"]))
    if percept:
        lines.append(" · ".join(percept))
    loc = m.get("localisation") or {}
    if loc:
        text = f"**Localisation** quality {loc['quality']:.2f}" + (" · LOST" if loc["lost"] else "")
        if "error_m" in loc:
            text += f" · error vs truth {loc['error_m']:.3f} m, {loc['error_rad']:.3f} rad"
        lines.append(text)
    for which, title in (("frame", "this frame"), ("run", "since reset")):
        figures = m["scores"].get(which)
        if figures:
            lines.append(f"**Truth, {title}**: " + " · ".join(f"{k} {v:.2f}" for k, v in figures.items()))
    if m["warnings"]:
        lines.append("Warnings (all in the Log tab): " + "; ".join(m["warnings"][:3]))
    return "\n\n".join(lines)
