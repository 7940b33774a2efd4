"""The exact Riemann solver of the ideal-gas Euler equations (plyshock.riemann),
the reference for the shock-tube verification of the Eulerian cells.

Every rank runs the same checks (numpy only)."""
import numpy as np
import pytest

from plyshock import riemann


def sod():
    return riemann.solve(1.0, 0.0, 1.0, 0.125, 0.0, 0.1, gamma_l=1.4)


def test_sod_star_state():
    """Sod's star state (Toro, table 4.3): p* 0.30313, u* 0.92745, rho*L 0.42632,
    rho*R 0.26557, to 1e-5; the pressure function is zero there to round-off."""
    s = sod()
    assert abs(s.p_star - 0.30313) <= 1e-5
    assert abs(s.u_star - 0.92745) <= 1e-5
    assert abs(s.rho_star_left - 0.42632) <= 1e-5
    assert abs(s.rho_star_right - 0.26557) <= 1e-5
    fl, _ = riemann.pressure_function(s.p_star, s.left)
    fr, _ = riemann.pressure_function(s.p_star, s.right)
    assert abs(fl + fr + s.right.u - s.left.u) <= 1e-14
    assert not s.left_is_shock and s.right_is_shock


def waves_from_profile(x, rho, u, p, x0):
    """Where the waves are, read off a sampled profile: the rarefaction's head is
    the last point still in the left state, its tail the first point in the
    left star state, the contact the density jump at constant p, the shock the
    first point of the right state."""
    L = (rho == rho[0]) & (u == u[0]) & (p == p[0])
    R = (rho == rho[-1]) & (u == u[-1]) & (p == p[-1])
    head = x[np.nonzero(L)[0][-1]]
    shock = x[np.nonzero(R)[0][0]]
    star = np.nonzero(np.abs(p - p[np.argmin(np.abs(x - x0 - 0.1))]) <= 1e-12)[0]
    tail = x[star[0]]
    jump = np.argmax(np.abs(np.diff(rho[star[0]:star[-1] + 1]))) + star[0]
    contact = 0.5 * (x[jump] + x[jump + 1])
    return head, tail, contact, shock


def test_sod_profile_at_t_02():
    """At t = 0.2 (x0 = 0.5 in [0, 1]) the sampled profile's rarefaction head and
    tail, contact and shock sit where the closed-form wave speeds put them,
    within the sampling step: head 0.5 - c_L t; tail 0.5 + (u* - c*L) t with
    c*L = sqrt(gamma p*/rho*L); contact 0.5 + u* t; shock 0.5 + S t with S from
    mass conservation across it, S = rho*R u* / (rho*R - rho_R), all from the
    quoted star values (so to their 5 digits).  Outside the waves the states
    are the left, star and right states, and the fan is isentropic and has
    u + 2c/(gamma-1) constant (Toro 4.55)."""
    g, t, x0 = 1.4, 0.2, 0.5
    ps, us, rl, rr = 0.30313, 0.92745, 0.42632, 0.26557
    x = np.linspace(0.0, 1.0, 100001)
    dx = x[1] - x[0]
    rho, u, p, e, side = sod().profile(x, t, x0)
    head, tail, contact, shock = waves_from_profile(x, rho, u, p, x0)
    cl = np.sqrt(g * 1.0 / 1.0)
    tol = dx + 2e-5 * t
    assert abs(head - (x0 - cl * t)) <= tol
    assert abs(tail - (x0 + (us - np.sqrt(g * ps / rl)) * t)) <= tol
    assert abs(contact - (x0 + us * t)) <= tol
    assert abs(shock - (x0 + rr * us / (rr - 0.125) * t)) <= tol
    # the positions usually quoted for Sod's tube at t = 0.2
    assert np.allclose([head, tail, contact, shock], [0.263, 0.486, 0.685, 0.850], atol=1e-3)
    fan = (x > head) & (x < tail)
    assert np.allclose(p[fan] / rho[fan] ** g, 1.0, rtol=1e-12)
    assert np.allclose(u[fan] + 2 * np.sqrt(g * p[fan] / rho[fan]) / (g - 1), 2 * cl / (g - 1), rtol=0, atol=1e-12)
    assert np.all(side == (x > contact))
    assert np.allclose(e, p / ((g - 1) * rho), rtol=1e-15)


def rankine_hugoniot(a, b, S, ga, gb):
    """Residuals of mass, momentum and energy across a discontinuity moving at S
    between states a = (rho, u, p) with gamma ga and b with gamma gb."""
    def flux(s, gam):
        r, v, q = s
        E = q / (gam - 1) + 0.5 * r * v * v
        return np.array([r * (v - S), r * v * (v - S) + q, E * (v - S) + q * v])
    return flux(a, ga) - flux(b, gb)


@pytest.mark.parametrize("case, kinds", [
    # (rho_l, u_l, p_l, gamma_l, rho_r, u_r, p_r, gamma_r), (left wave, right wave is a shock):
    # a Sod-like tube of air into helium; two streams of different gases colliding;
    # in SI (kg/m^3, m/s, Pa), compressed air against a dense gas
    ((1.0, 0.0, 1.0, 1.4, 0.125, 0.0, 0.1, 5.0 / 3.0), (False, True)),
    ((1.0, 2.0, 1.0, 5.0 / 3.0, 4.0, -1.0, 0.5, 1.2), (True, True)),
    ((12.0, 0.0, 1e6, 1.4, 8930.0, 50.0, 1e5, 3.0), (False, True)),
    ((0.125, 0.0, 0.1, 5.0 / 3.0, 1.0, 0.0, 1.0, 1.4), (True, False)),   # the first, mirrored
    ((1.0, -1.0, 1.0, 1.4, 2.0, 1.5, 3.0, 1.2), (False, False)),         # two rarefactions
])
def test_two_gases(case, kinds):
    """Different gammas on the two sides: p and u continuous across the contact
    (to round-off), each gas keeps its own gamma in the energy, the
    Rankine-Hugoniot conditions hold across every shock (1e-12 of the fluxes)
    with the solver's own shock speed, and across a rarefaction p/rho^gamma and
    the Riemann invariant are kept with that side's gamma."""
    rl, ul, pl, gl, rr, ur, pr, gr = case
    s = riemann.solve(rl, ul, pl, rr, ur, pr, gamma_l=gl, gamma_r=gr)
    w = s.speeds()
    assert (s.left_is_shock, s.right_is_shock) == kinds
    span = max(abs(w["left"][0]), abs(w["right"][1])) * 1.5
    eps = 1e-9 * span
    c = w["contact"]
    a = s.sample(np.array([c - eps, c + eps]))
    assert abs(a[2][0] - a[2][1]) <= 1e-12 * s.p_star and abs(a[1][0] - a[1][1]) <= 1e-12 * (abs(s.u_star) + s.left.c)
    assert abs(a[2][0] - s.p_star) <= 1e-12 * s.p_star
    assert np.allclose(a[3], [s.p_star / ((gl - 1) * s.rho_star_left), s.p_star / ((gr - 1) * s.rho_star_right)], rtol=1e-14)
    assert list(a[4]) == [0, 1]
    for side, gam, outer in (("left", gl, s.left), ("right", gr, s.right)):
        lo, hi = w[side]
        if (side == "left" and s.left_is_shock) or (side == "right" and s.right_is_shock):
            S = lo
            rho, u, p, _, _ = s.sample(np.array([S - eps, S + eps]))
            pre, post = np.array([rho[0], u[0], p[0]]), np.array([rho[1], u[1], p[1]])
            scale = np.abs(np.r_[pre[0] * (abs(pre[1]) + abs(S)), pre[2] + pre[0] * pre[1] ** 2, (pre[2] / (gam - 1) + pre[0] * pre[1] ** 2) * (abs(pre[1]) + abs(S)) + pre[2] * abs(pre[1])])
            assert np.all(np.abs(rankine_hugoniot(pre, post, S, gam, gam)) <= 1e-12 * scale)
            # the shock compresses and raises the entropy of the gas it crosses
            out, star = (pre, post) if side == "left" else (post, pre)
            assert star[0] > out[0] and star[2] / star[0] ** gam > out[2] / out[0] ** gam
        else:
            xi = np.linspace(lo, hi, 101)
            rho, u, p, _, _ = s.sample(xi)
            assert np.allclose(p / rho ** gam, outer.p / outer.rho ** gam, rtol=1e-12)
            cs = np.sqrt(gam * p / rho)
            J = u + 2 * cs / (gam - 1) if side == "left" else u - 2 * cs / (gam - 1)
            assert np.allclose(J, J[0], rtol=0, atol=1e-12 * (abs(J[0]) + outer.c))
            # the fan joins the outer state at its head and the star state at its tail
            assert np.isclose(p[0 if side == "left" else -1], outer.p, rtol=1e-12)
            assert np.isclose(p[-1 if side == "left" else 0], s.p_star, rtol=1e-12)


def test_same_gamma_is_symmetric_and_vacuum_is_refused():
    """Mirroring the problem mirrors the solution; states whose rarefactions
    would open a vacuum are refused."""
    a = riemann.solve(1.0, 0.3, 2.0, 0.5, -0.1, 0.4, gamma_l=1.4, gamma_r=1.6)
    b = riemann.solve(0.5, 0.1, 0.4, 1.0, -0.3, 2.0, gamma_l=1.6, gamma_r=1.4)
    assert np.isclose(a.p_star, b.p_star, rtol=1e-14) and np.isclose(a.u_star, -b.u_star, rtol=1e-14)
    assert np.isclose(a.rho_star_left, b.rho_star_right, rtol=1e-14)
    with pytest.raises(ValueError):
        riemann.solve(1.0, -10.0, 1.0, 1.0, 10.0, 1.0)
