"""Flow-stress models through the solver's own kernel (core.drive_material, one
3D marker, no grid): Zerilli-Armstrong (fcc, bcc) and the Mechanical Threshold
Stress model follow their adiabatic flow curves, computed here independently
of src/; bad constants are named errors."""
import numpy as np
import pytest
import yaml
from mpi4py import MPI

from plyshock import DeckError, Material
from plyshock import core
from plyshock.deck import load_text

COMM = MPI.COMM_WORLD


def drive_isochoric(material, rate, n=20000, strain=1.0):
    """Isochoric uniaxial compression at a constant rate (1/s) to a true strain
    of `strain` in n steps; the von Mises stress after each step."""
    dt = strain / (n * rate)
    L = np.zeros((n, 3, 3))
    L[:, 0, 0], L[:, 1, 1], L[:, 2, 2] = -rate, rate / 2, rate / 2
    r = core.drive_material(material, L, dt)
    dev = r["stress"] - np.einsum("nii->n", r["stress"])[:, None, None] / 3 * np.eye(3)
    return np.sqrt(1.5 * np.einsum("nij,nij->n", dev, dev))


def adiabatic_reference(flow_at, G, rho, cv, T0, nr=2000, strain=1.0, chi=0.9):
    """The flow curve implicit in eps_p: at each total strain step of strain/nr,
    bisection on eps - eps_p = Y(eps_p, T)/(3G) (elastic-plastic split of the
    strain along the curve), with T raised trapezoidally by chi Y d eps_p/(rho cv).
    flow_at(T) returns Y(eps_p) at that temperature (vectorised)."""
    ep, T, y, ref = 0.0, T0, 0.0, np.empty(nr)
    for k in range(nr):
        eps = (k + 1) * strain / nr
        Y = flow_at(T)
        lo, hi = ep, eps
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if eps - mid > Y(mid) / (3 * G) else (lo, mid)
        y_new = min(3 * G * eps, float(Y(hi)))
        T += chi * 0.5 * (y + y_new) * (hi - ep) / (rho * cv)
        ep, y, ref[k] = hi, y_new, y_new
    return ref


def compare(seq, ref, rel, strain=1.0):
    n, nr = len(seq), len(ref)
    for s in (0.05, 0.2, 0.5, 1.0):
        k, kr = round(s / strain * n) - 1, round(s / strain * nr) - 1
        assert seq[k] == pytest.approx(ref[kr], rel=rel), (s, seq[k], ref[kr])


@pytest.mark.parametrize("rate", [1.0e3, 1.0e5])
def test_zerilli_armstrong_fcc_kernel_follows_the_adiabatic_flow_curve(rate):
    """OFHC copper, Zerilli-Armstrong fcc form: Y = C0 + C2 eps_p^1/2
    exp(-C3 T + C4 T ln rate), adiabatic; the kernel (explicit in eps_p and T,
    20,000 steps) agrees with the implicit reference to 0.1%."""
    if COMM.rank:
        return
    cu = Material("cu", preset="OFHC-copper-ZA").validate("m")
    z = cu.strength
    flow_at = lambda T: (lambda ep: z["C0"] + z["C2"] * np.sqrt(ep) * np.exp(-z["C3"] * T + z["C4"] * T * np.log(rate)))
    ref = adiabatic_reference(flow_at, cu.shear_modulus, cu.density, cu.specific_heat, 294.0)
    compare(drive_isochoric(cu, rate), ref, 1e-3)
    assert ref[-1] > 2 * z["C0"]            # it hardens: the curve is not its constant part


IRON_ZA = {"type": "zerilli-armstrong-bcc", "C0": 70e6, "C1": 1033e6, "C3": 0.00698, "C4": 0.000415, "C5": 266e6, "n": 0.289}


@pytest.mark.parametrize("rate", [1.0e3, 1.0e5])
def test_zerilli_armstrong_bcc_kernel_follows_the_adiabatic_flow_curve(rate):
    """The bcc form with Armco-iron-like constants (C1 1033 MPa, C3 0.00698/K,
    C4 0.000415/K, C5 266 MPa, n 0.289, C0 70 MPa; an isotropic elastic iron,
    E 211 GPa, nu 0.29): Y = C0 + C1 exp(-C3 T + C4 T ln rate) + C5 eps_p^n,
    adiabatic, within 0.1% (the thermal term softens as the marker heats)."""
    if COMM.rank:
        return
    fe = Material("fe", density=7870.0, elastic={"type": "isotropic", "E": 211e9, "nu": 0.29},
                  strength=dict(IRON_ZA), specific_heat=452.0).validate("m")
    z = fe.strength
    G = 211e9 / (2 * 1.29)
    flow_at = lambda T: (lambda ep: z["C0"] + z["C1"] * np.exp(-z["C3"] * T + z["C4"] * T * np.log(rate)) + z["C5"] * ep ** z["n"])
    ref = adiabatic_reference(flow_at, G, fe.density, fe.specific_heat, 294.0)
    compare(drive_isochoric(fe, rate), ref, 1e-3)


def mts_flow_at(st, rate):
    """The MTS flow stress of src/materials/strength_mts.c written from the
    model's equations, with the evolving threshold sigma_e(eps_p) at (rate, T)
    from a quadrature of its hardening law d sigma_e/d eps_p = theta_0 (1 -
    tanh(alpha X)/tanh(alpha)) (not the closed form the kernel uses)."""
    a = st["alpha"]
    u = np.linspace(0.0, 30.0, 30001)              # u = -ln(1 - X): the law's saturation is at X = 1
    X = -np.expm1(-u)
    g = np.exp(-u) / (1.0 - np.tanh(a * X) / np.tanh(a))   # dX/du / (theta / theta_0)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(u))])   # eps_p theta_0 / sigma_es

    def at(T):
        mu = st["mu_0"] - st["D"] / np.expm1(st["T_0"] / T)
        c = st["k_over_b3"] * T / mu
        Se = max(0.0, 1.0 - (c / st["g_0e"] * np.log(st["eps_dot_0e"] / rate)) ** (1.0 / st["q_e"])) ** (1.0 / st["p_e"])
        th0 = st["a_0"] + st["a_1"] * np.log(rate) + st["a_2"] * np.sqrt(rate) - st["a_3"] * T
        ses = st["sigma_es0"] * (rate / st["eps_dot_es0"]) ** (c / st["g_0es"])
        return lambda ep: st["sigma_a"] + Se * ses * np.interp(ep * th0 / ses, cum, X) * mu / st["mu_0"]
    return at


@pytest.mark.parametrize("rate", [1.0e3, 1.0e5])
def test_mts_kernel_follows_the_adiabatic_flow_curve(rate):
    """OFHC copper, Mechanical Threshold Stress (Follansbee & Kocks 1988,
    Uintah's copper constants): the kernel follows the adiabatic curve within
    0.1% (0.06% at a strain of 0.05, explicit in eps_p against the steep early
    hardening, theta_0 ~ 2.4 GPa),
    and the curve saturates toward sigma_a + sigma_es mu/mu_0."""
    if COMM.rank:
        return
    cu = Material("cu", preset="OFHC-copper-MTS").validate("m")
    ref = adiabatic_reference(mts_flow_at(cu.strength, rate), cu.shear_modulus, cu.density, cu.specific_heat, 294.0)
    seq = drive_isochoric(cu, rate)
    compare(seq, ref, 1e-3)
    # hardening slows as sigma_e nears its saturation: the last half adds less than the first 5%
    assert ref[-1] - ref[len(ref) // 2] < ref[len(ref) // 20] - ref[0]


def test_mts_constant_temperature_curve_is_the_integrated_hardening_law():
    """With no heating (taylor_quinney 0) T stays 294 K and the kernel's flow
    stress at every plastic strain is sigma_a + S_e sigma_e(eps_p) mu/mu_0 with
    sigma_e from the quadrature of the hardening law, within 0.1%."""
    if COMM.rank:
        return
    cu = Material("cu", preset="OFHC-copper-MTS").validate("m")
    cu.strength["taylor_quinney"] = 0.0
    rate = 1.0e4
    ref = adiabatic_reference(mts_flow_at(cu.strength, rate), cu.shear_modulus, cu.density, cu.specific_heat, 294.0, chi=0.0)
    compare(drive_isochoric(cu, rate), ref, 1e-3)


def deck_with_strength(strength):
    return {"dimension": 2, "grid": {"lower": [0, 0], "upper": [1, 1], "cells": [4, 4]},
            "materials": [{"name": "cu", "preset": "OFHC-copper-MTS", "strength": strength}],
            "bodies": [{"name": "b", "material": "cu", "box": {"lower": [0.1, 0.1], "upper": [0.6, 0.6]}}]}


BAD = [
    ({"type": "zerilli-armstrong-fcc", "C0": 65e6, "C2": 890e6, "C3": 0.0028}, "materials[0].strength.C4", "is required"),
    ({"type": "zerilli-armstrong-fcc", "C0": 65e6, "C2": -1.0, "C3": 0.0028, "C4": 1e-4}, "materials[0].strength.C2", "allowed [0, inf]"),
    ({**IRON_ZA, "n": 1.5}, "materials[0].strength.n", "allowed [0, 1]"),
    ({**IRON_ZA, "C3": -0.001}, "materials[0].strength.C3", "allowed [0, inf]"),
    ({"type": "zerilli-armstrong-bcc", "C0": 0.0}, "materials[0].strength.C1", "is required"),
    ({"type": "mts", "alpha": 0.0}, "materials[0].strength.alpha", "allowed [0.01, 50]"),
    ({"type": "mts", "p_e": 1.5}, "materials[0].strength.p_e", "allowed (0, 1]"),
    ({"type": "mts", "q_e": 0.5}, "materials[0].strength.q_e", "allowed [1, 2]"),
    ({"type": "mts", "sigma_es0": 0.0}, "materials[0].strength.sigma_es0", "allowed (0, inf]"),
    ({"type": "mts", "D": 60e9}, "materials[0].strength.D", "mu(T)"),
    ({"type": "mts", "sigma_i": 100e6}, "materials[0].strength.g_0i", "is required"),
    ({"type": "mts", "thetaIV": 0.0}, "materials[0].strength.thetaIV", "unknown key"),
]


@pytest.mark.parametrize("strength,path,words", BAD)
def test_bad_strength_constants_name_the_key_and_range(strength, path, words):
    with pytest.raises(DeckError) as e:
        load_text(yaml.safe_dump(deck_with_strength(strength)))
    assert e.value.path == path, str(e.value)
    assert words in str(e.value), str(e.value)


def test_the_kernel_refuses_bad_constants_that_bypass_the_deck():
    """The C models check their constants too (a caller of the C API without
    the front end): MTS with alpha 0 and Zerilli-Armstrong with n 2 stop with
    a PETSc error at material set-up."""
    from petsc4py import PETSc
    from plyshock import _core
    cu = Material("cu", preset="OFHC-copper-MTS").validate("m")
    md = core.material_to_c(cu, "m")
    md["mts"]["alpha"] = 0.0
    with pytest.raises(PETSc.Error):
        _core.drive(md, np.eye(3), np.zeros((1, 3, 3)), 1e-9, 1e-3)
    cz = core.material_to_c(Material("cu", preset="OFHC-copper-ZA").validate("m"), "m")
    cz["za"]["n"] = 2.0
    with pytest.raises(PETSc.Error):
        _core.drive(cz, np.eye(3), np.zeros((1, 3, 3)), 1e-9, 1e-3)
