"""NumPy's standard normals drawn inside compiled loops, bit for bit.

``numpy.random.Generator.standard_normal`` on an SFC64 bit generator is a 256-layer ziggurat
(one 64-bit output per draw in 99 % of the cases: 8 bits pick the layer, one the sign, 52 the
abscissa; the wedges and the tail use more outputs and ``exp`` / ``log1p``). The kernels of
:mod:`fusioncenter._compiled.transitions` run the same algorithm inline, so a particle filter
draws its noise in the pass that uses it, with NumPy's numbers. What they need is NumPy's own
three tables (acceptance bounds ``ki``, widths ``wi``, densities ``fi``): these were generated
at high precision and cannot be recomputed in double precision to the last bit, so
:func:`tables` reads them from the installed NumPy's compiled ``_generator`` module (its ELF
symbol table names them), and accepts them only if the inline draws then reproduce
``standard_normal`` bit for bit on a check stream that exercises the tail and the wedges.
Anything else (another platform, a stripped build, another NumPy algorithm, a failed check)
returns ``None``, and the callers draw through NumPy as before: the results are the same either
way, only the speed differs. NumPy's default generator, PCG64, has its own inline twin
(:func:`pcg64_tables` checks it the same way): the filters of the censoring FCs run on SFC64,
the library's :class:`fusioncenter.particle.LinearGaussianDynamics` on whichever of the two it
is given (the nonlinear FC and the chapters' own models use ``default_rng``).
"""

from __future__ import annotations

import functools
import glob
import math
import os
import struct

import numpy as np

__all__ = ["tables", "pcg64_tables", "draw_state", "set_state", "standard_normal"]

_NAMES = (b"ki_double", b"wi_double", b"fi_double")
#: Draws of the acceptance check (about 0.7 % go through a wedge, 0.03 % through the tail).
CHECK_DRAWS = 200_000


def _elf_symbols(path: str) -> dict[bytes, np.ndarray] | None:
    """The three tables from the ELF file ``path`` (64-bit little-endian), or ``None``."""
    with open(path, "rb") as fh:
        raw = fh.read()
    if raw[:4] != b"\x7fELF" or raw[4] != 2 or raw[5] != 1:
        return None
    shoff, = struct.unpack_from("<Q", raw, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", raw, 0x3A)
    secs = [struct.unpack_from("<IIQQQQIIQQ", raw, shoff + i * shentsize) for i in range(shnum)]
    found: dict[bytes, np.ndarray] = {}
    for sec in secs:
        if sec[1] != 2:  # SHT_SYMTAB
            continue
        strtab = secs[sec[6]]
        for k in range(sec[5] // 24):
            st_name, _info, _other, shndx, value, size = struct.unpack_from(
                "<IBBHQQ", raw, sec[4] + 24 * k)
            start = strtab[4] + st_name
            name = raw[start:raw.index(b"\0", start)]
            if name in _NAMES and size == 256 * 8 and 0 < shndx < shnum:
                home = secs[shndx]
                off = value - home[3] + home[4]
                dtype = np.uint64 if name == b"ki_double" else np.float64
                found[name] = np.frombuffer(raw, dtype, 256, off).copy()
    return found if len(found) == 3 else None


_MASK64 = (1 << 64) - 1


def draw_state(rng: np.random.Generator) -> np.ndarray:
    """The state ``(4,) uint64`` of ``rng``'s SFC64 or PCG64 bit generator, for the inline
    draws: SFC64's four words, or PCG64's 128-bit state (high, low) and increment (high,
    low)."""
    st = rng.bit_generator.state["state"]
    if isinstance(rng.bit_generator, np.random.PCG64):
        return np.array([st["state"] >> 64, st["state"] & _MASK64, st["inc"] >> 64,
                         st["inc"] & _MASK64], dtype=np.uint64)
    return np.array(st["state"], dtype=np.uint64)


def set_state(rng: np.random.Generator, s: np.ndarray) -> None:
    """Give ``rng`` the state ``s`` (:func:`draw_state`'s layout) after the inline draws (the
    rest of its state, the buffered 32-bit half, is untouched: the normals do not use it)."""
    st = rng.bit_generator.state
    if isinstance(rng.bit_generator, np.random.PCG64):
        st["state"]["state"] = (int(s[0]) << 64) | int(s[1])
    else:
        st["state"]["state"] = s
    rng.bit_generator.state = st


@functools.cache
def tables():
    """``(ki, wi, fi, r, inv_r)``: NumPy's ziggurat tables and tail constants, checked, or
    ``None`` (see the module docstring). ``FUSIONCENTER_INLINE_NORMALS=0`` disables them."""
    if os.environ.get("FUSIONCENTER_INLINE_NORMALS", "1") == "0":
        return None
    from fusioncenter._compiled import transitions

    here = os.path.dirname(np.random.__file__)
    for path in sorted(glob.glob(os.path.join(here, "_generator*"))):
        try:
            found = _elf_symbols(path)
        except (OSError, ValueError, struct.error, IndexError):
            found = None
        if found is None:
            continue
        ki, wi, fi = (found[n] for n in _NAMES)
        r = float(wi[255] * 2.0**52)
        zig = (ki, wi, fi, r, 1.0 / r)
        rng = np.random.Generator(np.random.SFC64(20141031))
        s = draw_state(rng)
        mine = np.empty(CHECK_DRAWS)
        transitions.sfc64_normals(s, *zig, mine)
        want = rng.standard_normal(CHECK_DRAWS)
        if np.array_equal(mine, want) and np.array_equal(s, draw_state(rng)):
            return zig
    return None


@functools.cache
def pcg64_tables():
    """:func:`tables` for NumPy's default bit generator, PCG64: the same tables, accepted only
    if the inline PCG64 draws (:data:`fusioncenter._compiled.transitions.pcg64_normals`) then
    reproduce ``standard_normal`` bit for bit, and leave the generator's state where NumPy's
    draws leave it; else ``None``."""
    zig = tables()
    if zig is None:
        return None
    from fusioncenter._compiled import transitions

    rng = np.random.Generator(np.random.PCG64(20141031))
    s = draw_state(rng)
    mine = np.empty(CHECK_DRAWS)
    transitions.pcg64_normals(s, *zig, mine)
    want = rng.standard_normal(CHECK_DRAWS)
    return zig if np.array_equal(mine, want) and np.array_equal(s, draw_state(rng)) else None


#: Below this many normals, NumPy's own call is cheaper than reading and writing the state
#: (about 4 us for both: 19 ns a normal for 200 draws inline, 12 through NumPy; 2.9 against
#: 8.5 for 20 000).
INLINE_MIN = 4096


def standard_normal(rng: np.random.Generator, shape: tuple) -> np.ndarray:
    """``rng.standard_normal(shape)``: the same numbers, and ``rng`` left in the same state,
    drawn by the compiled ziggurat (:data:`fusioncenter._compiled.transitions.sfc64_normals` or
    ``pcg64_normals``) when ``rng`` runs on SFC64 or PCG64, the tables check (:func:`tables`,
    :func:`pcg64_tables`) and there are at least :data:`INLINE_MIN` draws; else by NumPy."""
    n = math.prod(shape)
    kind = type(rng.bit_generator)
    zig = None
    if n >= INLINE_MIN and kind in (np.random.SFC64, np.random.PCG64):
        zig = tables() if kind is np.random.SFC64 else pcg64_tables()
    if zig is None:
        return rng.standard_normal(shape)
    from fusioncenter._compiled import transitions

    fill = (transitions.sfc64_normals if kind is np.random.SFC64
            else transitions.pcg64_normals)
    out = np.empty(shape)
    s = draw_state(rng)
    fill(s, *zig, out)
    set_state(rng, s)
    return out
