"""Exact solution of the Riemann problem for the Euler equations of two ideal gases.

The reference for the shock-tube verification of the Eulerian cells: a
discontinuity at x0 between a left state (rho_L, u_L, p_L) of a gas with
gamma_L and a right state of a gas with gamma_R (the contact separates the two
materials), evolved to time t.  Numpy only; shares no code with src/.

Method: Toro, "Riemann Solvers and Numerical Methods for Fluid Dynamics" (3rd ed.,
Springer 2009), chapter 4, with each side's pressure function written with its
own gamma (the star pressure and velocity are continuous across the contact
whatever the gases, so nothing else changes):
- the pressure function f(p) = f_L(p) + f_R(p) + (u_R - u_L), f_K the shock
  branch (4.6)-(4.8) for p > p_K and the rarefaction branch (4.7) for p <= p_K;
  its root p* by Newton's method (4.44) from the PVRS guess (4.47) (f is
  increasing and concave, so Newton converges; Toro section 4.3.1), to 1e-15
  relative;
- u* = (u_L + u_R)/2 + (f_R(p*) - f_L(p*))/2 (4.9);
- the star densities from the shock (4.50, 4.57) or isentropic (4.53, 4.60) relations;
- sampling of the self-similar solution at xi = (x - x0)/t (section 4.5,
  fan states 4.56 and 4.63), vectorised over the points with numpy masks.
No vacuum: states whose rarefactions would open one (the pressure positivity
condition 4.40 fails) are refused.

Units: any consistent set (SI in the code: kg/m^3, m/s, Pa, and then J/kg for e).

    >>> s = solve(1.0, 0.0, 1.0, 0.125, 0.0, 0.1)          # Sod, gamma 1.4
    >>> round(s.p_star, 5), round(s.u_star, 5)
    (0.30313, 0.92745)
    >>> rho, u, p, e, side = s.sample((x - 0.5) / 0.2)       # the profile at t = 0.2
"""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Gas:
    """One side's state: density, velocity, pressure and the gas's gamma."""
    rho: float
    u: float
    p: float
    gamma: float

    @property
    def c(self):
        """Sound speed sqrt(gamma p / rho)."""
        return float(np.sqrt(self.gamma * self.p / self.rho))


def pressure_function(p, g: Gas):
    """Toro's f_K(p) and its derivative (4.6, 4.7, 4.37): the velocity change
    across the K wave that brings g to pressure p (shock for p > p_K,
    rarefaction otherwise)."""
    p = np.asarray(p, dtype=float)
    G = g.gamma
    A, B = 2.0 / ((G + 1.0) * g.rho), (G - 1.0) / (G + 1.0) * g.p
    shock = p > g.p
    ps = np.where(shock, p, g.p + 1.0)  # keep each branch's formula finite on the other side
    pr = np.where(shock, g.p, p)
    q = np.sqrt(A / (ps + B))
    f_s = (ps - g.p) * q
    df_s = q * (1.0 - 0.5 * (ps - g.p) / (B + ps))
    r = (pr / g.p) ** ((G - 1.0) / (2.0 * G))
    f_r = 2.0 * g.c / (G - 1.0) * (r - 1.0)
    df_r = r / (g.rho * g.c) * (g.p / pr)  # (1/(rho c)) (p/p_K)^(-(G+1)/(2G))
    return np.where(shock, f_s, f_r), np.where(shock, df_s, df_r)


@dataclass(frozen=True)
class Riemann:
    """The solved problem: the two states, the star region and the wave speeds."""
    left: Gas
    right: Gas
    p_star: float
    u_star: float
    rho_star_left: float
    rho_star_right: float
    iterations: int

    @property
    def left_is_shock(self):
        return self.p_star > self.left.p

    @property
    def right_is_shock(self):
        return self.p_star > self.right.p

    def speeds(self):
        """The wave speeds: for the left wave (head, tail) of the rarefaction or
        (S, S) of the shock; the contact u*; the same for the right wave."""
        L, R, ps, us = self.left, self.right, self.p_star, self.u_star
        if self.left_is_shock:
            S = L.u - L.c * np.sqrt((L.gamma + 1) / (2 * L.gamma) * ps / L.p + (L.gamma - 1) / (2 * L.gamma))
            left = (S, S)
        else:
            left = (L.u - L.c, us - L.c * (ps / L.p) ** ((L.gamma - 1) / (2 * L.gamma)))
        if self.right_is_shock:
            S = R.u + R.c * np.sqrt((R.gamma + 1) / (2 * R.gamma) * ps / R.p + (R.gamma - 1) / (2 * R.gamma))
            right = (S, S)
        else:
            right = (us + R.c * (ps / R.p) ** ((R.gamma - 1) / (2 * R.gamma)), R.u + R.c)
        return dict(left=tuple(map(float, left)), contact=float(us), right=tuple(map(float, right)))

    def sample(self, xi):
        """The solution at xi = (x - x0)/t (any array shape): density, velocity,
        pressure, specific internal energy p/((gamma-1) rho), and the side
        (0: left gas, 1: right gas) of each point."""
        xi = np.asarray(xi, dtype=float)
        L, R, ps, us = self.left, self.right, self.p_star, self.u_star
        w = self.speeds()
        rho = np.empty_like(xi)
        u = np.empty_like(xi)
        p = np.empty_like(xi)
        left = xi < us
        # left of the contact: the left state, the fan, the star state
        G, c = L.gamma, L.c
        head, tail = w["left"]
        m = left & (xi < head)
        rho[m], u[m], p[m] = L.rho, L.u, L.p
        m = left & (xi >= tail)
        rho[m], u[m], p[m] = self.rho_star_left, us, ps
        m = left & (xi >= head) & (xi < tail)  # empty for a shock
        k = 2.0 / (G + 1.0) + (G - 1.0) / ((G + 1.0) * c) * (L.u - xi[m])
        rho[m] = L.rho * k ** (2.0 / (G - 1.0))
        u[m] = 2.0 / (G + 1.0) * (c + 0.5 * (G - 1.0) * L.u + xi[m])
        p[m] = L.p * k ** (2.0 * G / (G - 1.0))
        # right of the contact
        G, c = R.gamma, R.c
        tail, head = w["right"]
        right = ~left
        m = right & (xi > head)
        rho[m], u[m], p[m] = R.rho, R.u, R.p
        m = right & (xi <= tail)
        rho[m], u[m], p[m] = self.rho_star_right, us, ps
        m = right & (xi > tail) & (xi <= head)
        k = 2.0 / (G + 1.0) - (G - 1.0) / ((G + 1.0) * c) * (R.u - xi[m])
        rho[m] = R.rho * k ** (2.0 / (G - 1.0))
        u[m] = 2.0 / (G + 1.0) * (-c + 0.5 * (G - 1.0) * R.u + xi[m])
        p[m] = R.p * k ** (2.0 * G / (G - 1.0))
        gamma = np.where(left, L.gamma, R.gamma)
        return rho, u, p, p / ((gamma - 1.0) * rho), (~left).astype(int)

    def profile(self, x, t, x0=0.0):
        """sample() at the points x (m) at time t > 0 (s) for a discontinuity at x0."""
        return self.sample((np.asarray(x, dtype=float) - x0) / t)


def solve(rho_l, u_l, p_l, rho_r, u_r, p_r, gamma_l=1.4, gamma_r=None, tol=1e-15, max_iter=100):
    """Solve the Riemann problem between (rho_l, u_l, p_l) with gamma_l and
    (rho_r, u_r, p_r) with gamma_r (default gamma_l).  Returns a Riemann."""
    gamma_r = gamma_l if gamma_r is None else gamma_r
    L, R = Gas(float(rho_l), float(u_l), float(p_l), float(gamma_l)), Gas(float(rho_r), float(u_r), float(p_r), float(gamma_r))
    for name, g in (("left", L), ("right", R)):
        if not (g.rho > 0 and g.p > 0 and g.gamma > 1):
            raise ValueError(f"{name} state needs rho > 0, p > 0 and gamma > 1: {g}")
    du = R.u - L.u
    if 2 * L.c / (L.gamma - 1) + 2 * R.c / (R.gamma - 1) <= du:
        raise ValueError("the rarefactions open a vacuum (Toro 4.40 fails): not handled")
    # PVRS guess (Toro 4.47), kept positive
    p = max(0.5 * (L.p + R.p) - 0.125 * du * (L.rho + R.rho) * (L.c + R.c), 1e-8 * min(L.p, R.p))
    for it in range(1, max_iter + 1):
        fl, dfl = pressure_function(p, L)
        fr, dfr = pressure_function(p, R)
        step = float((fl + fr + du) / (dfl + dfr))
        p_new = p - step
        if p_new <= 0.0:  # an overshoot to the left of 0: f is concave, so from the left it converges
            p_new = 0.5 * p
        change = abs(p_new - p) / (0.5 * (p_new + p))
        p = p_new
        if change <= tol:
            break
    else:
        raise RuntimeError(f"Newton's iteration for p* did not converge in {max_iter} steps")
    fl, _ = pressure_function(p, L)
    fr, _ = pressure_function(p, R)
    u = 0.5 * (L.u + R.u) + 0.5 * float(fr - fl)

    def star_density(g):
        if p > g.p:
            k = (g.gamma - 1.0) / (g.gamma + 1.0)
            return g.rho * (p / g.p + k) / (k * p / g.p + 1.0)
        return g.rho * (p / g.p) ** (1.0 / g.gamma)

    return Riemann(L, R, float(p), float(u), float(star_density(L)), float(star_density(R)), it)
