"""The operation counts of one filter step (the cost model of the comparison): the Kalman
filter's (:func:`kf_flops`) and the particle filter's (:func:`pf_flops`), term by term as the
code computes them."""

from __future__ import annotations

from fusioncenter import _validate as _v
from fusioncenter.comparison._args import doc
from fusioncenter.comparison.particle_family import PF_SCHEMES

__all__ = ["kf_flops", "pf_flops"]


def _matmul(a: int, b: int, c: int) -> int:
    """Floating-point operations of an ``(a, b) @ (b, c)`` product: ``a c (2 b - 1)``."""
    return a * c * (2 * b - 1)


def _solve(k: int, rhs: int) -> int:
    """LU solve of a ``k x k`` system with ``rhs`` right-hand sides: ``2k^3/3 + 2 k^2 rhs``."""
    return (2 * k**3) // 3 + 2 * k * k * rhs


@doc(returns=("dict", '``{"flops": int, "special": int}``.'),
     n=("int", "State dimension."), m=("int", "Number of sensors."))
def kf_flops(n: int = 2, m: int = 2) -> dict[str, int]:
    """Operation count of one step of
    :func:`~fusioncenter.comparison.kalman_family.kf_filter` for one trial (``n`` states, ``m``
    sensors), term by term as the code computes it (a dropped or silent sensor costs the same):
    ``flops`` counts additions and multiplications, ``special`` the exponentials of the trigger.
    """
    f, n, m = 0, _v.posint("n", n), _v.posint("m", m)
    f += _matmul(1, n, m) + m  # innovations nu = z - xpred H^T
    f += 3 * m  # the trigger (nu^2 / (2 delta)), or the random-selection comparison
    f += _matmul(n, n, m)  # P C^T
    f += _matmul(m, n, m) + m  # S = C P C^T + R
    f += _solve(m, 1) + _matmul(n, m, 1) + n  # S^{-1} nu, xpost
    f += _solve(m, n) + _matmul(n, m, n) + n * n  # P - P C^T S^{-1} C P
    f += _matmul(1, n, n)  # xpred = F xpost
    f += 2 * _matmul(n, n, n) + n * n  # F P F^T + Q
    return {"flops": int(f), "special": m}


@doc(returns=("dict", '``{"flops": int, "special": int}``, for all the particles.'),
     n=("int", "State dimension."), m=("int", "Number of sensors."),
     scheme=("str", '``"all-send"``, ``"random"``, ``"cfomd"`` or ``"cfwmd"``.'))
def pf_flops(n: int = 2, m: int = 2, n_particles: int = 1000,
             scheme: str = "cfwmd") -> dict[str, int]:
    """Operation count of one step of the particle filter (zheng2014, state feedback) for one
    trial: per particle, the propagation ``F x + L u`` (``rank Q = 1``: one normal), ``h_i^T x``
    for each sensor, the Gaussian term of each received sensor (3 flops), for CFwMD the silent
    sensor's ``log(Phi(b) - Phi(a))`` (4 flops and 3 special functions per sensor), the weight
    normalization (max, exp, sum: 3 flops and 1 exp), the weighted mean (``2 n``), the ESS (2)
    and systematic resampling (cumulative sum and search, ~4). Counted with every sensor both
    received and silent as the worst case, so it is an upper estimate of a step's work;
    ``special`` counts exponentials, logarithms, ``ndtr`` calls and normal draws.
    """
    if scheme not in ("all-send", "random") + PF_SCHEMES:
        raise ValueError(f"scheme must be 'all-send', 'random', 'cfomd' or 'cfwmd', "
                         f"got {scheme!r}")
    n, m, n_particles = _v.posint("n", n), _v.posint("m", m), _v.posint("n_particles", n_particles)
    per = _matmul(1, n, n) + 2 * n  # F x + L u
    per += m * (2 * n - 1)  # h_i^T x
    per += 3 * m  # received: -(z - hx)^2 / (2 r)
    special = 1  # the normal draw of the propagation
    if scheme == "cfwmd":
        per += 4 * m  # (hx - h xpred)/sd, h -/+ m, the difference
        special += 3 * m  # two ndtr and one log per silent sensor
    per += 3  # normalization: subtract the max, sum, divide
    special += 1  # exp of the weight
    per += 2 * n + 2 + 4  # weighted mean, ESS, resampling
    return {"flops": int(per * n_particles), "special": int(special * n_particles)}
