"""An independent reference for the copper Taylor bar: a 2D axisymmetric
Lagrangian finite-element solution of the same model, in numpy, sharing no
code with src/.  SI units.

It tells the discretisation's error (plyshock's MPM against this solution of
the same equations) apart from the model's (this solution against the test).

  mesh     nr x nz quadrilaterals on the bar's (r, z) half-section, one-point
           quadrature, true-volume (r-weighted) forces, lumped nodal masses
           (Hallquist, DYNA2D manual UCRL-52429, 1980; Benson, CMAME 99, 1992)
  time     central differences, the rates at the mid-step geometry, dt from the
           zones' smallest altitude / sound speed at Courant number 0.3
  stress   Jaumann rate, J2 radial return on the material's flow stress
           (Johnson-Cook, Zerilli-Armstrong fcc/bcc or MTS, written here from
           the models' equations: flow_stress below) with the total
           equivalent deviatoric rate, adiabatic heating 0.9 of the plastic
           work; Mie-Grueneisen pressure (as eos_mie_gruneisen.c); von
           Neumann-Richtmyer + linear viscosity in compression; viscous
           Flanagan-Belytschko hourglass control (IJNME 17, 1981), 0.05
  wall     a frictionless rigid wall at z = 0: a node there cannot move into it

Loops run over the four corners of a zone and over time steps, never over
zones or nodes.
"""
import numpy as np

from .materials import preset

_CORNERS = [(slice(None, -1), slice(None, -1)), (slice(None, -1), slice(1, None)),
            (slice(1, None), slice(1, None)), (slice(1, None), slice(None, -1))]   # counter-clockwise in (r, z)
_HOURGLASS = np.array([1.0, -1.0, 1.0, -1.0])[:, None, None]


def _corners(a):
    return np.stack([a[s] for s in _CORNERS])


def _geometry(r, z):
    """Planar area A, r-weighted volume int r dA (per radian), shape-function
    gradients at the centre (4 x zones), mean radius, smallest altitude."""
    (r1, r2, r3, r4), (z1, z2, z3, z4) = _corners(r), _corners(z)
    A = 0.5 * ((r3 - r1) * (z4 - z2) + (r2 - r4) * (z3 - z1))
    A1 = 0.5 * ((r2 - r1) * (z3 - z1) - (r3 - r1) * (z2 - z1))
    vol = A1 * (r1 + r2 + r3) / 3 + (A - A1) * (r1 + r3 + r4) / 3
    br = np.stack([z2 - z4, z3 - z1, z4 - z2, z1 - z3]) / (2 * A)
    bz = np.stack([r4 - r2, r1 - r3, r2 - r4, r3 - r1]) / (2 * A)
    ell = A / np.maximum(np.hypot(r3 - r1, z3 - z1), np.hypot(r4 - r2, z4 - z2))
    return A, vol, br, bz, 0.25 * (r1 + r2 + r3 + r4), ell


def _scatter(f, shape):
    out = np.zeros(shape)
    for k, s in enumerate(_CORNERS):
        out[s] += f[k]
    return out


def flow_stress(st, T_room=294.0):
    """Y(eps_p, rate, T) (Pa; arrays) of a deck's strength mapping:

      johnson-cook          (A + B eps_p^n)(1 + C ln max(rate/eps_dot0, 1))(1 - T*^m)
      zerilli-armstrong-fcc C0 + C2 eps_p^1/2 exp(-C3 T) rate^(C4 T)
      zerilli-armstrong-bcc C0 + C1 exp(-C3 T) rate^(C4 T) + C5 eps_p^n
      mts                   sigma_a + S_e sigma_e mu(T)/mu_0 (+ S_i sigma_i), the
                            threshold sigma_e at the current rate and T from a table
                            of the hardening law's quadrature, eps_p(X) = sigma_es/theta_0
                            int_0^X dX'/(1 - tanh(alpha X')/tanh alpha), interpolated
    """
    t = st["type"]
    if t == "johnson-cook":
        e0 = st.get("eps_dot0", 1.0)
        return lambda ep, rate, T: ((st["A"] + st["B"] * ep ** st["n"]) * (1 + st["C"] * np.log(np.maximum(rate / e0, 1.0)))
                                    * (1 - np.clip((T - T_room) / (st["T_melt"] - T_room), 0.0, 1.0) ** st["m"]))
    if t == "zerilli-armstrong-fcc":
        return lambda ep, rate, T: st["C0"] + st["C2"] * np.sqrt(ep) * np.exp(-st["C3"] * T) * rate ** (st["C4"] * T)
    if t == "zerilli-armstrong-bcc":
        return lambda ep, rate, T: (st["C0"] + st["C1"] * np.exp(-st["C3"] * T) * rate ** (st["C4"] * T)
                                    + st["C5"] * ep ** st["n"])
    if t != "mts":
        raise ValueError(f"taylor_rz: no flow stress for strength type {t!r}")
    a = st["alpha"]
    u = np.linspace(0.0, 30.0, 30001)                      # X = 1 - exp(-u): the table reaches X = 1 - 1e-13
    X = -np.expm1(-u)
    g = np.exp(-u) / (1.0 - np.tanh(a * X) / np.tanh(a))
    eps_table = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(u))])   # eps_p theta_0/sigma_es

    def S(c, g0, e0, rate, p, q):
        x = np.maximum(c / g0 * np.log(e0 / rate), 0.0)
        return np.maximum(1.0 - x ** (1.0 / q), 0.0) ** (1.0 / p)

    def Y(ep, rate, T):
        rate = np.maximum(rate, 1e-7)
        mu = st["mu_0"] - st["D"] / np.expm1(st["T_0"] / T)
        c = st["k_over_b3"] * T / mu
        th0 = np.maximum(st["a_0"] + st["a_1"] * np.log(rate) + st["a_2"] * np.sqrt(rate) - st["a_3"] * T, 1e-30)
        ses = st["sigma_es0"] * (rate / st["eps_dot_es0"]) ** (c / st["g_0es"])
        se = ses * np.interp(ep * th0 / ses, eps_table, X)
        out = st["sigma_a"] + S(c, st["g_0e"], st["eps_dot_0e"], rate, st["p_e"], st["q_e"]) * se * mu / st["mu_0"]
        if st.get("sigma_i", 0.0) > 0:
            out = out + S(c, st["g_0i"], st["eps_dot_0i"], rate, st["p_i"], st["q_i"]) * st["sigma_i"] * mu / st["mu_0"]
        return out
    return Y


def solve(nr=16, nz=107, t_end=80e-6, material="OFHC-copper", radius=3.81e-3, length=25.4e-3, speed=190.0,
          c_linear=0.2, c_quadratic=2.0, hourglass=0.05, T_room=294.0, chi=0.9):
    """The bar (radius, length in m) at speed (m/s) onto the wall, to t_end (s);
    material: a preset name (its EOS, shear modulus, specific heat and flow stress).
    Returns the final length and foot diameter (m), the kinetic energy left and
    (kinetic + internal) / initial kinetic energy."""
    P = preset(material)
    rho0, eos, G, cv = P["density"], P["eos"], P["shear_modulus"], P["specific_heat"]
    flow = flow_stress(P["strength"], T_room)
    c0, s, g0 = eos["c0"], eos["s"], eos["gamma0"]
    r = np.tile(np.linspace(0.0, radius, nr + 1), (nz + 1, 1))
    z = np.tile(np.linspace(0.0, length, nz + 1)[:, None], (1, nr + 1))
    u, w = np.zeros_like(r), np.full_like(r, -speed)
    _, V0, *_ = _geometry(r, z)
    mz = rho0 * V0                                        # zone mass per radian
    mn = _scatter(np.broadcast_to(mz / 4, (4,) + mz.shape), r.shape)
    srr, szz, stt, srz = (np.zeros(mz.shape) for _ in range(4))
    p, q, e, ep, T = np.zeros(mz.shape), np.zeros(mz.shape), np.zeros(mz.shape), np.zeros(mz.shape), np.full(mz.shape, T_room)

    def sound(J):
        return np.sqrt((rho0 * c0 * c0 / J + 4.0 * G / 3.0) * J / rho0)

    def forces():
        A, vol, br, bz, rbar, ell = _geometry(r, z)
        J = vol / V0
        c = sound(J)
        Sr, Sz, St = srr - p - q, szz - p - q, stt - p - q
        fr = -(Sr * br + srz * bz) * vol - St * A / 4     # the hoop stress: int sigma_tt N_i dA
        fz = -(srz * br + Sz * bz) * vol
        gam = _HOURGLASS - (_HOURGLASS * _corners(r)).sum(0) * br - (_HOURGLASS * _corners(z)).sum(0) * bz
        k = hourglass * rho0 / J * c * rbar * np.sqrt(A)
        fr = fr - k * (gam * _corners(u)).sum(0) * gam
        fz = fz - k * (gam * _corners(w)).sum(0) * gam
        return _scatter(fr, r.shape), _scatter(fz, r.shape), (ell / c).min()

    ke0 = 0.5 * (mn * w * w).sum()
    Fr, Fz, dtc = forces()
    t, dt, first = 0.0, 0.3 * dtc, True
    while t < t_end * (1 - 1e-12):
        dt = min(dt, t_end - t)
        h = 0.5 * dt if first else dt                       # velocities live at half steps
        first = False
        u, w = u + h * Fr / mn, w + h * Fz / mn
        u[:, 0] = 0.0                                       # the axis
        w = np.where((z <= 0.0) & (w < 0.0), 0.0, w)        # the wall
        rn, zn = r + dt * u, np.maximum(z + dt * w, 0.0)
        _, _, br, bz, rbar, _ = _geometry(0.5 * (r + rn), 0.5 * (z + zn))
        U, W = _corners(u), _corners(w)
        drr, dzz, dtt = (U * br).sum(0), (W * bz).sum(0), U.mean(0) / rbar
        dudz, dwdr = (U * bz).sum(0), (W * br).sum(0)
        drz, om = 0.5 * (dudz + dwdr), 0.5 * (dudz - dwdr)
        r, z = rn, zn
        _, vol, _, _, _, ell = _geometry(r, z)
        if np.any(vol <= 0.0):
            raise RuntimeError(f"taylor_rz: a zone inverted at t = {t:.3g} s")
        J = vol / V0
        rho = rho0 / J
        trD = drr + dzz + dtt
        d1, d2, d3 = drr - trD / 3, dzz - trD / 3, dtt - trD / 3
        old = (srr, szz, stt, srz)
        # elastic trial with the Jaumann rotation, then the radial return
        a1 = srr + dt * (2 * G * d1 + 2 * om * srz)
        a2 = szz + dt * (2 * G * d2 - 2 * om * srz)
        a3 = stt + dt * (2 * G * d3)
        a4 = srz + dt * (2 * G * drz + om * (szz - srr))
        seq = np.sqrt(1.5 * (a1 * a1 + a2 * a2 + a3 * a3 + 2 * a4 * a4))
        rate = np.sqrt(2.0 / 3.0 * (d1 * d1 + d2 * d2 + d3 * d3 + 2 * drz * drz))
        Y = flow(ep, rate, T)
        yielding = seq > Y
        scale = np.where(yielding, Y / np.maximum(seq, 1e-300), 1.0)
        dep = np.where(yielding, (seq - Y) / (3 * G), 0.0)
        srr, szz, stt, srz = a1 * scale, a2 * scale, a3 * scale, a4 * scale
        ep = ep + dep
        T = T + chi * Y * dep / (rho * cv)
        c = sound(J)
        q = np.where(trD < 0, rho * ell * (c_quadratic * ell * trD * trD + c_linear * c * np.abs(trD)), 0.0)
        wdev = 0.5 * ((old[0] + srr) * d1 + (old[1] + szz) * d2 + (old[2] + stt) * d3 + 2 * (old[3] + srz) * drz)
        e = e + dt / rho * (wdev - (p + q) * trD)
        mu = 1.0 / J - 1.0
        cold = np.where(mu > 0, rho0 * c0 * c0 * mu * (1 + mu) / (1 - (s - 1) * mu) ** 2 * (1 - 0.5 * g0 * mu / (1 + mu)),
                        rho0 * c0 * c0 * mu)
        p = cold + g0 * rho0 * e
        Fr, Fz, dtc = forces()
        t += dt
        dt = min(0.3 * dtc, 1.1 * dt)
    ke = 0.5 * (mn * (u * u + w * w)).sum()
    return dict(length=float(z.max() - z.min()), diameter=float(2 * r[0].max()), kinetic_left=float(ke / ke0),
                energy_ratio=float((ke + (mz * e).sum()) / ke0), eps_p_max=float(ep.max()), zones=nr * nz)
