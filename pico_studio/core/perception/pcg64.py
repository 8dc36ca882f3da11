"""numpy's default random generator (PCG64) and its `integers`, drawn inside compiled loops.

`np.random.default_rng(seed)` is PCG64 (O'Neill 2014): a 128-bit linear congruential
generator whose 64-bit output is a permutation of its state,

    state <- state * M + inc   (mod 2^128),   M = 0x2360ED051FC65DA4_4385DF649FCCF645
    out    = rotr64(hi(state) xor lo(state), hi(state) >> 58)             (XSL-RR)

A 32-bit draw is the low half of a 64-bit output; the high half is kept for the next 32-bit
draw. `Generator.integers(0, n, size)` for n <= 2^32 is Lemire's method (arXiv:1805.10941),
one 32-bit draw x per integer, redrawn (rarely) to remove the bias:

    p = x * n,   leftover = p mod 2^32,   redraw while leftover < (2^32 - n) mod n,   draw = p >> 32

Handing a numpy Generator to a compiled function costs ~6 us per call and seeding one another
~6 us: more than RANSAC's own work on a scan. So the state a seed gives is taken from numpy
once (`seeded_state`) and the same integers are drawn here (checked against numpy's in
tests/test_jit_perception.py). The state is a (6,) uint64 array: hi, lo of the 128-bit state,
hi, lo of the increment, whether a 32-bit half is kept, and that half.

The 128-bit arithmetic is done on 32-bit halves, so no uint64 operation overflows (the same
in the compiled code and in its Python).
"""

from __future__ import annotations

import numpy as np

from pico_studio.jit import njit

LOW = np.uint64(0xFFFFFFFF)
HALF = np.uint64(32)
MUL_HI = np.uint64(0x2360ED051FC65DA4)
MUL_LO = np.uint64(0x4385DF649FCCF645)
ROT_SHIFT = np.uint64(58)
ZERO, ONE, SIXTY_FOUR, SIXTY_THREE = np.uint64(0), np.uint64(1), np.uint64(64), np.uint64(63)


@njit
def _mul(a: np.uint64, b: np.uint64) -> tuple[np.uint64, np.uint64]:
    """(hi, lo) of the 128-bit product a * b."""
    a0, a1 = a & LOW, a >> HALF
    b0, b1 = b & LOW, b >> HALF
    p00, p01, p10, p11 = a0 * b0, a0 * b1, a1 * b0, a1 * b1
    mid = (p00 >> HALF) + (p01 & LOW) + (p10 & LOW)
    return p11 + (p01 >> HALF) + (p10 >> HALF) + (mid >> HALF), ((mid & LOW) << HALF) | (p00 & LOW)


@njit
def _add(a: np.uint64, b: np.uint64) -> tuple[np.uint64, np.uint64]:
    """(carry, a + b mod 2^64)."""
    lo = (a & LOW) + (b & LOW)
    hi = (a >> HALF) + (b >> HALF) + (lo >> HALF)
    return hi >> HALF, ((hi & LOW) << HALF) | (lo & LOW)


@njit
def next64(state: np.ndarray) -> np.uint64:
    """Step the state, return its XSL-RR output."""
    hi, lo = _mul(state[1], MUL_LO)  # state * M mod 2^128: lo * M_lo in full, the cross terms' low halves
    _, hi = _add(hi, _mul(state[1], MUL_HI)[1])
    _, hi = _add(hi, _mul(state[0], MUL_LO)[1])
    carry, lo = _add(lo, state[3])  # + inc
    _, hi = _add(hi, state[2])
    _, hi = _add(hi, carry)
    state[0], state[1] = hi, lo
    rot = hi >> ROT_SHIFT
    v = hi ^ lo
    return (v >> rot) | (v << ((SIXTY_FOUR - rot) & SIXTY_THREE))


@njit
def next32(state: np.ndarray) -> np.uint64:
    """A 32-bit draw: the kept high half of the last output, else the low half of a new one."""
    if state[4] != ZERO:
        state[4] = ZERO
        return state[5]
    v = next64(state)
    state[4], state[5] = ONE, v >> HALF
    return v & LOW


@njit
def integers_into(state: np.ndarray, n: int, out: np.ndarray) -> None:
    """Fill the int64 array `out` with draws from [0, n), as `Generator.integers(0, n,
    size=len(out))` would return them (1 <= n <= 2^32)."""
    if n == 1:
        out[:] = 0  # numpy draws nothing
        return
    if n == 1 << 32:
        for i in range(out.shape[0]):
            out[i] = next32(state)
        return
    n_u = np.uint64(n)
    threshold = (LOW - (n_u - ONE)) % n_u
    for i in range(out.shape[0]):
        p = next32(state) * n_u
        leftover = p & LOW
        if leftover < n_u:
            while leftover < threshold:
                p = next32(state) * n_u
                leftover = p & LOW
        out[i] = p >> HALF


@njit
def integers(state: np.ndarray, n: int, size: int) -> np.ndarray:
    """(size,) int64 draws from [0, n), as `Generator.integers(0, n, size)` (1 <= n <= 2^32)."""
    out = np.empty(size, dtype=np.int64)
    integers_into(state, n, out)
    return out


_SEEDED: dict[int, np.ndarray] = {}


def seeded_state(seed: int) -> np.ndarray:
    """The state of `np.random.default_rng(seed)`, fresh (a copy: drawing advances it)."""
    state = _SEEDED.get(seed)
    if state is None:
        s = np.random.default_rng(seed).bit_generator.state
        mask = (1 << 64) - 1
        st, inc = s["state"]["state"], s["state"]["inc"]
        state = np.array([st >> 64, st & mask, inc >> 64, inc & mask, s["has_uint32"], s["uinteger"]], dtype=np.uint64)
        if len(_SEEDED) >= 64:  # a few seeds in a run; a tuning study may try many
            _SEEDED.clear()
        _SEEDED[seed] = state
    return state.copy()
