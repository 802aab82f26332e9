"""zheng2014 Section VII.A.1: our particle filter against a hand-fused reference kernel.

Setting: the linear scenario's defaults (``N = 2`` sensors measuring the position, ``r = 1``,
white-noise acceleration, ``x_0`` known, ``T = 20``), 32 trials x 1000 particles x 20 steps
(one sub-block of :func:`fusioncenter.censoring.fusion.sub_blocks`), ``l = 1``.

Variants, timed in ONE interleaved run (each round runs every variant once, in turn; the
median over rounds of each variant's CPU time, ``time.process_time``, is reported as ns per
particle-step, with the ratios of the medians):

* ``ours all-send`` and ``ours CFwMD`` (state feedback): a
  :class:`~fusioncenter.censoring.fusion.LinearFusionCentre` built and run through
  :func:`fusioncenter.particle.run_filter`, as ``censoring.run``'s ``_chunk`` does for one
  sub-block (the truth and measurements are drawn beforehand, outside the timing); its
  transition draws NumPy's normals inside the propagation pass when
  :func:`fusioncenter._compiled.ziggurat.tables` is available (the run says whether);
* ``reference, NumPy draws``: all-send written by hand as one compiled pass per step and trial
  (:func:`_ref_block`: propagate, the sensors' Gaussian log-likelihood and its maximum; then
  ``exp``, the weight sum, the weighted means and the ESS; then systematic resampling fused
  with the gather), the normals and uniforms drawn with the same NumPy SFC64 generator in the
  same order as ours (one ``standard_normal(out=)`` and one ``random(n)`` per step), so its
  random numbers are NumPy's bit for bit;
* ``reference, in-kernel draws``: the same kernel drawing its normals and uniforms inside the
  compiled pass: SFC64 (NumPy's algorithm, started from the same state) and a 256-layer
  ziggurat laid out as NumPy's, with NumPy's own tables when
  :func:`fusioncenter._compiled.ziggurat.tables` can read them (then its normals are NumPy's bit for
  bit; otherwise tables computed here in double precision, whose last bits differ from
  NumPy's: the run prints the fraction of equal draws), trial by trial (so in another order
  than ours: statistically equivalent, not the same numbers). The practical floor.

Checks before timing (the run prints them): on 256 trials, the position and velocity RMSE of
each variant against the truth and the RMS distance of its estimate to the exact Kalman filter
(all-send is linear-Gaussian: the KF is the Bayes filter), and the paired difference of the
per-trial squared errors between ours and each reference (mean and standard error: the
variants must agree statistically). The NumPy-draws reference consumes exactly our random
numbers; its estimates differ from ours by rounding only (Numba's ``exp`` is glibc's, NumPy's
its own AVX-512 routine; they differ in the last bit for about 5 % of arguments), the largest
difference is printed.

Run: ``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 PYTHONPATH=src python
benchmarks/bench_particle_floor.py`` (or ``make bench`` / ``benchmarks/run.py floor``).
"""

from __future__ import annotations

import math
import os
import statistics
import time

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import numba  # noqa: E402
import numpy as np  # noqa: E402
from numba import types  # noqa: E402
from numba.extending import intrinsic  # noqa: E402

from fusioncenter import censoring as cs  # noqa: E402
from fusioncenter import particle  # noqa: E402
from fusioncenter._compiled import ziggurat  # noqa: E402
from fusioncenter.censoring.fusion import LinearFusionCentre  # noqa: E402
from fusioncenter.censoring.results import streams  # noqa: E402

SC = cs.LinearScenario()
L = 1.0
ETA = cs.threshold(L, SC.N)
TRIALS, PARTICLES = 32, 1000
CHECK_TRIALS = 256
ROUNDS = 15
SEED = 2014


# ----------------------------------------------------------------------------- the data
def data(n: int, seed: int):
    """Truth ``x (n, T+1, 2)``, measurements ``z (n, T, N)``, selection uniforms, and the seed of
    the filter's SFC64 stream (as ``censoring.run`` draws them for a block)."""
    rng_data, rng_pf = streams(np.random.default_rng(seed))
    x, z = SC.sample(rng_data, n)
    sel_u = rng_data.random(z.shape)
    return x, z, sel_u, rng_pf.bit_generator.state


def _generator(state) -> np.random.Generator:
    g = np.random.Generator(np.random.SFC64())
    g.bit_generator.state = state
    return g


# ----------------------------------------------------------------------------- ours
def ours(scheme: str, x, z, sel_u, state) -> np.ndarray:
    """Our filter's estimates ``(n, T, 2)``."""
    n = z.shape[0]
    fc = LinearFusionCentre(SC, scheme, "state", "corrected", ETA, L, z, sel_u)
    out = particle.run_filter(fc, _generator(state), n, PARTICLES, SC.T)
    return out.mean


# ----------------------------------------------------------------------------- the reference
@intrinsic
def _bits_to_float(typingctx, i):
    """The float64 whose bits are the int64 ``i``."""
    sig = types.float64(types.int64)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], context.get_value_type(types.float64))

    return sig, codegen


_LN2_HI, _LN2_LO = 6.93147180369123816490e-01, 1.90821492927058770002e-10


@numba.njit(cache=False, nogil=True, fastmath=True, inline="always")
def _exp_neg(x):
    """``exp(x)`` for ``x <= 0``, branch-free (vectorizable): ``2^k exp(r)``, ``|r| <= ln 2 / 2``,
    a degree-13 Taylor polynomial (relative error below 1e-13); 0 below ``-708``."""
    xc = max(x, -708.0)
    k = math.floor(xc * 1.4426950408889634 + 0.5)
    r = xc - k * _LN2_HI
    r = r - k * _LN2_LO
    p = 1.0 / 6227020800.0
    for q in (479001600.0, 39916800.0, 3628800.0, 362880.0, 40320.0, 5040.0, 720.0, 120.0,
              24.0, 6.0, 2.0, 1.0, 1.0):
        p = p * r + 1.0 / q
    scale = _bits_to_float((np.int64(k) + 1023) << 52)
    return p * scale if x >= -708.0 else 0.0


# --- an SFC64 stream and a 256-layer ziggurat, inlined (the in-kernel draws)
def _zig_tables():
    """Marsaglia and Tsang's 256-layer ziggurat for 52-bit mantissas (NumPy's layout: ``ki``
    acceptance bounds, ``wi`` widths per unit, ``fi`` densities), computed in double precision
    from ``r`` and the layers' common area ``v = r f(r) + P(Z > r) sqrt(2 pi)``. NumPy's tables
    (generated at higher precision) differ in the last bits: these draws are not NumPy's bit
    for bit (:func:`draws_agreement` counts them)."""
    from scipy.special import erfc
    r = 3.654152885361009
    v = r * math.exp(-0.5 * r * r) + math.sqrt(math.pi / 2) * erfc(r / math.sqrt(2))
    m1 = 2.0**52
    ki, wi, fi = np.zeros(256, np.uint64), np.zeros(256), np.zeros(256)
    dn = tn = r
    q = v / math.exp(-0.5 * dn * dn)
    ki[0] = np.uint64(dn / q * m1)
    wi[0], wi[255] = q / m1, dn / m1
    fi[0], fi[255] = 1.0, math.exp(-0.5 * dn * dn)
    for i in range(254, 0, -1):
        dn = math.sqrt(-2.0 * math.log(v / dn + math.exp(-0.5 * dn * dn)))
        ki[i + 1] = np.uint64(dn / tn * m1)
        tn = dn
        fi[i], wi[i] = math.exp(-0.5 * dn * dn), dn / m1
    return ki, wi, fi, r


#: NumPy's own tables when the library can read them (then the in-kernel normals are NumPy's
#: bit for bit), else the ones computed here
_NUMPY_TABLES = ziggurat.tables()
_KI, _WI, _FI, _ZR = _zig_tables() if _NUMPY_TABLES is None else _NUMPY_TABLES[:4]
_U11, _U24, _U40, _U3 = np.uint64(11), np.uint64(24), np.uint64(40), np.uint64(3)
_U1, _U8, _MASK52, _MASK8 = np.uint64(1), np.uint64(8), np.uint64(0xFFFFFFFFFFFFF), np.uint64(255)


@numba.njit(cache=False, nogil=True, inline="always")
def _next64(s):
    """SFC64's next output; state ``s (4,) uint64`` (NumPy's SFC64 state layout)."""
    tmp = s[0] + s[1] + s[3]
    s[3] = s[3] + _U1
    s[0] = s[1] ^ (s[1] >> _U11)
    s[1] = s[2] + (s[2] << _U3)
    s[2] = ((s[2] << _U24) | (s[2] >> _U40)) + tmp
    return tmp


@numba.njit(cache=False, nogil=True, inline="always")
def _next_double(s):
    return np.float64(_next64(s) >> _U11) * (1.0 / 9007199254740992.0)


@numba.njit(cache=False, nogil=True, inline="always")
def _normal(s):
    """A standard normal by the ziggurat from the SFC64 state ``s``."""
    while True:
        r = _next64(s)
        idx = np.intp(r & _MASK8)
        r = r >> _U8
        rabs = (r >> _U1) & _MASK52
        x = np.float64(rabs) * _WI[idx]
        if r & _U1:
            x = -x
        if rabs < _KI[idx]:
            return x
        if idx == 0:
            while True:
                xx = -(1.0 / _ZR) * math.log1p(-_next_double(s))
                yy = -math.log1p(-_next_double(s))
                if yy + yy > xx * xx:
                    return -(_ZR + xx) if (rabs >> _U8) & _U1 else _ZR + xx
        elif (_FI[idx - 1] - _FI[idx]) * _next_double(s) + _FI[idx] < math.exp(-0.5 * x * x):
            return x


@numba.njit(cache=False)
def _fill_normals(s, out):
    for i in range(out.size):
        out[i] = _normal(s)


def draws_agreement(n: int = 1_000_000, seed: int = SEED) -> float:
    """The fraction of ``n`` in-kernel normals equal, bit for bit, to NumPy's
    ``standard_normal`` from the same SFC64 state."""
    g = np.random.Generator(np.random.SFC64(seed))
    s = np.array(g.bit_generator.state["state"]["state"], dtype=np.uint64)
    ours_ = np.empty(n)
    _fill_normals(s, ours_)
    return float(np.mean(ours_ == g.standard_normal(n)))


@numba.njit(cache=False, nogil=True, fastmath=True)
def _ref_block(pos, vel, pos2, vel2, lw, anc, g, u, zbar, c, dt, L0, L1, mean, ess, draw, st):
    """One step of the all-send filter for every trial ``b``, fused: particles ``pos, vel (n,
    P)`` (resampled into ``pos2, vel2``), normals ``g (n, P)`` and uniforms ``u (n,)`` (drawn
    here from the SFC64 state ``st`` if ``draw``), log weights ``c (y - zbar[b])^2`` with
    ``y`` the position."""
    n, P = pos.shape
    for b in range(n):
        zb = zbar[b]
        mx = -np.inf
        if draw:
            for i in range(P):
                g[b, i] = _normal(st)
        for i in range(P):
            gi = g[b, i]
            p = pos[b, i] + vel[b, i] * dt
            p = p + gi * L0
            v = vel[b, i] + gi * L1
            pos[b, i] = p
            vel[b, i] = v
            e = p - zb
            li = e * e * c
            lw[i] = li
            mx = max(mx, li)
        s = 0.0
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        for i in range(P):
            wi = _exp_neg(lw[i] - mx)
            lw[i] = wi
            s += wi
            s0 += wi * pos[b, i]
            s1 += wi * vel[b, i]
            s2 += wi * wi
        mean[b, 0] = s0 / s
        mean[b, 1] = s1 / s
        ess[b] = s * s / s2
        # systematic resampling fused with the gather (branch-light: particle i marks the
        # first slot it owns, a running maximum gives every slot its ancestor)
        ub = _next_double(st) if draw else u[b]
        for k in range(P):
            anc[k] = 0
        acc = 0.0
        lo = 0
        for i in range(P - 1):
            acc += lw[i]
            if lo < P:
                anc[lo] = i
            lo = int(math.ceil(acc / s * P - ub))
        if lo < P:
            anc[lo] = P - 1
        a = 0
        for k in range(P):
            a = max(a, anc[k])
            pos2[b, k] = pos[b, a]
            vel2[b, k] = vel[b, a]


def reference(x, z, sel_u, state, *, draw: bool = False) -> np.ndarray:
    """The hand-fused all-send filter's estimates ``(n, T, 2)``; ``draw``: the normals and
    uniforms from Numba's generator inside the kernel (else NumPy's, in our order)."""
    n, T, N = z.shape
    P = PARTICLES
    x0 = SC.dynamics.m0
    LQ = particle.psd_factor(SC.Q)
    assert LQ.shape[1] == 1 and np.all(SC.H == SC.H[0]) and np.all(SC.rvec == SC.rvec[0])
    dt, L0, L1 = float(SC.F[0, 1]), float(LQ[0, 0]), float(LQ[1, 0])
    c = -0.5 / float(SC.rvec[0]) * N
    zbar = z.sum(axis=2) / N  # all sensors received: sum of the squares = N (y - zbar)^2 + const
    pos, vel = np.full((n, P), x0[0]), np.full((n, P), x0[1])
    pos2, vel2 = np.empty_like(pos), np.empty_like(vel)
    lw = np.empty(P)
    anc = np.empty(P, dtype=np.intp)
    g = np.empty((n, P))
    u = np.empty(n)
    out = np.empty((n, T, 2))
    ess = np.empty(n)
    rng = _generator(state)
    st = np.array(state["state"]["state"], dtype=np.uint64)  # the same SFC64 stream
    for t in range(T):
        if not draw:
            rng.standard_normal(out=g)
            u = rng.random(n)
        _ref_block(pos, vel, pos2, vel2, lw, anc, g, u, np.ascontiguousarray(zbar[:, t]), c, dt,
                   L0, L1, out[:, t], ess, draw, st)
        pos, pos2, vel, vel2 = pos2, pos, vel2, vel
    return out


# ----------------------------------------------------------------------------- checks
def kalman_means(z) -> np.ndarray:
    """The exact filter's means ``(n, T, 2)`` of the all-send data (every sensor received)."""
    F, Q, H, R = SC.F, SC.Q, SC.H, np.diag(SC.rvec)
    n, T, _ = z.shape
    m = np.broadcast_to(SC.dynamics.m0, (n, 2)).copy()
    Pc = SC.dynamics.P0.copy()
    out = np.empty((n, T, 2))
    for t in range(T):
        m = m @ F.T
        Pc = F @ Pc @ F.T + Q
        S = H @ Pc @ H.T + R
        K = Pc @ H.T @ np.linalg.inv(S)
        m = m + (z[:, t] - m @ H.T) @ K.T
        Pc = (np.eye(2) - K @ H) @ Pc
        out[:, t] = m
    return out


def check(seed: int = SEED) -> None:
    """Print the RMSEs, the distance to the KF and the paired differences (see the module)."""
    x, z, sel_u, state = data(CHECK_TRIALS, seed)
    kf = kalman_means(z)
    truth = x[:, 1:]
    est = {"ours all-send": ours("all-send", x, z, sel_u, state),
           "reference, NumPy draws": reference(x, z, sel_u, state),
           "reference, in-kernel draws": reference(x, z, sel_u, state, draw=True)}
    print(f"  checks on {CHECK_TRIALS} trials x {PARTICLES} particles x {SC.T} steps:")
    print(f"  {'variant':<28} {'RMSE pos':>9} {'RMSE vel':>9} {'RMS to KF':>10}")
    print(f"  {'exact Kalman filter':<28} "
          + " ".join(f"{v:9.4f}" for v in np.sqrt(((kf - truth) ** 2).mean(axis=(0, 1)))))
    for name, m in est.items():
        rm = np.sqrt(((m - truth) ** 2).mean(axis=(0, 1)))
        to_kf = math.sqrt(((m - kf) ** 2).mean())
        print(f"  {name:<28} {rm[0]:9.4f} {rm[1]:9.4f} {to_kf:10.5f}")
    base = ((est["ours all-send"] - truth) ** 2).mean(axis=1)  # (n, 2) per-trial MSE
    for name in ("reference, NumPy draws", "reference, in-kernel draws"):
        d = ((est[name] - truth) ** 2).mean(axis=1) - base
        se = d.std(axis=0, ddof=1) / math.sqrt(d.shape[0])
        dm = d.mean(axis=0)
        ok = bool(np.all(np.abs(dm) <= 4 * se + 1e-12))
        print(f"  {name} - ours: per-trial MSE difference pos {dm[0]:+.2e} (SE {se[0]:.1e}), "
              f"vel {dm[1]:+.2e} (SE {se[1]:.1e}): "
              f"{'agree (within 4 SE)' if ok else 'DISAGREE'}")
        assert ok, name
    same = np.array_equal(est["reference, NumPy draws"], est["ours all-send"])
    diff = np.abs(est["reference, NumPy draws"] - est["ours all-send"]).max()
    print(f"  reference (NumPy draws) vs ours: bitwise {'identical' if same else 'different'}, "
          f"largest difference {diff:.1e} (random numbers: NumPy's SFC64 stream, same order); "
          f"in-kernel draws: SFC64 + ziggurat, {100 * draws_agreement():.2f} % of its normals "
          f"equal NumPy's bit for bit from the same state")


# ----------------------------------------------------------------------------- timing
VARIANTS = {
    "ours all-send": lambda d: ours("all-send", *d),
    "ours CFwMD": lambda d: ours("cfwmd", *d),
    "reference, NumPy draws": lambda d: reference(*d),
    "reference, in-kernel draws": lambda d: reference(*d, draw=True),
}


def timing(rounds: int = ROUNDS, n: int = TRIALS) -> dict[str, float]:
    """Interleaved CPU times; returns the median ns per particle-step of each variant."""
    d = data(n, SEED)
    for fn in VARIANTS.values():
        fn(d)  # warm-up (compilation)
    times: dict[str, list[float]] = {k: [] for k in VARIANTS}
    for _ in range(rounds):
        for name, fn in VARIANTS.items():
            t0 = time.process_time()
            fn(d)
            times[name].append(time.process_time() - t0)
    ps = n * PARTICLES * SC.T
    med = {k: statistics.median(v) / ps * 1e9 for k, v in times.items()}
    ref = med["reference, NumPy draws"]
    print(f"  timing: {rounds} interleaved rounds of {n} trials x {PARTICLES} particles x "
          f"{SC.T} steps, CPU time, medians (load average {os.getloadavg()[0]:.2f})")
    for k, v in med.items():
        lo, hi = (min(times[k]) / ps * 1e9, max(times[k]) / ps * 1e9)
        print(f"  {k:<28} {v:6.1f} ns per particle-step (min {lo:5.1f}, max {hi:5.1f}); "
              f"x{v / ref:.2f} the NumPy-draws reference, "
              f"x{v / med['reference, in-kernel draws']:.2f} the in-kernel one")
    print(f"  CFwMD / all-send (ours): x{med['ours CFwMD'] / med['ours all-send']:.2f}; "
          f"ours all-send / in-kernel reference: "
          f"x{med['ours all-send'] / med['reference, in-kernel draws']:.2f}; our normals "
          f"{'inline' if _NUMPY_TABLES is not None else 'through NumPy'}")
    return med


def main() -> None:
    check()
    timing()


REPEATS = 1
CASES = [("particle floor (zheng2014 VII.A.1, 32 x 1000 x 20)", "ours vs fused reference",
          lambda: main)]

if __name__ == "__main__":
    main()
