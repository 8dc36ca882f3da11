"""`python -m pico_studio` runs the CLI."""

from __future__ import annotations

from pico_studio.cli import main

raise SystemExit(main())
