"""The progress line: drawn on a terminal only, with counts, percentage and a cleared end."""

from __future__ import annotations

import io

from pico_studio.progress import Progress


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_draws_on_a_terminal_and_clears_at_the_end() -> None:
    out = _Terminal()
    with Progress(50, "eval", "poses", stream=out, min_interval=0.0) as p:
        p.set(10)
        p.set(25)
    text = out.getvalue()
    assert "eval [" in text and "10/50 poses" in text and "25/50 poses  50%" in text
    assert text.endswith("\r\x1b[K")


def test_progress_is_silent_when_not_a_terminal() -> None:
    out = io.StringIO()
    with Progress(3, "run", stream=out, min_interval=0.0) as p:
        for k in range(4):
            p.set(k)
    assert out.getvalue() == "" and p.done == 3
