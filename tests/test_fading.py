"""fusioncenter.fading (dey2009): special functions, channel laws, Monte Carlo and bounds."""

from __future__ import annotations

import math
import warnings
from concurrent.futures import ThreadPoolExecutor

import mpmath
import numpy as np
import pytest
import scipy.integrate
import scipy.special
import scipy.stats
from hypothesis import given, settings
from hypothesis import strategies as st

from fusioncenter import fading, riccati
from fusioncenter.fading import Nakagami, Rayleigh

# Fig. 1's system: a = 1.25, sigma_w = 1, sigma_n = 2, lambda = 100
A, SW2, SN2, LAM = 1.25, 1.0, 4.0, 100.0


# ------------------------------------------------------------------------------- exp_e1
def test_exp_e1_against_mpmath_on_a_log_grid():
    xs = np.geomspace(1e-8, 1e8, 321)
    mpmath.mp.dps = 40
    ref = np.array([float(mpmath.exp(mpmath.mpf(x)) * mpmath.e1(mpmath.mpf(x))) for x in xs])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow/underflow warnings either
        got = fading.exp_e1(xs)
    assert np.all(np.isfinite(got))
    rel = np.abs(got / ref - 1)
    assert rel.max() <= 1e-12, (xs[rel.argmax()], rel.max())
    # both branches are exercised: scipy below the switch, the continued fraction above
    assert xs.min() < fading.channels._E1_SWITCH < xs.max()


def test_exp_e1_edges_and_scalars():
    assert fading.exp_e1(0.0) == np.inf
    assert fading.exp_e1(np.inf) == 0.0
    assert isinstance(fading.exp_e1(3.0), float)
    x = 1e300  # far beyond where exp(x) overflows: e^x E1(x) ~ 1/x
    assert fading.exp_e1(x) == pytest.approx(1 / x, rel=1e-12)
    assert fading.exp_e1(np.array([[1.0, 2.0]])).shape == (1, 2)
    with pytest.raises(ValueError, match="x must be non-negative"):
        fading.exp_e1(-1.0)


def test_scipy_alone_overflows_where_exp_e1_does_not():
    with np.errstate(all="ignore"):
        naive = np.exp(800.0) * scipy.special.exp1(800.0)
    assert not np.isfinite(naive) or naive == 0.0
    assert fading.exp_e1(800.0) == pytest.approx(1 / 801, rel=2e-6)


def test_exponential_integral_inequalities_on_a_wide_grid():
    """0.5 ln(1 + 2/x) < e^x E1(x) < ln(1 + 1/x) < 1/x (Abramowitz & Stegun 5.1.20)."""
    x = np.geomspace(1e-6, 1e6, 2001)
    f = fading.exp_e1(x)
    assert np.all(0.5 * np.log1p(2 / x) < f)
    assert np.all(f < np.log1p(1 / x))
    assert np.all(np.log1p(1 / x) < 1 / x)


def test_abramowitz_stegun_erfc_bounds_on_a_wide_grid():
    """1/(u + sqrt(u^2 + 2)) < (sqrt(pi)/2) exp(u^2) erfc(u) <= 1/(u + sqrt(u^2 + 4/pi))."""
    u = np.concatenate([[0.0], np.geomspace(1e-6, 1e6, 2001)])
    f = np.sqrt(np.pi) / 2 * scipy.special.erfcx(u)
    assert np.all(f <= 1 / (u + np.sqrt(u * u + 4 / np.pi)) * (1 + 1e-15))
    assert np.all(1 / (u + np.sqrt(u * u + 2)) <= f * (1 + 1e-13))  # equal to rounding for u >> 1
    assert np.all((1 / (u + np.sqrt(u * u + 2)) < f)[u < 1e3])
    assert f[0] == pytest.approx(0.5 * np.sqrt(np.pi))  # equality of the upper bound at u = 0
    assert 1 / np.sqrt(4 / np.pi) == pytest.approx(f[0])


def test_integral_representations_used_by_the_paper():
    """e^x E1(x) = int_0^inf e^-u / (u + x) du and
    (pi / 2u) e^{u^2} erfc(u) = int_0^inf e^{-t^2} / (t^2 + u^2) dt (Section 3.1)."""
    for x in (1e-3, 0.4, 7.0, 300.0):
        val = scipy.integrate.quad(lambda u, x=x: np.exp(-u) / (u + x), 0, np.inf,
                                   epsabs=0, epsrel=1e-12, limit=200)[0]
        assert fading.exp_e1(x) == pytest.approx(val, rel=1e-9)
    for u in (1e-3, 0.4, 7.0, 300.0):
        val = scipy.integrate.quad(lambda t, u=u: np.exp(-t * t) / (t * t + u * u), 0, np.inf,
                                   epsabs=0, epsrel=1e-12, limit=200)[0]
        assert np.pi / (2 * u) * scipy.special.erfcx(u) == pytest.approx(val, rel=1e-9)


# ------------------------------------------------------------------------ channel laws
CHANNELS = [Rayleigh(2.0), Nakagami(0.5, 2.0), Nakagami(1.0, 2.0), Nakagami(0.75, 0.5),
            Nakagami(1.5, 3.0), Nakagami(3.7, 1.0), Nakagami(10.0, 0.1)]


def _quad_expect(ch, fn):
    """E[fn(r)] by quadrature, r = t^2 to tame the r^(m - 1) singularity of m < 1."""
    def integrand(t):
        return fn(t * t) * ch.pdf(t * t) * 2 * t
    scale = 1 / np.sqrt(ch.lam)
    a = scipy.integrate.quad(integrand, 0, scale, epsabs=0, epsrel=1e-12, limit=400)[0]
    b = scipy.integrate.quad(integrand, scale, np.inf, epsabs=0, epsrel=1e-12, limit=400)[0]
    return a + b


@pytest.mark.parametrize("ch", CHANNELS, ids=lambda c: c.name)
def test_pdf_is_a_density_with_mean_one_over_lambda(ch):
    assert _quad_expect(ch, lambda r: 1.0) == pytest.approx(1.0, rel=1e-9)
    assert _quad_expect(ch, lambda r: r) == pytest.approx(ch.mean_gain, rel=1e-9)


@pytest.mark.parametrize("ch", CHANNELS, ids=lambda c: c.name)
def test_closed_form_expectations_against_quadrature(ch):
    for b in [1e-4, 0.03, 0.7, 5.0, 80.0, 3e3]:
        g = _quad_expect(ch, lambda r, b=b: b / (r + b))
        assert ch.ratio_mean(b) == pytest.approx(g, rel=1e-8), b
        assert ch.inverse_mean(b) == pytest.approx(g / b, rel=1e-8)
    assert ch.ratio_mean(0.0) == 0.0
    assert float(ch.ratio_mean(np.inf)) == 1.0


def test_nakagami_one_is_rayleigh_and_general_m_matches_mpmath():
    b = np.geomspace(1e-6, 1e6, 41)
    np.testing.assert_allclose(Nakagami(1.0, 3.0).ratio_mean(b), Rayleigh(3.0).ratio_mean(b),
                               rtol=1e-14)
    mpmath.mp.dps = 30
    for m in (0.5, 0.6, 1.5, 2.0, 2.5, 3.7, 5.5, 12.0, 60.0):
        ch = Nakagami(m, 0.7)
        z = 0.7 * m * b
        ref = [float(mpmath.mpf(x) ** m * mpmath.hyperu(m, m, x)) for x in z]
        np.testing.assert_allclose(ch.ratio_mean(b), ref, rtol=1e-9, err_msg=str(m))


@pytest.mark.parametrize("ch", CHANNELS[:5], ids=lambda c: c.name)
def test_expectations_against_monte_carlo(ch):
    rng = np.random.default_rng(1)
    r = ch.sample(rng, 200_000)
    assert r.min() >= 0
    assert abs(r.mean() - ch.mean_gain) < 5 * r.std() / np.sqrt(r.size)
    for b in [0.05, 0.5, 5.0]:
        x = b / (r + b)
        assert abs(x.mean() - ch.ratio_mean(b)) < 5 * x.std() / np.sqrt(x.size)


def test_nakagami_half_samples_follow_its_gamma_law():
    ch = Nakagami(0.5, 4.0)
    r = ch.sample(np.random.default_rng(2), 20_000)
    p = scipy.stats.kstest(r, scipy.stats.gamma(a=0.5, scale=1 / (4.0 * 0.5)).cdf).pvalue
    assert p > 1e-3


def test_loose_inequalities_of_the_channels():
    b = np.geomspace(1e-6, 1e6, 500)
    ray, nak = Rayleigh(3.0), Nakagami(0.5, 3.0)
    assert np.all(ray.ratio_mean(b) < ray.ratio_mean_bound(b))
    assert np.all(nak.ratio_mean(b) <= nak.ratio_mean_bound(b) * (1 + 1e-14))
    with pytest.raises(ValueError, match="m = 1/2"):
        Nakagami(2.0, 1.0).ratio_mean_bound(1.0)


def test_expected_posterior_is_the_bracket_of_16():
    ch = Rayleigh(LAM)
    for p, sv2 in [(0.5, 1.0), (30.0, 25.0), (400.0, 0.01)]:
        direct = _quad_expect(ch, lambda r, p=p, sv2=sv2:
                              p * (r * sv2 + SN2) / (r * (p + sv2) + SN2))
        assert fading.expected_posterior(p, sv2, SN2, ch) == pytest.approx(direct, rel=1e-9)


# ------------------------------------------------------------------- the paper's formulas
def _eq17(s, sv2, lam=LAM):
    m = lam * SN2 / (s + sv2)
    return SW2 + A**2 * s / (s + sv2) * (sv2 + lam * SN2 * s / (s + sv2)
                                         * np.exp(m) * scipy.special.exp1(m))


def _eq18(q, sv2, lam=LAM):
    return SW2 + A**2 * (sv2 + lam * SN2 * np.log(1 + (q + sv2) / (lam * SN2)))


def _eq19(s, sv2, lam=LAM):
    u = np.sqrt(SN2 * lam / (2 * (sv2 + s)))
    return SW2 + A**2 * s / (s + sv2) * (sv2 + SN2 * s / (s + sv2)
                                         * np.sqrt(lam * np.pi * (sv2 + s) / (2 * SN2))
                                         * np.exp(u**2) * scipy.special.erfc(u))


def _nakagami_intermediate(g, sv2, lam=LAM, drop_factor=False):
    """The bound before (19)-(20): A-S substituted into the Nakagami(1/2) expectation."""
    u = np.sqrt(SN2 * lam / (2 * (sv2 + g)))
    outer = 1.0 if drop_factor else g / (g + sv2)
    return SW2 + A**2 * outer * (sv2 + np.sqrt(SN2) * np.sqrt(2 * lam) * g / np.sqrt(g + sv2)
                                 / (u + np.sqrt(u**2 + 4 / np.pi)))


def _iterate(fn, x0, steps):
    out = [x0]
    for _ in range(steps):
        out.append(fn(out[-1]))
    return np.array(out)


@pytest.mark.parametrize("sv2", [0.01, 1.0, 25.0, 400.0])
def test_bound_sequences_are_the_printed_17_18_19(sv2):
    ray = fading.scalar_bounds(A, SW2, sv2, SN2, Rayleigh(LAM), 1.0, 60)
    nak = fading.scalar_bounds(A, SW2, sv2, SN2, Nakagami(0.5, LAM), 1.0, 60)
    np.testing.assert_allclose(ray["s"], _iterate(lambda s: _eq17(s, sv2), 1.0, 60), rtol=1e-12)
    np.testing.assert_allclose(ray["q"], _iterate(lambda q: _eq18(q, sv2), 1.0, 60), rtol=1e-12)
    np.testing.assert_allclose(nak["s"], _iterate(lambda s: _eq19(s, sv2), 1.0, 60), rtol=1e-11)


@pytest.mark.parametrize("sv2", [0.01, 1.0, 25.0, 400.0])
def test_eq20_as_derived_and_as_printed(sv2):
    """(20) is the intermediate Nakagami bound with g/(g + sigma_v^2) dropped; the printed nested
    square root is something else (and looser). See the errata page, book/errata.md."""
    ours = fading.scalar_bounds(A, SW2, sv2, SN2, Nakagami(0.5, LAM), 1.0, 60)["q"]
    derived = _iterate(lambda q: _nakagami_intermediate(q, sv2, drop_factor=True), 1.0, 60)
    np.testing.assert_allclose(ours, derived, rtol=1e-12)
    printed = fading.nakagami_q_as_printed(A, SW2, sv2, SN2, LAM, 1.0, 60)
    assert printed[-1] > 1.5 * ours[-1]  # the printed recursion settles far higher
    # the corrected (20) still lies above the tighter intermediate bound and (19)
    g = np.geomspace(1.0, 1e4, 50)  # (19) as printed overflows (exp(u^2)) for small g + sv2
    assert np.all(_nakagami_intermediate(g, sv2)
                  <= _nakagami_intermediate(g, sv2, drop_factor=True))
    assert np.all(_eq19(g, sv2) <= _nakagami_intermediate(g, sv2) * (1 + 1e-13))


def test_first_step_of_the_tight_bound_is_exact():
    """With p_0 deterministic, Jensen's step is an equality: s_1 = E[p_1] (quadrature)."""
    p0, sv2 = 50.0, 4.0

    def post(r):
        return p0 * (r * sv2 + SN2) / (r * (p0 + sv2) + SN2)

    for ch in (Rayleigh(LAM), Nakagami(0.5, LAM), Nakagami(2.0, 1.0)):
        e1 = SW2 + A**2 * _quad_expect(ch, post)
        assert fading.scalar_bounds(A, SW2, sv2, SN2, ch, p0, 1)["s"][1] == pytest.approx(
            e1, rel=1e-9)


@pytest.mark.parametrize("ch", [Rayleigh(LAM), Nakagami(0.5, LAM), Nakagami(3.0, LAM)],
                         ids=lambda c: c.name)
def test_bounds_dominate_the_monte_carlo_mean(ch):
    mean, se = fading.scalar_mc(A, SW2, 1.0, SN2, ch, 1.0, 40, 3000, 5)
    b = fading.scalar_bounds(A, SW2, 1.0, SN2, ch, 1.0, 40)
    assert mean.shape == se.shape == b["s"].shape == b["q"].shape == (41,)
    assert mean[0] == 1.0 and se[0] == 0.0
    assert np.all(mean[1:] - 4 * se[1:] <= b["s"][1:])
    assert np.all(b["s"] <= b["q"])
    assert abs(mean[1] - b["s"][1]) < 4 * se[1]  # exact first step


def test_bound_limits_are_fixed_points_and_the_limits_of_the_sequences():
    for ch in (Rayleigh(LAM), Nakagami(0.5, LAM)):
        lim = fading.scalar_bound_limits(A, SW2, 1.0, SN2, ch)
        seq = fading.scalar_bounds(A, SW2, 1.0, SN2, ch, 1e4, 200)  # from above this time
        assert seq["s"][-1] == pytest.approx(lim["s"], rel=1e-10)
        assert seq["q"][-1] == pytest.approx(lim["q"], rel=1e-10)
        assert np.all(np.diff(seq["s"]) <= 1e-12 * lim["s"])  # monotone (Appendix C)
        assert lim["s"] <= lim["q"]


def test_general_nakagami_bounds_are_ordered_by_severity():
    """Less severe fading (larger m) gives a smaller tight bound; the loose bound of the more
    severe paper case used for general m stays above."""
    s = {m: fading.scalar_bounds(A, SW2, 1.0, SN2, Nakagami(m, LAM), 1.0, 80)
         for m in (0.5, 0.7, 1.0, 2.0, 5.0)}
    for lo, hi in [(0.5, 0.7), (0.7, 1.0), (1.0, 2.0), (2.0, 5.0)]:
        assert np.all(s[hi]["s"][1:] <= s[lo]["s"][1:])
    for m, b in s.items():
        assert np.all(b["s"] <= b["q"]), m


@settings(max_examples=20, deadline=None, derandomize=True)
@given(a=st.floats(0.3, 2.0), sw2=st.floats(0.01, 10.0), sv2=st.floats(0.01, 100.0),
       sn2=st.floats(0.01, 100.0), lam=st.floats(0.01, 1000.0), p0=st.floats(0.0, 1e3),
       nakagami=st.booleans())
def test_property_tight_below_loose_and_monotone(a, sw2, sv2, sn2, lam, p0, nakagami):
    ch = Nakagami(0.5, lam) if nakagami else Rayleigh(lam)
    b = fading.scalar_bounds(a, sw2, sv2, sn2, ch, p0, 30)
    assert np.all(np.isfinite(b["s"])) and np.all(np.isfinite(b["q"]))
    assert np.all(b["s"] <= b["q"] * (1 + 1e-12))
    higher = fading.scalar_bounds(a, sw2, sv2, sn2, ch, p0 + 1.0, 30)
    assert np.all(higher["s"] >= b["s"] * (1 - 1e-12))


@settings(max_examples=8, deadline=None, derandomize=True)
@given(a=st.floats(0.5, 1.6), sv2=st.floats(0.1, 20.0), lam=st.floats(0.05, 200.0),
       nakagami=st.booleans())
def test_property_bounds_dominate_monte_carlo(a, sv2, lam, nakagami):
    ch = Nakagami(0.5, lam) if nakagami else Rayleigh(lam)
    mean, se = fading.scalar_mc(a, 1.0, sv2, 4.0, ch, 1.0, 25, 800, 11)
    s = fading.scalar_bounds(a, 1.0, sv2, 4.0, ch, 1.0, 25)["s"]
    assert np.all(mean[1:] - 5 * se[1:] <= s[1:])


def test_recursions_are_kalman_riccati_steps():
    """(15), the multi-access and orthogonal recursions and (21) are one Kalman (Riccati) step
    with the faded measurement (checked against fusioncenter.riccati)."""
    rng = np.random.default_rng(4)
    for _ in range(5):
        p, r = rng.uniform(0.1, 50), rng.exponential(1.0)
        sv2, h = rng.uniform(0.1, 5), np.sqrt(r)
        step15 = SW2 + A**2 * p * (r * sv2 + SN2) / (r * (p + sv2) + SN2)
        ref = riccati.riccati_step([[p]], [[A]], [[SW2]], [[h]], [[h * h * sv2 + SN2]])[0, 0]
        assert step15 == pytest.approx(ref, rel=1e-12)
        # two sensors
        rr = rng.exponential(1.0, 2)
        hh, c, s2 = np.sqrt(rr), np.array([1.0, 0.7]), np.array([1.0, 4.0])
        ma = SW2 + A**2 * p * (rr @ s2 + SN2) / ((hh @ c) ** 2 * p + rr @ s2 + SN2)
        ref = riccati.riccati_step([[p]], [[A]], [[SW2]], [[hh @ c]], [[rr @ s2 + SN2]])[0, 0]
        assert ma == pytest.approx(ref, rel=1e-12)
        orth = SW2 + A**2 * p / (1 + p * np.sum(rr * c**2 / (rr * s2 + SN2)))
        ref = riccati.riccati_step([[p]], [[A]], [[SW2]], (hh * c)[:, None],
                                   np.diag(rr * s2 + SN2))[0, 0]
        assert orth == pytest.approx(ref, rel=1e-12)
    # (21), vector state: the weight r / (r + beta) form
    P, Am, cb = np.array([[3.0, 0.5], [0.5, 1.0]]), np.array([[1.25, 1.0], [0, 0.9]]), [1.0, 0.3]
    r = 0.37
    S = np.array(cb) @ P @ np.array(cb) + 2.0
    got = fading.vector._vector_step(P, Am, np.array(cb), np.eye(2), 2.0, r / (r + SN2 / S))
    ref = riccati.riccati_step(P, Am, np.eye(2), np.sqrt(r) * np.array([cb]),
                               [[r * 2.0 + SN2]])
    np.testing.assert_allclose(got, ref, rtol=1e-12)


def test_ordering_22_is_what_makes_a1_minus_b1_nonnegative():
    """Multi-access: A_1 - B_1 >= 0 for every r_2 when sensor 1 is the better one ((22)), and
    negative for large r_2 when the order is reversed."""
    c, s2, lam1, g = np.array([1.0, 1.0]), np.array([1.0, 4.0]), 0.5, 3.0
    r2 = np.geomspace(1e-4, 1e4, 200)

    def a_minus_b(first, second):
        a1 = lam1 / s2[first] * (r2 * s2[second] + SN2)
        b1 = lam1 / (c[first] ** 2 * g + s2[first]) * (r2 * (c[second] ** 2 * g + s2[second])
                                                       + SN2)
        return a1 - b1
    assert np.all(a_minus_b(0, 1) >= 0)
    assert np.any(a_minus_b(1, 0) < 0)


# ------------------------------------------------------------------------------ multisensor
MS = {"a": A, "c": [1.0, 1.0], "sigma_v2": [1.0, 4.0], "sigma_n2": 4.0, "sigma_w2": SW2}


def _ms(access, lams, **kw):
    return (access, MS["a"], kw.get("c", MS["c"]), kw.get("sigma_v2", MS["sigma_v2"]),
            kw.get("sigma_n2", MS["sigma_n2"]), lams, MS["sigma_w2"])


@pytest.mark.parametrize("access", fading.ACCESS_SCHEMES)
def test_one_sensor_reduces_to_the_scalar_bound(access):
    for c in (1.0, 0.5):
        b = fading.multisensor_bounds(access, A, [c], [2.0], SN2, [3.0], SW2, 1.0, 30)
        # c x + v observed: the scalar model (5) with x scaled by c
        ref = fading.scalar_bounds(A, SW2 * c**2, 2.0, SN2, Rayleigh(3.0), c**2, 30)["s"] / c**2
        np.testing.assert_allclose(b["s"], ref, rtol=1e-12)
        np.testing.assert_allclose(b["t"], ref, rtol=1e-12)


def _exact_first_step(access, lams, p0):
    """E[p_1] for two sensors by a 2-D quadrature over the channel gains."""
    c, sv2, sn2 = np.array(MS["c"]), np.array(MS["sigma_v2"]), MS["sigma_n2"]

    def info(r1, r2):
        r = np.array([r1, r2])
        if access == "multi-access":
            return (np.sqrt(r) @ c) ** 2 / (r @ sv2 + sn2)
        return float(np.sum(r * c**2 / (r * sv2 + sn2)))

    def f(r2, r1):
        dens = lams[0] * lams[1] * math.exp(-lams[0] * r1 - lams[1] * r2)
        return p0 / (1 + p0 * info(r1, r2)) * dens
    val = scipy.integrate.dblquad(f, 0, np.inf, 0, np.inf, epsabs=1e-11, epsrel=1e-9)[0]
    return SW2 + A**2 * val


@pytest.mark.parametrize("access", fading.ACCESS_SCHEMES)
def test_multisensor_monte_carlo_first_step_is_exact_and_bounds_dominate(access):
    lams = (1.0, 10.0)
    mean, se = fading.multisensor_mc(*_ms(access, lams), 3.0, 30, 4000, 3)
    assert abs(mean[1] - _exact_first_step(access, lams, 3.0)) < 4 * se[1]
    b = fading.multisensor_bounds(*_ms(access, lams), 3.0, 30)
    for key in ("s", "t"):
        assert np.all(mean[1:] - 4 * se[1:] <= b[key][1:]), key


def test_multisensor_terms_against_quadrature():
    """The per-sensor expectations of (24) and (25) against quadrature over r_i."""
    lams, g, m = np.array([0.5, 3.0]), 2.5, 2
    c, sv2, sn2 = np.array(MS["c"]), np.array(MS["sigma_v2"]), MS["sigma_n2"]
    for i in range(m):
        w = (sv2 / lams).sum() - sv2[i] / lams[i] + sn2

        def ma_term(r, i=i, w=w):
            dens = lams[i] * np.exp(-lams[i] * r)
            return (r * sv2[i] + w) / (r * (c[i] ** 2 * g + sv2[i]) + sn2 / m) * dens

        def orth_term(r, i=i):
            dens = lams[i] * np.exp(-lams[i] * r)
            return 1 / (1 / m + g * r * c[i] ** 2 / (r * sv2[i] + sn2)) * dens

        ma = scipy.integrate.quad(ma_term, 0, np.inf, epsrel=1e-12)[0]
        assert fading.multisensor._ratio_expect(sv2[i], c[i] ** 2 * g + sv2[i], w, sn2 / m,
                                                lams[i]) == pytest.approx(ma, rel=1e-9)
        orth = scipy.integrate.quad(orth_term, 0, np.inf, epsrel=1e-12)[0]
        assert fading.multisensor._ratio_expect(m * sv2[i], m * c[i] ** 2 * g + sv2[i], m * sn2,
                                                sn2, lams[i]) == pytest.approx(orth, rel=1e-9)


def test_ordering_22_worst_sensor_is_chosen_and_violation_is_smaller():
    lams = (0.1, 0.01)
    valid = fading.multisensor_bounds(*_ms("multi-access", lams), 1.0, 50)["s"]
    explicit = fading.multisensor_bounds(*_ms("multi-access", lams), 1.0, 50, last_sensor=1)
    np.testing.assert_array_equal(valid, explicit["s"])
    swapped = fading.multisensor_bounds("multi-access", A, [1.0, 1.0], [4.0, 1.0], SN2,
                                        lams[::-1], SW2, 1.0, 50)["s"]
    np.testing.assert_array_equal(valid, swapped)  # the order of the arguments does not matter
    violated = fading.multisensor_bounds(*_ms("multi-access", lams), 1.0, 50, last_sensor=0)
    assert violated["s"][-1] < valid[-1]
    mean, se = fading.multisensor_mc(*_ms("multi-access", lams), 1.0, 50, 3000, 4)
    assert np.any(mean - 4 * se > violated["s"])  # ... and it is not a bound


def test_orthogonal_accepts_per_sensor_channel_noise():
    b1 = fading.multisensor_bounds("orthogonal", A, [1, 1], [1, 4], [4.0, 4.0], [1, 2], SW2,
                                   1.0, 20)
    b2 = fading.multisensor_bounds("orthogonal", A, [1, 1], [1, 4], 4.0, [1, 2], SW2, 1.0, 20)
    np.testing.assert_allclose(b1["s"], b2["s"])
    mean, se = fading.multisensor_mc("orthogonal", A, [1, -1], [1, 4], [0.5, 8.0], [1, 2], SW2,
                                     1.0, 20, 2000, 1)
    b = fading.multisensor_bounds("orthogonal", A, [1, -1], [1, 4], [0.5, 8.0], [1, 2], SW2,
                                  1.0, 20)
    assert np.all(mean[1:] - 4 * se[1:] <= np.minimum(b["s"], b["t"])[1:])


# --------------------------------------------------------------------------------- vector
def test_vector_bound_with_one_state_is_the_scalar_bound():
    Z = fading.vector_bound([[A]], [1.0], [[SW2]], 2.0, SN2, Rayleigh(LAM), [[3.0]], 40)
    s = fading.scalar_bounds(A, SW2, 2.0, SN2, Rayleigh(LAM), 3.0, 40)["s"]
    np.testing.assert_allclose(Z[:, 0, 0], s, rtol=1e-12)


def test_vector_monte_carlo_against_zbar():
    Am = np.array([[1.25, 1.0], [0.0, 0.9]])
    args = (Am, [1.0, 0.0], np.eye(2), 1.0, SN2, Rayleigh(10.0), np.eye(2))
    mean, se = fading.vector_mc(*args, 30, 3000, 2)
    Z = fading.vector_bound(*args, 30)
    assert mean.shape == Z.shape == (31, 2, 2)
    np.testing.assert_allclose(mean, np.swapaxes(mean, 1, 2))
    ok = (np.abs(mean[1] - Z[1]) <= 4 * se[1] + 1e-9 * np.abs(Z[1]))
    assert ok.all()  # exact first step
    res = fading.vector_paths(*args, 30, 3000, 2)
    for th in np.linspace(0, np.pi, 12, endpoint=False):
        v = np.array([np.cos(th), np.sin(th)])
        vpv = res.samples @ np.array([v[0] ** 2, 2 * v[0] * v[1], v[1] ** 2])
        m, e = vpv.mean(0), vpv.std(0, ddof=1) / np.sqrt(vpv.shape[0])
        bound = np.einsum("kij,i,j->k", Z, v, v)
        assert np.all(m[1:] - 4 * e[1:] <= bound[1:] * (1 + 1e-9))  # rounding: some are exact


# -------------------------------------------------------------------------------- runner
def _all_paths():
    return [
        lambda **kw: fading.scalar_paths(A, SW2, 1.0, SN2, Nakagami(0.5, LAM), 1.0, 12, 700, 9,
                                         block_size=128, **kw),
        lambda **kw: fading.multisensor_paths("multi-access", A, [1, 1], [1, 4], SN2, [1, 10],
                                              SW2, 1.0, 12, 700, 9, block_size=128, **kw),
        lambda **kw: fading.vector_paths([[1.25, 1.0], [0, 0.9]], [1, 0], np.eye(2), 1.0, SN2,
                                         Rayleigh(1.0), np.eye(2), 12, 700, 9, block_size=128,
                                         **kw),
    ]


@pytest.mark.parametrize("run", _all_paths(), ids=["scalar", "multisensor", "vector"])
def test_results_do_not_depend_on_chunking_or_executor(run):
    ref = run().samples
    np.testing.assert_array_equal(ref, run(chunk_size=128).samples)
    np.testing.assert_array_equal(ref, run(chunk_size=300).samples)
    with ThreadPoolExecutor(2) as ex:
        np.testing.assert_array_equal(ref, run(executor=ex, chunk_size=256).samples)
    assert ref.shape[:2] == (700, 13)


def test_seed_changes_the_draws_and_mc_wraps_paths():
    res = fading.scalar_paths(A, SW2, 1.0, SN2, Rayleigh(LAM), 1.0, 5, 300, 1)
    mean, se = fading.scalar_mc(A, SW2, 1.0, SN2, Rayleigh(LAM), 1.0, 5, 300, 1)
    np.testing.assert_array_equal(mean, res.mean)
    np.testing.assert_array_equal(se, res.stderr)
    other = fading.scalar_mc(A, SW2, 1.0, SN2, Rayleigh(LAM), 1.0, 5, 300, 2)[0]
    assert not np.array_equal(mean, other)


# ----------------------------------------------------------------------------- validation
@pytest.mark.parametrize("kwargs, name", [
    ({"sigma_w2": -1.0}, "sigma_w2"),
    ({"sigma_v2": -1.0}, "sigma_v2"),
    ({"sigma_v2": np.nan}, "sigma_v2"),  # 0 is a legitimate limit (test_fading_limits)
    ({"sigma_n2": -4.0}, "sigma_n2"),
    ({"p0": -1.0}, "p0"),
    ({"steps": -1}, "steps"),
    ({"steps": 2.5}, "steps"),
    ({"a": np.nan}, "a"),
    ({"channel": "rayleigh"}, "channel"),
])
def test_scalar_input_validation(kwargs, name):
    args = {"a": A, "sigma_w2": SW2, "sigma_v2": 1.0, "sigma_n2": SN2, "channel": Rayleigh(1.0),
            "p0": 1.0, "steps": 5}
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        fading.scalar_bounds(**args)
    with pytest.raises(ValueError, match=name):
        fading.scalar_mc(**args, n_paths=10, seed=0)


def test_channel_and_runner_validation():
    for bad in (0.0, -1.0, np.inf, np.nan, "x", True):
        with pytest.raises(ValueError, match="lam"):
            Rayleigh(bad)
        with pytest.raises(ValueError, match="lam"):
            Nakagami(1.0, bad)
    for bad in (0.49, np.nan, "x"):
        with pytest.raises(ValueError, match="m must"):
            Nakagami(bad, 1.0)
    with pytest.raises(ValueError, match="n_paths"):
        fading.scalar_mc(A, SW2, 1.0, SN2, Rayleigh(1.0), 1.0, 5, 0, 0)
    with pytest.raises(ValueError, match="seed"):
        fading.scalar_mc(A, SW2, 1.0, SN2, Rayleigh(1.0), 1.0, 5, 10, -1)
    with pytest.raises(ValueError, match="b must"):
        Rayleigh(1.0).ratio_mean(-1.0)


@pytest.mark.parametrize("change, name", [
    ({"access": "tdma"}, "access"),
    ({"lams": [1.0]}, "lams"),
    ({"lams": [1.0, 0.0]}, "lams"),
    ({"sigma_v2": [1.0, -4.0]}, "sigma_v2"),
    ({"sigma_v2": [1.0, 4.0, 2.0]}, "sigma_v2"),
    ({"c": [1.0, -1.0]}, "c must be positive"),
    ({"sigma_n2": [4.0, 4.0]}, "sigma_n2"),
    ({"sigma_n2": -4.0}, "sigma_n2"),
    ({"sigma_w2": -1.0}, "sigma_w2"),
    ({"steps": -3}, "steps"),
])
def test_multisensor_input_validation(change, name):
    args = {"access": "multi-access", "a": A, "c": [1.0, 1.0], "sigma_v2": [1.0, 4.0],
            "sigma_n2": SN2, "lams": [1.0, 2.0], "sigma_w2": SW2, "p0": 1.0, "steps": 5}
    args.update(change)
    with pytest.raises(ValueError, match=name):
        fading.multisensor_bounds(**args)
    with pytest.raises(ValueError, match=name):
        fading.multisensor_mc(**args, n_paths=10, seed=0)


def test_last_sensor_validation():
    args = (A, [1.0, 1.0], [1.0, 4.0], SN2, [1.0, 2.0], SW2, 1.0, 5)
    with pytest.raises(ValueError, match="last_sensor"):
        fading.multisensor_bounds("orthogonal", *args, last_sensor=0)
    with pytest.raises(ValueError, match="last_sensor"):
        fading.multisensor_bounds("multi-access", *args, last_sensor=2)
    with pytest.raises(ValueError, match="sigma_n2"):
        fading.multisensor_bounds("orthogonal", A, [1, 1], [1, 4], [4.0, 4.0, 4.0], [1, 2], SW2,
                                  1.0, 5)


def test_vector_input_validation():
    good = {"A": np.eye(2), "c": [1.0, 0.0], "Sigma_w": np.eye(2), "sigma_v2": 1.0,
            "sigma_n2": 1.0, "channel": Rayleigh(1.0), "P0": np.eye(2), "steps": 3}
    for change, name in [({"c": [1.0]}, "c"), ({"A": np.ones((2, 3))}, "A"),
                         ({"Sigma_w": -np.eye(2)}, "Sigma_w"), ({"P0": np.eye(3)}, "P0"),
                         ({"sigma_v2": -1.0}, "sigma_v2"), ({"steps": -1}, "steps")]:
        with pytest.raises(ValueError, match=name):
            fading.vector_bound(**{**good, **change})


@pytest.mark.parametrize("channel", [Rayleigh(100.0), Nakagami(0.5, 3.0), Nakagami(2.0, 1.0)])
def test_scalar_chunk_matches_the_direct_recursion_on_one_draw(channel, monkeypatch):
    """The harmonic, batched form of (15) equals the printed recursion on the same channel
    draws: batching the draws by steps must not change which numbers are drawn."""
    n, steps = 37, 23
    r = channel.sample(np.random.default_rng(3), (steps, n))  # one draw of all steps
    p = np.full(n, 0.7)
    want = [p]
    for k in range(steps):
        p = 1.0 + 1.5625 * p * (r[k] * 2.0 + 4.0) / (r[k] * (p + 2.0) + 4.0)
        want.append(p)
    want = np.array(want).T
    for batch_elements in (1, n * 5, 10**6):  # one step per batch, five, all
        monkeypatch.setattr(fading.scalar, "_BATCH_ELEMENTS", batch_elements)
        got = fading.scalar._scalar_chunk(np.random.default_rng(3), n, a=1.25, sigma_w2=1.0,
                                          sigma_v2=2.0, sigma_n2=4.0, channel=channel, p0=0.7,
                                          steps=steps)
        np.testing.assert_allclose(got, want, rtol=1e-13)


def test_scalar_chunk_limits_p0_zero_and_deep_fade():
    class Dead(Rayleigh):  # r = 0 always: no information, p' = sigma_w2 + a^2 p
        def sample(self, rng, size):
            return np.zeros(size)

    got = fading.scalar._scalar_chunk(np.random.default_rng(0), 2, a=2.0, sigma_w2=1.0,
                                      sigma_v2=1.0, sigma_n2=1.0, channel=Dead(1.0), p0=0.0,
                                      steps=3)
    np.testing.assert_array_equal(got, [[0.0, 1.0, 5.0, 21.0]] * 2)
