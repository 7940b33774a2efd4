"""Stiff and extreme cases of issue 15, kept as tests at small size (under
mpiexec -n 2), each against theory or conservation: an elastic precursor's
speed and amplitude, the plane a spall opens on, a 4 km/s tantalum impact and
a 12:1 density contrast (mass exact, energy drift under 2.5%).  A ply a
tenth of a cell thick is covered by test_plies.py's thinner one (1/25 of a
cell; energy drift 0.03%, bound 2.5%)."""
import os

import h5py
import numpy as np
from mpi4py import MPI

from plyshock import Body, Box, Grid, Material, Run, Scene
from plyshock import core

COMM = MPI.COMM_WORLD

# Steinberg's Mie-Grueneisen data (NOTES; UCRL-MA-106439), hydrodynamic unless a strength is given
STEEL = dict(density=7810.0, eos={"type": "mie-gruneisen", "c0": 4578.0, "s": 1.33, "gamma0": 1.67})
CU = dict(density=8930.0, eos={"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02})
TA = dict(density=16690.0, eos={"type": "mie-gruneisen", "c0": 3410.0, "s": 1.20, "gamma0": 1.67})
EPOXY = dict(density=1198.0, eos={"type": "mie-gruneisen", "c0": 2678.0, "s": 1.52, "gamma0": 1.13})   # Epon 828, Kinslow


def strip(length, h, bodies, materials, run, width=3):
    """A uniaxial-strain strip along x (symmetry on the sides), square cells of h."""
    return Scene(2, Grid([0.0, 0.0], [length, width * h], [round(length / h), width],
                         {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}), materials, bodies, run).validate()


def run(scene, outdir):
    m = core.initialize(scene)
    core.run(m, outdir, scene.to_yaml())
    return np.genfromtxt(os.path.join(outdir, "history.csv"), delimiter=",", names=True)


def columns(fn, key="v"):
    """Marker x and the column means of v_x (markers at one x averaged), sorted by x."""
    with h5py.File(fn, "r") as f:
        x, v = f["markers/x"][:, 0], f["markers/v"][:, 0]
    xc, inv = np.unique(np.round(x, 12), return_inverse=True)
    return xc, np.bincount(inv, weights=v) / np.bincount(inv)


def front(xc, vc, level):
    """A right-running front: where the column means, read from the right (the
    material at rest ahead), first reach level (linear between columns)."""
    j = np.flatnonzero(vc >= level)[-1]
    return xc[j] + (vc[j] - level) / (vc[j] - vc[j + 1]) * (xc[j + 1] - xc[j])


def conserved(H, bound):
    """Mass exact (in the grid + booked), every value finite, energy drift under bound; the drift."""
    for k in H.dtype.names:
        assert np.all(np.isfinite(H[k])), k
    assert abs(H["mass"][-1] + H["lost_mass"][-1] - H["mass"][0]) <= 1e-12 * H["mass"][0]
    drift = abs(H["total"][-1] - H["total"][0]) / H["total"][0]
    assert drift < bound, drift
    return drift


def test_elastic_precursor_runs_ahead_at_the_longitudinal_speed_with_the_hugoniot_elastic_limit(tmpdir_mpi):
    """Steel (elastic-plastic, Y = 1 GPa) struck at 400 m/s in uniaxial strain:
    an elastic precursor runs ahead of the plastic shock at c_L =
    sqrt(c0^2 + 4G/(3 rho)) carrying the Hugoniot elastic limit,
    sigma_HEL = (rho c0^2 + 4G/3) Y / (2G), i.e. u_HEL = sigma_HEL/(rho c_L);
    both within 1.2%."""
    G, Y, rho, c0 = 77.5e9, 1.0e9, STEEL["density"], STEEL["eos"]["c0"]
    c_l = np.sqrt(c0 ** 2 + 4 * G / (3 * rho))
    u_hel = (rho * c0 ** 2 + 4 * G / 3) * Y / (2 * G) / (rho * c_l)
    steel = Material("steel", **STEEL, shear_modulus=G, strength={"type": "elastic-plastic", "yield_stress": Y})
    h, t1, t2 = 20e-6, 0.6e-6, 1.2e-6
    bodies = [Body("flyer", box=Box([0.0, 0.0], [0.002, 3 * h]), material="steel", velocity=[400.0, 0.0]),
              Body("target", box=Box([0.002, 0.0], [0.01, 3 * h]), material="steel")]
    H = run(strip(0.01, h, bodies, [steel], Run(t_end=t2, output_interval=t1)), tmpdir_mpi)
    fronts, plateau = [], []
    for k in (1, 2):
        xc, vc = columns(os.path.join(tmpdir_mpi, f"markers_{k:05d}.h5"))
        x_el = front(xc, vc, 0.5 * u_hel)                  # the precursor's front: half its jump
        x_pl = front(xc, vc, 0.5 * (200.0 + u_hel))        # the plastic shock's: half way up from the precursor
        fronts.append(x_el)
        between = (xc > x_pl + 0.2 * (x_el - x_pl)) & (xc < x_el - 0.2 * (x_el - x_pl))
        plateau.append(np.median(vc[between]))
    speed = (fronts[1] - fronts[0]) / (t2 - t1)
    amp = plateau[-1]                                      # the later, longer plateau (the earlier still rings)
    if COMM.rank == 0:
        print(f"\nelastic precursor: speed {speed:.1f} m/s (c_L {c_l:.1f}, {100 * (speed / c_l - 1):+.2f}%), "
              f"u_HEL {amp:.3f} m/s (at t1 {plateau[0]:.3f}) (theory {u_hel:.3f}, {100 * (amp / u_hel - 1):+.2f}%)")
    assert abs(speed - c_l) <= 0.012 * c_l
    assert abs(amp - u_hel) <= 0.012 * u_hel
    conserved(H, 0.025)


def test_spall_opens_where_the_release_waves_meet(tmpdir_mpi):
    """A 0.5 mm copper flyer onto a 1 mm copper plate at 100 m/s, copper
    spalling at -1 GPa: the release from the flyer's back and the one
    reflected from the plate's free face meet (their heads, at the Lagrangian
    sound speed of the shocked state c_L = c0 sqrt((1+s eta)/(1-s eta)^3),
    against the shock's Us) at X = (b - a)(1 + c_L/Us)/2 from the impact
    plane.  The cut of tension opens a zone some 80 um wide (every marker
    stretched past J = 1.05); its centre, weighted by J - 1 and taken at the
    markers' initial places, is within 20 um of X (measured: 10 um at
    10 um cells, 6 um at 5 um)."""
    a, b, v, h = 0.5e-3, 1.0e-3, 100.0, 10e-6
    c0, s = CU["eos"]["c0"], CU["eos"]["s"]
    up = v / 2
    us = c0 + s * up
    eta = up / us
    c_l = c0 * np.sqrt((1 + s * eta) / (1 - s * eta) ** 3)
    X = (b - a) * (1 + c_l / us) / 2
    cu = Material("cu", density=CU["density"], eos=dict(CU["eos"], spall_pressure=-1.0e9))
    x0 = 0.2e-3
    bodies = [Body("flyer", box=Box([x0, 0.0], [x0 + a, 3 * h]), material="cu", velocity=[v, 0.0]),
              Body("plate", box=Box([x0 + a, 0.0], [x0 + a + b, 3 * h]), material="cu")]
    t_end = 0.6e-6                                               # the release heads meet near 0.37 us; the zone opens after
    H = run(strip(2.0e-3, h, bodies, [cu], Run(t_end=t_end, output_interval=t_end)), tmpdir_mpi)
    with h5py.File(os.path.join(tmpdir_mpi, "markers_00000.h5"), "r") as f0, h5py.File(os.path.join(tmpdir_mpi, "markers_00001.h5"), "r") as f1:
        o0, o1 = np.argsort(f0["markers/id"][...]), np.argsort(f1["markers/id"][...])
        x_init = f0["markers/x"][:, 0][o0]
        J = (f1["markers/volume"][...] * cu.density / f1["markers/mass"][...])[o1]
        plate = f1["markers/body"][...][o1] == 1
        assert np.array_equal(f0["markers/id"][...][o0], f1["markers/id"][...][o1])
    opened = plate & (J > 1.05)
    assert opened.sum() >= 3 and J.max() > 1.2                    # a zone opened
    x_spall = np.sum((J[opened] - 1) * x_init[opened]) / np.sum(J[opened] - 1) - (x0 + a)
    if COMM.rank == 0:
        print(f"\nspall: the plate opens {1e6 * x_spall:.1f} um from the impact plane (zone "
              f"{1e6 * (x_init[opened].min() - x0 - a):.0f} to {1e6 * (x_init[opened].max() - x0 - a):.0f} um, J up to {J.max():.2f}); "
              f"the release heads meet at {1e6 * X:.1f} um (acoustic: {1e6 * (b - a):.0f} um)")
    assert abs(x_spall - X) <= 20e-6 and abs(x_init[opened].mean() - x0 - a - X) < 60e-6
    conserved(H, 0.025)


def test_tantalum_impact_at_4_km_per_s(tmpdir_mpi):
    """A 1 mm tantalum flyer onto a tantalum plate at 4 km/s (about 190 GPa):
    runs without NaN or inverted markers, mass exact, energy drift under 3.5%
    at cfl 0.1.  The drift is the time step's (first order: 6.1% at cfl 0.4,
    3.3% at 0.2, 1.7% at 0.1 measured bonded; the shape functions do not change
    it; bonded now -1.24%) and the contact's between flyer and plate, an
    inelastic loss of first order in h (in contact -2.54%; docs/contact.md)."""
    h = 25e-6
    ta = Material("ta", **TA)
    bodies = [Body("flyer", box=Box([0.001, 0.0], [0.002, 3 * h]), material="ta", velocity=[4000.0, 0.0]),
              Body("plate", box=Box([0.002, 0.0], [0.004, 3 * h]), material="ta")]
    H = run(strip(0.006, h, bodies, [ta], Run(t_end=0.6e-6, cfl=0.1, history_interval=50)), tmpdir_mpi)
    assert H["max_pressure"].max() > 1.5e11
    drift = conserved(H, 0.035)
    if COMM.rank == 0:
        print(f"\ntantalum at 4 km/s: peak {H['max_pressure'].max() / 1e9:.0f} GPa, {int(H['step'][-1])} steps, "
              f"energy drift {100 * drift:.2f}%")


def test_a_12_to_1_density_contrast(tmpdir_mpi):
    """A tantalum flyer (16690 kg/m^3) through epoxy (1198 kg/m^3, 13.9:1)
    at 1 km/s onto a tantalum backing: mass exact, energy drift under 3.5% at
    cfl 0.1 (5.9% at 0.4, 3.4% at 0.2, 1.8% at 0.1: the time step's, measured
    bonded; the bodies in contact 2.09%: contact's inelastic loss added)."""
    h = 25e-6
    mats = [Material("ta", **TA), Material("epoxy", **EPOXY)]
    bodies = [Body("flyer", box=Box([0.0005, 0.0], [0.0015, 3 * h]), material="ta", velocity=[1000.0, 0.0]),
              Body("epoxy", box=Box([0.0015, 0.0], [0.003, 3 * h]), material="epoxy"),
              Body("backing", box=Box([0.003, 0.0], [0.004, 3 * h]), material="ta")]
    H = run(strip(0.005, h, bodies, mats, Run(t_end=1.0e-6, cfl=0.1, history_interval=50)), tmpdir_mpi)
    drift = conserved(H, 0.035)
    if COMM.rank == 0:
        print(f"\n13.9:1 density contrast: {int(H['step'][-1])} steps, energy drift {100 * drift:.2f}%")
