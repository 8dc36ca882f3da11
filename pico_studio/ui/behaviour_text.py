"""What the behaviour panel says: state, target, plan and progress, from the behaviour object
and the frame it last stepped on (`FrameRecord.behaviour_*`). No viser here."""

from __future__ import annotations

from typing import Any

import numpy as np

from pico_studio.ui.timeline import FrameRecord


def behaviour_lines(name: str, behaviour: Any, frame: FrameRecord | None) -> list[str]:
    """Markdown lines: **state**, target (which cabinet / room / exit, where), plan, progress."""
    state = frame.behaviour_state if frame is not None and frame.behaviour_state else name
    lines = [f"**{name}** · state **{state.split(': ', 1)[-1] or '–'}**"]
    result: dict[str, Any] = {}
    if behaviour is not None and callable(getattr(behaviour, "result", None)):
        try:
            result = dict(behaviour.result())
        except Exception:  # a behaviour's bookkeeping must not break the page
            result = {}
    target = frame.behaviour_target if frame is not None else None
    lines.append("Target: " + _target_text(name, result, target))
    plan = np.asarray(frame.behaviour_plan, dtype=float).reshape(-1, 2) if frame is not None and frame.behaviour_plan is not None else np.zeros((0, 2))
    if len(plan) >= 2:
        length = float(np.hypot(*np.diff(plan, axis=0).T).sum())
        lines.append(f"Plan: {len(plan)} waypoints, {length:.2f} m")
    else:
        lines.append("Plan: –")
    progress = _progress_text(result)
    if progress:
        lines.append("Progress: " + progress)
    notes = result.get("notes") or []
    if notes:
        lines.append("Last note: " + str(notes[-1]))
    return lines


def _target_text(name: str, result: dict[str, Any], target: Any) -> str:
    where = "–" if target is None else f"({float(target[0]):.2f}, {float(target[1]):.2f})"
    order = result.get("order")
    if order:  # hospital: the cabinet after the visited ones
        k = len(result.get("cabinets_visited") or [])
        if k < len(order):
            return f"cabinet {order[k]} at {where}"
        return "all cabinets visited"
    if name == "escape-room":
        return f"the exit at {where}" if target is not None else "looking for the exit"
    if name == "room-finder":
        return f"the next room at {where}" if target is not None else "looking for a room"
    return where


def _progress_text(result: dict[str, Any]) -> str:
    order = result.get("order")
    if order:
        visited = list(result.get("cabinets_visited") or [])
        text = f"visited {len(visited)} of {len(order)} cabinets"
        return text + (f" ({', '.join(map(str, visited))})" if visited else "")
    rooms = result.get("rooms")
    if rooms:
        return f"{len(rooms)} room(s) found"
    return ""
