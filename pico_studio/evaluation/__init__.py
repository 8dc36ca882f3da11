"""Everything that scores perception, localisation and behaviour against ground truth.

One package, one scorer: the session loop yields frames, the observers here judge them.
"""

from __future__ import annotations
