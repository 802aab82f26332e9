"""Input validators shared by the modules (each raises ``ValueError`` naming the argument).

The rule they enforce at the public surface: a function either returns finite, meaningful
numbers or raises ``ValueError`` (or a named subclass) whose message starts with the name of the
offending argument and states the reason. NaN and infinities are rejected by every numeric
validator; covariances are checked symmetric and positive semi-definite (or definite) with a
relative tolerance. The validators never modify the values they accept (``covariance`` returns
the input unchanged, not symmetrized), so accepting an input does not change any result bit.

* ``is_text(value) -> bool``: text, or a sequence/array holding text (refused by every
  numeric validator: NumPy would turn ``"1"`` into ``1.0``).
* ``posint(name, value) -> int``: a positive integer (``bool`` rejected, NumPy integers
  accepted).
* ``integer(name, value, minimum=0) -> int``: an integer ``>= minimum`` (``bool`` rejected).
* ``finite(name, value) -> ndarray``: a float array with finite entries (text such as ``"1"``
  is rejected, not converted).
* ``positive(name, value, what="a variance") -> ndarray``: finite and ``> 0``.
* ``nonneg(name, value, what=None) -> ndarray``: finite and ``>= 0``.
* ``one_of(name, value, options)``: ``value`` must be one of ``options``.
* ``flags(name, value) -> ndarray``: booleans (or integers 0/1), as a bool array.
* ``generator(name, value)``: a ``numpy.random.Generator``.
* ``covariance(name, value, *, definite=False, n=None, batch=False) -> ndarray``: a finite,
  square, symmetric, positive semi-definite (or definite) matrix, or a stack of them.
* ``square(name, arr) -> ndarray``: a 2-D array must be square (a state transition ``A``).
* ``nonempty(name, arr, what) -> ndarray``: the last axis (a state or a sensor axis) must not
  have length 0 (a 0x0 state matrix is not a model).
* ``finite_result(name, value, why) -> ndarray``: a computed result must be finite (raises
  ``ValueError`` saying why it is not: an overflow the inputs caused).
* ``shape_is(name, arr, shape, what)``: ``arr.shape`` must equal ``shape`` (``None`` entries
  free); the message states the expected shape.
* ``broadcast(**arrays)``: broadcast arrays together, or raise ``ValueError`` naming them and
  their shapes (instead of NumPy's message).
* ``received(sent, z, name="z") -> (sent, z)``: measurements that must be finite where a
  sensor sent (ignored, and may be NaN, elsewhere).
* ``finite_where(mask, values, mismatch=..., missing=...) -> (mask, values)``: the same check
  with the caller's messages, returning both broadcast together.
* ``consistent(name, S, rhs, scale)``: a measurement must lie in the range of its singular
  innovation covariance ``S`` (up to 40 standard deviations along its near-zero directions),
  otherwise it contradicts the model (a noise-free sensor measuring a direction the prior
  already knows, differently).

``what`` is the reason stated in the message, e.g. ``"x must be positive (a variance), got 0"``.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._docstrings import Glossary

__all__ = ["is_text", "as_float", "posint", "integer", "finite", "positive", "nonneg", "one_of",
           "flags", "generator",
           "covariance", "square", "nonempty", "finite_result", "shape_is", "broadcast", "received",
           "finite_where", "consistent", "SYMMETRY_RTOL", "PSD_RTOL", "CONSISTENCY_RTOL"]

#: Relative tolerance of the symmetry check of :func:`covariance`: ``|M - M^T| <= SYMMETRY_RTOL
#: * max |M|`` entrywise.
SYMMETRY_RTOL = 1e-10
#: Relative tolerance of the semi-definiteness check: the smallest eigenvalue of ``(M + M^T)/2``
#: must be ``>= -PSD_RTOL * max |M|`` (rounding in a computed covariance gives eigenvalues of
#: order ``-1e-16 * max |M|``); for ``definite=True`` it must be ``> PSD_RTOL * max |M|``.
PSD_RTOL = 1e-10
#: Relative tolerance of :func:`consistent`: a measurement may leave the range of its singular
#: innovation covariance by at most ``CONSISTENCY_RTOL`` times its scale (rounding only).
CONSISTENCY_RTOL = 1e-8

#: The arguments the validators share, by name.
_doc = Glossary("""
name : str
    The argument's name, used in the message.
value : array_like
    Numbers (Python or NumPy scalars, sequences, arrays).
""")
#: ``value`` of the validators that accept anything and check its type.
_ANY = ("object", "The value to check.")


@_doc(returns=("int", "``value`` as a Python ``int``."), value=_ANY, raises=((
    "ValueError", "If ``value`` is not an integer ``>= 1`` (``True`` is not an integer here)."),))
def posint(name: str, value) -> int:
    """A positive integer (Python or NumPy integer; ``bool`` rejected)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


@_doc(returns=("int", "``value`` as a Python ``int``."),
      value=("object", "The value to check (a seed, a number of steps, an index)."),
      minimum=("int", "The smallest value accepted."),
      raises=(("ValueError", "If ``value`` is not an integer (``True``, ``2.0`` and ``\"3\"`` are "
                             "not) or is below\n``minimum``."),))
def integer(name: str, value, minimum: int = 0) -> int:
    """An integer ``>= minimum`` (Python or NumPy integer; ``bool`` rejected)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def is_text(value) -> bool:
    """Whether ``value`` is (or holds) text: NumPy would turn ``"1"`` into ``1.0`` silently."""
    if isinstance(value, str | bytes):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "USO" and (value.dtype.kind != "O" or any(
            isinstance(e, str | bytes) for e in value.flat))
    if isinstance(value, list | tuple):
        return any(is_text(e) for e in value)
    return False


@_doc(returns=("numpy.ndarray", "``numpy.asarray(value, dtype=float)`` (0-d for a scalar)."),
      raises=(("ValueError", "If ``value`` is text, complex or not convertible to floats."),))
def as_float(name: str, value) -> np.ndarray:
    """A float array, any values (NaN and infinities allowed); text and complex refused."""
    if is_text(value):
        raise ValueError(f"{name} must be a real number or array of them, not text, "
                         f"got {value!r}")
    if np.iscomplexobj(value):  # NumPy would drop the imaginary part with a warning
        raise ValueError(f"{name} must be real, not complex, got {value!r}")
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number or array of them, got {value!r}") from None


@_doc(returns=("numpy.ndarray", "``numpy.asarray(value, dtype=float)`` (0-d for a scalar)."),
      raises=(("ValueError", "If ``value`` is not convertible to floats or has a NaN or infinite "
                             "entry."),))
def finite(name: str, value) -> np.ndarray:
    """A float array with finite entries."""
    arr = as_float(name, value)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return arr


@_doc(returns=("numpy.ndarray", "The values as floats."),
      what=("str", "Why the value must be positive, quoted in the message."),
      raises=(("ValueError", "If an entry is NaN, infinite or ``<= 0``."),))
def positive(name: str, value, what: str = "a variance") -> np.ndarray:
    """A finite float array with entries ``> 0``."""
    arr = finite(name, value)
    if np.any(arr <= 0):
        raise ValueError(f"{name} must be positive ({what}), got {value!r}")
    return arr


@_doc(returns=("numpy.ndarray", "The values as floats."),
      what=("str, optional", "Why the value must be non-negative, quoted in the message."),
      raises=(("ValueError", "If an entry is NaN, infinite or negative."),))
def nonneg(name: str, value, what: str | None = None) -> np.ndarray:
    """A finite float array with entries ``>= 0``."""
    arr = finite(name, value)
    if np.any(arr < 0):
        why = f" ({what})" if what else ""
        raise ValueError(f"{name} must be non-negative{why}, got {value!r}")
    return arr


def one_of(name: str, value, options) -> None:
    """``value`` must be one of ``options``.

    Parameters
    ----------
    name : str
        The argument's name, used in the message.
    value : object
        Checked for membership.
    options : container
        The allowed values.

    Raises
    ------
    ValueError
        If ``value not in options``.
    """
    if value not in options:
        raise ValueError(f"{name} must be one of {options}, got {value!r}")


@_doc(returns=("numpy.ndarray", "``value`` as a bool array."),
      value=("array_like", "Booleans, or integers that are all 0 or 1."),
      raises=(("ValueError", "If ``value`` holds anything else (``0.5``, ``2``, text)."),))
def flags(name: str, value) -> np.ndarray:
    """Booleans (e.g. who sent, which packet was lost); integers 0/1 accepted."""
    arr = np.asarray(value)
    if arr.dtype.kind not in "biu" or (arr.dtype.kind != "b" and np.any((arr != 0)
                                                                        & (arr != 1))):
        raise ValueError(f"{name} must hold booleans (or 0/1), got {value!r}")
    return arr.astype(bool)


@_doc(returns=("numpy.random.Generator", "``value``, unchanged."), value=_ANY,
      raises=(("ValueError", "If ``value`` is not a ``numpy.random.Generator`` (a seed is "
                             "not: the caller\nspawns from the generator)."),))
def generator(name: str, value) -> np.random.Generator:
    """A ``numpy.random.Generator``."""
    if not isinstance(value, np.random.Generator):
        raise ValueError(f"{name} must be a numpy.random.Generator, got {value!r}")
    return value


@_doc(returns=("numpy.ndarray", "The matrix as floats, unchanged (not symmetrized)."),
      value=("array_like", "A matrix ``(n, n)``, or with ``batch=True`` a stack ``(..., n, n)`` "
                           "of them."),
      definite=("bool", "Require positive definiteness (smallest eigenvalue ``> PSD_RTOL * max "
                        "|M|``) instead of\nsemi-definiteness (``>= -PSD_RTOL * max |M|``)."),
      n=("int, optional", "The required size."), batch=("bool", "Allow leading (batch) axes."),
      raises=(("ValueError", "If it is not finite, not a (stack of) square matrices of the right "
                             "size, not symmetric\nto ``SYMMETRY_RTOL``, or has an eigenvalue "
                             "below the tolerance."),))
def covariance(name: str, value, *, definite: bool = False, n: int | None = None,
               batch: bool = False) -> np.ndarray:
    """A covariance matrix: finite, square, symmetric and positive semi-definite (or definite)."""
    arr = finite(name, value)
    if arr.ndim < 2 or (arr.ndim > 2 and not batch) or arr.shape[-1] != arr.shape[-2]:
        want = "a square matrix (..., n, n)" if batch else "a square matrix (n, n)"
        raise ValueError(f"{name} must be {want}, got shape {arr.shape}")
    if n is not None and arr.shape[-1] != n:
        raise ValueError(f"{name} must be {n}x{n}, got shape {arr.shape}")
    if arr.size == 0:
        return arr
    scale = np.abs(arr).max(axis=(-2, -1), keepdims=True)
    asym = np.abs(arr - np.swapaxes(arr, -1, -2))
    if np.any(asym > SYMMETRY_RTOL * scale):
        raise ValueError(f"{name} must be symmetric (a covariance), got {value!r}")
    low = np.linalg.eigvalsh(0.5 * (arr + np.swapaxes(arr, -1, -2)))[..., 0]
    tol = PSD_RTOL * scale[..., 0, 0]
    if definite and np.any(low <= tol):
        raise ValueError(f"{name} must be positive definite, got smallest eigenvalue "
                         f"{float(np.min(low)):.3g}")
    if np.any(low < -tol):
        raise ValueError(f"{name} must be positive semi-definite (a covariance), got smallest "
                         f"eigenvalue {float(np.min(low)):.3g}")
    return arr


@_doc(returns=("numpy.ndarray", "``arr``, unchanged."),
      arr=("numpy.ndarray", "A 2-D array (the caller has converted and checked it)."),
      raises=(("ValueError", "If ``arr`` is not square."),))
def square(name: str, arr: np.ndarray) -> np.ndarray:
    """A matrix must be square."""
    if arr.shape != (arr.shape[0],) * 2:
        raise ValueError(f"{name} must be square, got {arr.shape}")
    return arr


@_doc(returns=("numpy.ndarray", "``arr``, unchanged."),
      arr=("numpy.ndarray", "An array whose last axis is the state (or the sensors)."),
      what=("str", "What the axis is, quoted in the message."),
      raises=(("ValueError", "If ``arr`` has no axis or its last axis has length 0."),))
def nonempty(name: str, arr, what: str = "a state of dimension 0 is not a model") -> np.ndarray:
    """The last axis of ``arr`` must not be empty (e.g. a ``0x0`` state matrix)."""
    shape = np.shape(arr)
    if not shape or shape[-1] == 0:
        raise ValueError(f"{name} must not be empty ({what}), got shape {shape}")
    return arr


@_doc(returns=("numpy.ndarray", "``value`` as an array, unchanged."),
      name=("str", "What was computed, used in the message."), value=("array_like", "The result."),
      why=("str", "Which inputs make it overflow, quoted in the message."),
      raises=(("ValueError", "If an entry is NaN or infinite."),))
def finite_result(name: str, value, why: str) -> np.ndarray:
    """A computed result must be finite."""
    arr = np.asarray(value)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} is not finite: {why}")
    return arr


def shape_is(name: str, arr, shape: tuple, what: str = "") -> np.ndarray:
    """``arr`` must have ``shape`` (``None`` entries free; a leading ``...`` allows batch axes).

    Parameters
    ----------
    name : str
        The argument's name, used in the message.
    arr : numpy.ndarray
        The (converted) argument.
    shape : tuple
        The expected shape: integers, ``None`` (any length) and an optional leading ``...``.
    what : str
        Why, quoted in the message (e.g. ``"P is 2x2"``).

    Returns
    -------
    numpy.ndarray
        ``arr``, unchanged.

    Raises
    ------
    ValueError
        If the shape differs; the message states the expected shape.
    """
    got = np.shape(arr)
    want = tuple(shape)
    lead = bool(want) and want[0] is Ellipsis
    tail = want[1:] if lead else want
    ok = (len(got) >= len(tail)) if lead else (len(got) == len(tail))
    if ok:
        ok = all(w is None or g == w for g, w in zip(got[len(got) - len(tail):], tail,
                                                      strict=True))
    if not ok:
        txt = ", ".join("..." if w is Ellipsis else ("k" if w is None else str(w)) for w in want)
        why = f" ({what})" if what else ""
        raise ValueError(f"{name} must have shape ({txt}){why}, got {got}")
    return arr


def broadcast(**arrays) -> list[np.ndarray]:
    """Broadcast the named arrays together, or raise ``ValueError`` naming them and their shapes.

    Parameters
    ----------
    **arrays : numpy.ndarray
        The arrays, by argument name.

    Returns
    -------
    list of numpy.ndarray
        ``numpy.broadcast_arrays`` of them, in order.

    Raises
    ------
    ValueError
        If the shapes do not broadcast (the message lists every argument's shape).
    """
    try:
        return list(np.broadcast_arrays(*arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {np.shape(v)}" for k, v in arrays.items())
        raise ValueError(f"{', '.join(arrays)} must have shapes that broadcast together, got "
                         f"{shapes}") from None


def consistent(name: str, S, rhs, scale, rcond: float = 1e-10) -> None:
    """A measurement must lie in the range of its (singular) innovation covariance.

    Along an eigenvector ``v`` of ``S`` whose eigenvalue ``lam`` counts as zero (``lam <= rcond
    * max lam``, the pseudo-inverse's rule), the innovation ``v^T rhs`` is a
    ``N(0, lam)`` draw; if it exceeds ``CONSISTENCY_RTOL * scale + 40 sqrt(max(lam, 4 eps
    max lam))`` (eigenvalues are known to rounding only) the
    measurement has a component along a direction in which it has (next to) no uncertainty
    (``P = 0`` and ``R = 0`` there): the measured value contradicts the model, and no
    posterior exists. A merely ill-conditioned ``S`` (one large noise variance beside a small
    one) passes: its small directions are 40-sigma consistent.

    Parameters
    ----------
    name : str
        The measurement's (or innovation's) name, used in the message.
    S : numpy.ndarray
        ``(..., m, m)``, symmetric PSD.
    rhs : numpy.ndarray
        ``(..., m, k)``: the innovations.
    scale : float
        The magnitude of the measurement (e.g. ``max |y|``); at least 1 is used.
    rcond : float
        The pseudo-inverse's relative threshold.

    Raises
    ------
    ValueError
        If an innovation leaves the range of ``S`` by more than the tolerance.
    """
    S = np.asarray(S)
    rhs = np.asarray(rhs)
    if S.size == 0 or rhs.size == 0:
        return
    lam, V = np.linalg.eigh(S)
    top = np.abs(lam).max(axis=-1, keepdims=True)
    zero = lam <= rcond * top  # (..., m)
    if not np.any(zero):
        return
    proj = np.abs(np.swapaxes(V, -1, -2) @ rhs)  # (..., m, k)
    # an eigenvalue is known to about eps * max lam only: data drawn with a square root of a
    # computed covariance carry sqrt(eps * max lam) along its null directions
    floor = 4.0 * np.finfo(float).eps * top
    lim = CONSISTENCY_RTOL * max(1.0, float(scale)) + 40.0 * np.sqrt(np.maximum(lam, floor))
    bad = zero[..., None] & (proj > lim[..., None])
    if np.any(bad):
        worst = float(np.max(np.where(bad, proj, 0.0)))
        raise ValueError(f"{name} contradicts the model: the innovation covariance is singular "
                         f"(P = 0 and R = 0 along a measured direction) and the measurement "
                         f"differs from its prediction there by {worst:.3g}; no posterior "
                         f"exists")


def received(sent, z, name: str = "z", *, axis_extra: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Who sent and what arrived: ``z`` must be finite where ``sent`` is true.

    Parameters
    ----------
    sent : array_like
        Booleans ``(..., N)`` (0/1 accepted).
    z : array_like
        Measurements ``(..., N)`` (with ``axis_extra`` trailing axes per sensor, e.g. ``m`` for
        vector observations); ignored, and allowed to be NaN, where a sensor was silent.
    name : str
        The measurements' name, used in the message.
    axis_extra : int
        Number of trailing axes of ``z`` beyond those of ``sent``.

    Returns
    -------
    tuple of numpy.ndarray
        ``sent`` as bool and ``z`` as floats (unchanged).

    Raises
    ------
    ValueError
        If ``z`` is text, the shapes do not broadcast, or a sent entry is NaN or infinite.
    """
    sent = np.asarray(sent)
    if sent.dtype.kind not in "biu" or (sent.dtype.kind != "b" and np.any((sent != 0)
                                                                          & (sent != 1))):
        raise ValueError(f"sent must hold booleans (or 0/1), got {sent!r}")
    sent = sent.astype(bool)
    z = as_float(name, z)
    finite_where(sent.reshape(sent.shape + (1,) * axis_extra), z,
                 mismatch=f"sent and {name} must have shapes that broadcast together, got sent "
                 f"{sent.shape}, {name} {z.shape}",
                 missing=f"{name} must be finite where a sensor sent (a received measurement)")
    return sent, z


def finite_where(mask, values, *, mismatch: str, missing: str) -> tuple[np.ndarray, np.ndarray]:
    """``(mask, values)`` broadcast together, ``values`` finite where ``mask`` is true (a received
    measurement; anything, NaN included, elsewhere). ``ValueError(mismatch)`` if the shapes do
    not broadcast, ``ValueError(missing)`` if a received value is NaN or infinite."""
    try:
        mask_b, values_b = np.broadcast_arrays(mask, values)
    except ValueError:
        raise ValueError(mismatch) from None
    if not np.all(np.isfinite(values_b[mask_b])):
        raise ValueError(missing)
    return mask_b, values_b
