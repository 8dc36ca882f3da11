"""Runs `pico-studio` command lines in one process, each bounded in time, for
tests/test_bad_inputs.py: one JSON case a line on stdin, one JSON result a line on stdout.

A case: {"id", "argv", "env", "timeout", "wall_timeout"}. A result: {"id", "code" (int,
"timeout" or "traceback"), "out", "err", "seconds" (wall), "cpu_seconds", "rss_mb" (the
process's peak so far)}. The time bounds: `timeout` seconds of CPU (SIGPROF: what a case
costs, whatever the machine's load) and `wall_timeout` seconds of wall time (SIGALRM: it
interrupts a blocking system call too, e.g. opening a FIFO, which costs no CPU). The memory
bound is the address-space limit the test sets on this process, under which an allocation
that would have eaten gigabytes raises MemoryError — a "traceback" result.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import resource
import signal
import sys
import time
import traceback


class _Timeout(BaseException):
    """Raised by the alarm; a BaseException so that no `except Exception` swallows it."""


def _alarm(signum: int, frame: object) -> None:
    raise _Timeout


def main() -> None:
    from pico_studio.cli import main as cli_main

    signal.signal(signal.SIGALRM, _alarm)
    signal.signal(signal.SIGPROF, _alarm)
    real_stdout = sys.stdout
    for line in sys.stdin:
        case = json.loads(line)
        saved = {k: os.environ.get(k) for k in case["env"]}
        os.environ.update(case["env"])
        out, err = io.StringIO(), io.StringIO()
        t0, c0 = time.perf_counter(), time.process_time()
        code: int | str
        try:
            signal.setitimer(signal.ITIMER_PROF, case["timeout"])
            signal.setitimer(signal.ITIMER_REAL, case["wall_timeout"])
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                code = int(cli_main(case["argv"]) or 0)
        except _Timeout:
            code = "timeout"
        except BaseException:  # noqa: BLE001 - anything else escaping main() is what the table catches
            code = "traceback"
            err.write(traceback.format_exc())
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.setitimer(signal.ITIMER_PROF, 0)
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        result = {
            "id": case["id"], "code": code, "out": out.getvalue()[-4000:], "err": err.getvalue()[-4000:],
            "seconds": time.perf_counter() - t0, "cpu_seconds": time.process_time() - c0,
            "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        }
        real_stdout.write(json.dumps(result) + "\n")
        real_stdout.flush()


if __name__ == "__main__":
    main()
