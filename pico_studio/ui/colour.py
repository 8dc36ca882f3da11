"""Making line colours show as declared, despite the renderer's tone mapping.

viser's page renders with three.js's ACES-filmic tone mapping and an sRGB output, and its
line segments are tone-mapped (its point clouds are not). A line's colour reaches the tone
curve as a linear value, which depends on how it is sent:
- one colour for the whole node (a hex colour): three.js decodes it from sRGB to linear;
- per-vertex colours: taken as linear as they are (c / 255).
Either way a wall declared dark grey (40, 40, 40) would show much lighter. So for lines we
find the linear value whose *displayed* colour is nearest the declared one and send that,
encoded for the way it is sent (`line_uniform`, `line_vertex`); `line_display` says what
the page will show. Bright saturated colours lie beyond the tone curve (its maximum is
about 226 grey); `style.py` keeps line colours within reach.

The maths (three.js `ACESFilmicToneMapping`, exposure 1), x linear in 0..1:
    x = x / 0.6;  v = M_in x;  v = (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.4329510) + 0.238081)
    out = clamp(M_out v, 0, 1);  displayed = srgb_encode(out)
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

# three.js's matrices (rows here = columns of its GLSL mat3 literals)
_M_IN = np.array([[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]])
_M_OUT = np.array([[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605], [-0.00327, -0.07276, 1.07602]])


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    c = np.clip(encoded, 0.0, 1.0)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def aces_display(linear: np.ndarray) -> np.ndarray:
    """What the page shows (sRGB, 0..255 float) for a linear line colour (0..1)."""
    x = np.asarray(linear, dtype=float) / 0.6
    v = x @ _M_IN.T
    v = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081)
    return srgb_encode(v @ _M_OUT.T) * 255.0


@lru_cache(maxsize=256)
def linear_for(target: tuple[int, int, int]) -> tuple[float, float, float]:
    """The linear colour (0..1) whose displayed value is nearest `target`: the grey curve
    inverted channel by channel as a start, then damped Gauss-Newton for the channel mixing."""
    t = np.array(target, dtype=float)
    grid = np.linspace(0.0, 1.0, 2049)
    grey = aces_display(np.repeat(grid[:, None], 3, axis=1))[:, 0]
    x = np.interp(t, grey, grid)
    h = 1e-4
    for _ in range(60):
        f = aces_display(x) - t
        jac = np.empty((3, 3))
        for k in range(3):
            dx = np.zeros(3)
            dx[k] = h
            jac[:, k] = (aces_display(x + dx) - aces_display(x - dx)) / (2 * h)
        step = np.clip(np.linalg.lstsq(jac, -f, rcond=None)[0], -0.05, 0.05)
        x = np.clip(x + step, 1e-4, 1.0)  # at 0 the curve is flat: keep a gradient
        if np.abs(step).max() < 1e-7:
            break
    return tuple(float(v) for v in x)  # type: ignore[return-value]


def _map(rgb: tuple[int, int, int] | np.ndarray, encode: bool) -> np.ndarray:
    a = np.asarray(rgb, dtype=np.uint8)
    flat = a.reshape(-1, 3).astype(np.uint32)
    # one int per colour: np.unique on them is far cheaper than on rows (this runs per frame)
    keys = (flat[:, 0] << 16) | (flat[:, 1] << 8) | flat[:, 2]
    uniq, inverse = np.unique(keys, return_inverse=True)
    sent = np.array([_sent(int(k), encode) for k in uniq], dtype=np.uint8).reshape(-1, 3)
    return sent[inverse.reshape(-1)].reshape(a.shape)


@lru_cache(maxsize=1024)
def _sent(key: int, encode: bool) -> tuple[int, int, int]:
    lin = np.array(linear_for((key >> 16, (key >> 8) & 255, key & 255)))
    return tuple(int(v) for v in np.round((srgb_encode(lin) if encode else lin) * 255.0))  # type: ignore[return-value]


def line_uniform(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    """The colour to give a whole line node so that it shows as `rgb`."""
    return tuple(int(v) for v in _map(rgb, encode=True))  # type: ignore[return-value]


def line_vertex(rgb: np.ndarray) -> np.ndarray:
    """Per-vertex line colours (..., 3) to send so that they show as `rgb`."""
    return _map(rgb, encode=False)


def line_display(rgb: tuple[int, int, int], *, per_vertex: bool = False) -> tuple[int, int, int]:
    """How a line declared `rgb` shows on the page (sent per vertex or as one colour)."""
    if per_vertex:
        lin = line_vertex(np.array(rgb)).astype(float) / 255.0
    else:
        lin = srgb_decode(np.array(line_uniform(rgb), dtype=float) / 255.0)
    return tuple(int(round(v)) for v in aces_display(lin))  # type: ignore[return-value]
