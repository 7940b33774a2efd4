"""The explicit MPM solver under mpiexec -n 2: conservation, analytic shock and
wave answers, Sulsky's disks, rank independence, stiff and extreme cases."""
import os

import h5py
import numpy as np
import pytest
import yaml
from mpi4py import MPI

from plyshock import Body, Box, Contact, DeckError, Grid, Material, Run, Scene, Sphere
from plyshock import core
from conftest import energy_and_work_per_step, run_cli
from helpers import gather

COMM = MPI.COMM_WORLD
CU = Material("cu", density=8930.0, eos={"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02})


def strip(length, width_cells, h, bodies, materials, run, dim=2, contact=None):
    """A uniaxial-strain strip along x: symmetry on the sides."""
    cells = [round(length / h), width_cells]
    return Scene(dim, Grid([0.0, 0.0], [length, width_cells * h], cells,
                           {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}), materials, bodies, run,
                 contact=contact).validate()


def history(outdir):
    return np.genfromtxt(os.path.join(outdir, "history.csv"), delimiter=",", names=True)


def front_speed(outdir, x0):
    """Speed of the right-running front of a 1 m/s velocity step (outputs 1 and
    2, 0.75 us apart): where v first falls below half the 0.5 m/s jump beyond x0."""
    fronts = []
    for k in (1, 2):
        with h5py.File(os.path.join(outdir, f"markers_{k:05d}.h5"), "r") as f:
            x, v = f["markers/x"][:, 0], f["markers/v"][:, 0]
        o = np.argsort(x)
        right = np.flatnonzero((x[o] > x0) & (v[o] < 0.25))
        fronts.append(x[o][right[0]])
    return (fronts[1] - fronts[0]) / 0.75e-6


def run_scene(scene, outdir):
    m = core.initialize(scene)
    core.run(m, outdir, scene.to_yaml())
    return m


@pytest.mark.parametrize("transfer,shape", [("musl", "gimp"), ("apic", "bspline2")])
def test_copper_plate_impact_matches_the_hugoniot(transfer, shape, tmpdir_mpi):
    """Cu onto Cu at 500 m/s: u_p 250 m/s, p 9.63 GPa, Us 4312 m/s (impedance match),
    with either transfer scheme: musl with flyer and target in contact (the
    default; measured 250.4 m/s, 9.636 GPa at 1 us), apic bonded (contact is
    MUSL only; docs/contact.md)."""
    h = 50e-6
    W = 4 * h
    run = Run(t_end=1.0e-6, output_interval=0.5e-6, shape=shape, transfer=transfer)
    scene = strip(0.02, 4, h, [Body("flyer", box=Box([0.002, 0.0], [0.007, W]), material="cu", velocity=[500.0, 0.0], subdivision=2),
                               Body("target", box=Box([0.007, 0.0], [0.017, W]), material="cu", subdivision=2)], [CU], run,
                  contact=None if transfer == "musl" else Contact(type="bonded"))
    run_scene(scene, tmpdir_mpi)
    fronts = []
    for k, t in ((1, 0.5e-6), (2, 1.0e-6)):
        with h5py.File(os.path.join(tmpdir_mpi, f"markers_{k:05d}.h5"), "r") as f:
            assert np.isclose(f.attrs["time"], t, rtol=1e-12)
            x, v, p = f["markers/x"][:, 0], f["markers/v"][:, 0], f["markers/pressure"][...]
            assert f["markers/stress"].shape == (len(x), 3, 3)
        # the shocked plateau lies between the two shock fronts, away from them by 4 cells
        xl, xr = 0.007 - (4312 - 500) * t + 4 * h + 500 * 0, 0.007 + 4312 * t - 4 * h
        sel = (x > xl + 250 * t) & (x < xr)
        up, pp = np.median(v[sel]), np.median(p[sel])
        assert abs(up - 250.0) <= 0.02 * 250.0, up
        assert abs(pp - 9.63e9) <= 0.02 * 9.63e9, pp
        # half-pressure point of the front running into the target
        o = np.argsort(x)
        xs, ps = x[o], p[o]
        ahead = np.flatnonzero((xs > 0.007 + 250 * t) & (ps < 0.5 * 9.63e9))
        fronts.append(xs[ahead[0]])
    Us = (fronts[1] - fronts[0]) / 0.5e-6 + 0.0
    assert abs(Us - 4312.0) <= 0.02 * 4312.0, Us
    # conservation: mass exactly, momentum to round-off, energy drift small
    H = history(tmpdir_mpi)
    assert np.all(H["mass"] == H["mass"][0]) and np.all(H["lost_mass"] == 0)
    assert np.max(np.abs(H["px"] - H["px"][0])) <= 1e-12 * H["px"][0]
    drift = abs(H["total"][-1] - H["total"][0]) / H["total"][0]
    assert drift < 0.01, drift


@pytest.mark.parametrize("transfer", ["musl", "apic"])
def test_elastic_wave_speed_in_uniaxial_strain(transfer, tmpdir_mpi):
    """A velocity step in an elastic strip: fronts at sqrt((lambda + 2 mu)/rho).
    The two halves are bonded: the step runs across a welded interface (and
    contact is MUSL only)."""
    E, nu, rho = 200e9, 0.3, 7800.0
    c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    h = 50e-6
    steel = Material("el", density=rho, elastic={"type": "isotropic", "E": E, "nu": nu})
    run = Run(t_end=1.5e-6, output_interval=0.75e-6, shape="bspline2", transfer=transfer,
              artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0})
    scene = strip(0.02, 3, h, [Body("left", box=Box([0.0, 0.0], [0.01, 3 * h]), material="el", velocity=[1.0, 0.0]),
                               Body("right", box=Box([0.01, 0.0], [0.02, 3 * h]), material="el")], [steel], run,
                  contact=Contact(type="bonded"))
    run_scene(scene, tmpdir_mpi)
    speed = front_speed(tmpdir_mpi, 0.0101)
    assert abs(speed - c) <= 0.02 * c, (speed, c)


def test_sulsky_disks_bounce_and_report_energy_loss(tmpdir_mpi):
    """Two elastic disks (Sulsky et al. 1994): they collide and bounce apart.
    Stated bound: MUSL with FLIP (the default) at 40 x 40 cells loses under 5% of the energy
    (measured: about 1%; a PIC share dissipates more, 8% at pic_fraction 0.05).
    In one velocity field (contact bonded): this measures the transfers; the
    disks in contact (the default) are tests/test_contact.py's."""
    mat = Material("el", density=1000.0, elastic={"type": "isotropic", "E": 1000.0, "nu": 0.3})
    run = Run(t_end=3.5, cfl=0.4, shape="gimp", history_interval=5, artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0})
    scene = Scene(2, Grid([0, 0], [1, 1], [40, 40]), [mat],
                  [Body("d1", sphere=Sphere([0.2, 0.2], 0.2), material="el", velocity=[0.1, 0.1], subdivision=2),
                   Body("d2", sphere=Sphere([0.8, 0.8], 0.2), material="el", velocity=[-0.1, -0.1], subdivision=2)], run,
                  contact=Contact(type="bonded")).validate()
    run_scene(scene, tmpdir_mpi)
    H = history(tmpdir_mpi)
    E0 = H["total"][0]
    assert abs(E0 - 2 * 0.5 * 1000 * np.pi * 0.04 * 0.02) <= 1e-5 * E0      # 2.513 J/m from the exact disks
    B = np.genfromtxt(os.path.join(tmpdir_mpi, "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
    d1 = B[B["body"] == "d1"]
    assert d1["vx"][0] > 0.09 and d1["vx"][-1] < -0.02          # bounced back
    loss = 1 - H["total"][-1] / E0
    if COMM.rank == 0:
        print(f"\nSulsky disks: energy lost to the transfers {100 * loss:.2f}% (bound 5%)")
    assert -0.01 < loss < 0.05


def test_3d_elastic_wave_and_conservation_under_each_transfer(tmpdir_mpi):
    """The 3D kernels (apic's 4-wide P2G/G2P, musl's): a velocity step in a
    uniaxial-strain bar (symmetry on the four sides) runs at
    sqrt((lambda + 2 mu)/rho) within 2%; mass exact, momentum to round-off.
    The halves bonded (a welded interface; contact is MUSL only)."""
    E, nu, rho = 200e9, 0.3, 7800.0
    c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    h = 100e-6
    steel = Material("el", density=rho, elastic={"type": "isotropic", "E": E, "nu": nu})
    bc = {"y-": "symmetry", "y+": "symmetry", "z-": "symmetry", "z+": "symmetry"}
    for transfer in ("musl", "apic"):
        run = Run(t_end=1.5e-6, output_interval=0.75e-6, shape="bspline2", transfer=transfer, history_interval=5,
                  artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0})
        scene = Scene(3, Grid([0, 0, 0], [0.02, 3 * h, 3 * h], [200, 3, 3], bc), [steel],
                      [Body("left", box=Box([0.0, 0, 0], [0.01, 3 * h, 3 * h]), material="el", velocity=[1.0, 0.0, 0.0]),
                       Body("right", box=Box([0.01, 0, 0], [0.02, 3 * h, 3 * h]), material="el")], run,
                      contact=Contact(type="bonded")).validate()
        out = os.path.join(tmpdir_mpi, transfer)
        run_scene(scene, out)
        speed = front_speed(out, 0.0102)
        assert abs(speed - c) <= 0.02 * c, (transfer, speed, c)
        H = history(out)
        assert np.all(H["mass"] == H["mass"][0])
        assert np.max(np.abs(H["px"] - H["px"][0])) <= 1e-12 * H["px"][0], transfer
        assert np.max(np.abs(H["py"])) + np.max(np.abs(H["pz"])) <= 1e-12 * H["px"][0], transfer


@pytest.mark.parametrize("dim", [2, 3])
def test_gimp_support_keeps_momentum_and_rigid_translation_strain_free(dim, tmpdir_mpi):
    """MUSL/GIMP visits per marker and direction only the nodes that carry
    weight (2 while the particle lies inside one cell, 3 where it straddles a
    node; PSShapeSupport in src/shape.h).  Two blocks of 2^dim markers per cell
    (l = h/4: half the markers' positions straddle) fly obliquely across
    several cells, one translating rigidly, the other striking a third at
    rest: every node that carries weight must be visited in P2G, G2P and the
    gradient.  Momentum to round-off (a node missed in P2G or G2P breaks
    sum_i grad N_ip = 0 or m_i = sum_p N_ip m_p); the rigidly moving block
    stays strain-free (a node missed in the gradient gives L_p != 0 under a
    uniform velocity): its stress under 1e-9 of the impact's rho c u.
    run.mass_threshold 0: the default drops the force on the lightest nodes
    (GIMP's far corners), 1e-9 of the momentum here."""
    E, nu, rho = 1e9, 0.3, 1000.0
    c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    h, u = 1e-3, 20.0
    el = Material("el", density=rho, elastic={"type": "isotropic", "E": E, "nu": nu})
    n = 24 if dim == 2 else 18
    lo, hi = [0.0] * dim, [n * h] * dim
    def box(a, b):
        return Box([a[0] * h, a[1] * h] + ([a[2] * h] if dim == 3 else []), [b[0] * h, b[1] * h] + ([b[2] * h] if dim == 3 else []))
    vel = [u, 0.6 * u, -0.35 * u][:dim]
    bodies = [Body("rigid", box=box([2, 9, 8], [6, 13, 12]), material="el", velocity=vel, subdivision=2),
              Body("flyer", box=box([2, 2, 2], [6, 6, 6]), material="el", velocity=[u, 0.6 * u, 0.35 * u][:dim], subdivision=2),
              Body("target", box=box([7, 2, 2], [10, 7, 7]), material="el", subdivision=2)]
    t_end = 3.0 * h / u                                  # the blocks travel 3 cells
    run = Run(t_end=t_end, cfl=0.5, shape="gimp", transfer="musl", history_interval=5, output_interval=t_end, mass_threshold=0.0,
              artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0})
    scene = Scene(dim, Grid(lo, hi, [n] * dim), [el], bodies, run, contact=Contact(type="bonded")).validate()
    m = run_scene(scene, tmpdir_mpi)
    H = history(tmpdir_mpi)
    p0 = rho * (4 * h) ** dim * u                        # one block's momentum, the scale of the round-off
    assert np.all(H["mass"] == H["mass"][0])
    for comp in "xyz"[:dim]:
        assert np.max(np.abs(H["p" + comp] - H["p" + comp][0])) < 1e-12 * p0, (comp, H["p" + comp])
    f = gather(m, ["body", "stress", "v"])
    rigid = f["body"][:, 0] == 0
    assert np.count_nonzero(rigid) == 2 ** dim * 4 ** dim
    assert np.max(np.abs(f["stress"][rigid])) < 1e-9 * rho * c * u, np.max(np.abs(f["stress"][rigid]))
    assert np.max(np.abs(f["v"][rigid] - vel)) < 1e-9 * u
    target = f["body"][:, 0] == 2
    assert np.max(np.abs(f["stress"][target])) > 1e-3 * rho * c * u   # the strike did load the target


def test_apic_dissipates_between_flip_and_pic_and_conserves_momentum(tmpdir_mpi):
    """Sulsky's disks with bspline2 under each transfer.  Stated bounds: MUSL-FLIP
    loses under 5%, APIC (run.transfer apic) under 20% (measured 13%: APIC drops
    the non-affine part of each marker's velocity field), pure PIC (musl with
    pic_fraction 1) more than twice APIC's loss (measured 43%).  Every transfer
    keeps mass exact and momentum to round-off (the disks' momenta cancel).
    One velocity field (contact bonded): this compares the transfers."""
    mat = Material("el", density=1000.0, elastic={"type": "isotropic", "E": 1000.0, "nu": 0.3})
    loss = {}
    for name, transfer, pic in (("flip", "musl", 0.0), ("apic", "apic", 0.0), ("pic", "musl", 1.0)):
        run = Run(t_end=3.5, cfl=0.4, shape="bspline2", transfer=transfer, pic_fraction=pic, history_interval=5,
                  artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0})
        scene = Scene(2, Grid([0, 0], [1, 1], [40, 40]), [mat],
                      [Body("d1", sphere=Sphere([0.2, 0.2], 0.2), material="el", velocity=[0.1, 0.1], subdivision=2),
                       Body("d2", sphere=Sphere([0.8, 0.8], 0.2), material="el", velocity=[-0.1, -0.1], subdivision=2)], run,
                      contact=Contact(type="bonded")).validate()
        out = os.path.join(tmpdir_mpi, name)
        run_scene(scene, out)
        H = history(out)
        assert np.all(H["mass"] == H["mass"][0])
        p0 = 1000 * np.pi * 0.04 * 0.1                     # one disk's momentum, the scale of the round-off
        assert np.max(np.abs(H["px"])) < 1e-12 * p0 and np.max(np.abs(H["py"])) < 1e-12 * p0
        B = np.genfromtxt(os.path.join(out, "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
        assert B[B["body"] == "d1"]["vx"][-1] < -0.05       # bounced back
        loss[name] = 1 - H["total"][-1] / H["total"][0]
    if COMM.rank == 0:
        print("\nSulsky disks, energy lost: " + ", ".join(f"{k} {100 * v:.1f}%" for k, v in loss.items()))
    assert 0 <= loss["flip"] < 0.05 and loss["flip"] < loss["apic"] < 0.20 and loss["pic"] > 2 * loss["apic"]


def _write_deck(path, d):
    if COMM.rank == 0:
        with open(path, "w") as f:
            f.write("# plyshock test deck; SI units\n" + yaml.safe_dump(d))
    COMM.Barrier()


PLATE = {
    "dimension": 2,
    "grid": {"lower": [0, 0], "upper": [0.01, 0.0003], "cells": [100, 3], "boundary": {"y-": "symmetry", "y+": "symmetry"}},
    "materials": [{"name": "steel", "preset": "4340-steel"}, {"name": "cu", "preset": "OFHC-copper"}],
    "bodies": [{"name": "flyer", "material": "steel", "box": {"lower": [0.001, 0], "upper": [0.003, 0.0003]}, "velocity": [800, 0]},
               {"name": "target", "material": "cu", "box": {"lower": [0.003, 0], "upper": [0.008, 0.0003]}}],
    "run": {"t_end": 2.0e-6, "output_interval": 1.0e-6, "history_interval": 5},
    "gauges": [{"name": "flyer", "point": [0.002, 0.00015]}, {"name": "target", "point": [0.0035, 0.00015]}],
}


APIC = ["-run_transfer", "apic", "-run_shape", "bspline2"]
# the plate deck's bodies as hydrodynamic Mie-Grueneisen steel and copper
HYDRO = [{"name": "steel", "density": 7850.0, "eos": {"type": "mie-gruneisen", "c0": 4570.0, "s": 1.49, "gamma0": 1.93}},
         {"name": "cu", "density": 8930.0, "eos": {"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02}}]


def test_one_and_two_ranks_give_the_same_history(tmpdir_mpi):
    deck = os.path.join(tmpdir_mpi, "plate.yaml")
    _write_deck(deck, PLATE)
    hs = []
    for k in (1, 2):
        out = os.path.join(tmpdir_mpi, f"o{k}")
        rc, so, se = run_cli(["run", deck, "-o", out, "-run_t_end", "1.5e-6"], ranks=k)
        assert rc == 0, se
        hs.append(history(out))
    a, b = hs
    assert abs(a["time"][-1] - 1.5e-6) < 1e-15       # -run_t_end overrides the deck
    for k in a.dtype.names:
        # momentum components on the scale of the momentum (py is round-off noise around 0)
        scale = np.abs(a["px"]).max() if k in ("px", "py") else np.abs(a[k]).max() + 1e-300
        assert np.max(np.abs(a[k] - b[k])) <= 1e-10 * scale, k
    # gauges follow the same markers on any rank count and record the shock arriving
    g1, g2 = (np.genfromtxt(os.path.join(tmpdir_mpi, f"o{k}", "gauges.csv"), delimiter=",", names=True) for k in (1, 2))
    assert np.array_equal(g1["id"], g2["id"]) and np.all(g1["present"] == 1)
    # on the scale of the velocities (800 m/s): a gauge at rest may differ by round-off of that scale
    assert np.max(np.abs(g1["vx"] - g2["vx"])) <= 1e-10 * np.abs(g1["vx"]).max()
    tgt = g2[g2["gauge"] == 1]
    assert tgt["vx"][0] == 0.0 and tgt["vx"].max() > 300.0 and tgt["pressure"].max() > 5e9
    # Johnson-Cook materials write plastic strain and temperature; the series opens in ParaView
    with h5py.File(os.path.join(tmpdir_mpi, "o2", "markers_00001.h5"), "r") as f:
        assert "plastic_strain" in f["markers"] and "temperature" in f["markers"]
        assert f["markers/temperature"][...].min() >= 294.0 - 1e-9
    assert os.path.exists(os.path.join(tmpdir_mpi, "o2", "markers.xdmf"))
    with h5py.File(os.path.join(tmpdir_mpi, "o2", "grid_00001.h5"), "r") as f:
        assert f["grid/mass"].shape == (3 + 3, 100 + 3)        # nodes with one pad layer on each side
        assert np.isclose(f["grid/mass"][...].sum(), 7810 * 0.002 * 0.0003 + 8930 * 0.005 * 0.0003, rtol=1e-12)


def test_apic_one_and_two_ranks_give_the_same_history(tmpdir_mpi):
    """run.transfer apic on 1 and 2 ranks, the plate deck with hydrodynamic and
    with elastic materials: the same history to 1e-10.  (With Johnson-Cook
    plasticity APIC's histories part at ~1e-6 after a few hundred steps: the
    ghost sums' round-off is amplified where markers sit at yield; MUSL's stay
    within 1e-10, test above.)"""
    mats = {"hydro": HYDRO,
            "elastic": [{"name": "steel", "density": 7850.0, "elastic": {"type": "isotropic", "E": 200e9, "nu": 0.29}},
                        {"name": "cu", "density": 8930.0, "elastic": {"type": "isotropic", "E": 124e9, "nu": 0.34}}]}
    for kind, m in mats.items():
        deck = os.path.join(tmpdir_mpi, f"{kind}.yaml")
        _write_deck(deck, dict(PLATE, materials=m, contact={"type": "bonded"}))     # contact is MUSL only
        hs = []
        for k in (1, 2):
            out = os.path.join(tmpdir_mpi, f"{kind}{k}")
            rc, so, se = run_cli(["run", deck, "-o", out, "-run_t_end", "1.5e-6"] + APIC, ranks=k)
            assert rc == 0, se
            hs.append(history(out))
        a, b = hs
        assert a["step"][-1] > 100 and a["max_pressure"].max() > 5e9      # the shock ran
        for n in ("time", "dt", "mass", "px", "kinetic", "internal", "total", "max_pressure"):
            scale = np.abs(a["px"]).max() if n == "px" else np.abs(a[n]).max()
            assert np.max(np.abs(a[n] - b[n])) <= 1e-10 * scale, (kind, n)


def test_four_ranks_in_a_2x2_grid_match_one_rank(tmpdir_mpi):
    """The ghost exchange (halo.c) with ranks on both sides of a node, corners
    included: Sulsky's disks split 2 x 2 cross every cut; 1 and 4 ranks give the
    same history to 1e-10 under both transfers (musl with the disks in contact,
    the default: the fields' ghost exchange too; apic bonded, contact is MUSL only)."""
    deck = os.path.join(tmpdir_mpi, "disks.yaml")
    disks = {
        "dimension": 2, "grid": {"lower": [0, 0], "upper": [1, 1], "cells": [40, 40]},
        "materials": [{"name": "el", "density": 1000.0, "elastic": {"type": "isotropic", "E": 1000.0, "nu": 0.3}}],
        "bodies": [{"name": "d1", "material": "el", "sphere": {"center": [0.2, 0.2], "radius": 0.2}, "velocity": [0.1, 0.1]},
                   {"name": "d2", "material": "el", "sphere": {"center": [0.8, 0.8], "radius": 0.2}, "velocity": [-0.1, -0.1]}],
        "run": {"t_end": 3.0, "shape": "bspline2", "history_interval": 10}}
    for transfer in ("musl", "apic"):
        _write_deck(deck, disks if transfer == "musl" else dict(disks, contact={"type": "bonded"}))
        hs = []
        for k in (1, 4):
            out = os.path.join(tmpdir_mpi, f"{transfer}{k}")
            rc, so, se = run_cli(["run", deck, "-o", out, "-run_transfer", transfer], ranks=k)
            assert rc == 0, se
            hs.append(history(out))
        a, b = hs
        assert len(a) == len(b) and a["step"][-1] > 300
        for n in ("time", "mass", "kinetic", "internal", "total"):
            assert np.max(np.abs(a[n] - b[n])) <= 1e-10 * np.abs(a[n]).max(), (transfer, n)
        # both zero: round-off on one disk's momentum in one field (apic, bonded); the disks in
        # contact (musl) drift to 9.4e-5 of it after their rebound (measured): the force dropped
        # on nodes lighter than run.mass_threshold no longer cancels between the disks once the
        # contact's tie rule has broken their mirror symmetry (docs/contact.md), so bound 2e-4
        bound = 2e-4 if transfer == "musl" else 1e-12
        for n in ("px", "py"):
            assert np.max(np.abs(b[n])) <= bound * 1000 * np.pi * 0.04 * 0.1, (transfer, n)


@pytest.mark.parametrize("case", ["steel-on-aluminium-5km/s", "stiff-bonded-to-soft"])
def test_stiff_and_extreme_cases_run_10000_steps(case, tmpdir_mpi):
    if case.startswith("steel"):
        mats = [Material("steel", preset="4340-steel"), Material("al", preset="6061-T6-aluminum")]
        bodies = [Body("flyer", box=Box([0.003, 0], [0.005, 2e-4]), material="steel", velocity=[5000.0, 0.0]),
                  Body("plate", box=Box([0.005, 0], [0.015, 2e-4]), material="al")]
    else:
        mats = [Material("stiff", density=1850.0, elastic={"type": "isotropic", "E": 300e9, "nu": 0.2}),
                Material("soft", density=1200.0, elastic={"type": "isotropic", "E": 1e9, "nu": 0.3})]
        bodies = [Body("stiff", box=Box([0.004, 0], [0.01, 2e-4]), material="stiff", velocity=[200.0, 0.0]),
                  Body("soft", box=Box([0.01, 0], [0.02, 2e-4]), material="soft")]
    # case (a) at cfl 0.2: the energy error of a 5 km/s impact is a time-step error
    # (measured 6.9% lost at cfl 0.4, 5.4% at 0.3, 3.8% at 0.2)
    cfl = 0.2 if case.startswith("steel") else 0.4
    scene = strip(0.03, 4, 50e-6, bodies, mats, Run(t_end=1.0, cfl=cfl, max_steps=10000, history_interval=250))
    m = run_scene(scene, tmpdir_mpi)
    H = history(tmpdir_mpi)
    assert H["step"][-1] == 10000
    for k in H.dtype.names:
        assert np.all(np.isfinite(H[k])), k
    f = core.local_fields(m, ["volume", "x", "v"])
    assert np.all(f["volume"] > 0) and np.all(np.isfinite(f["x"])) and np.all(np.isfinite(f["v"]))
    # nothing lost unaccounted: mass in the domain + booked removals = initial mass
    assert abs(H["mass"][-1] + H["lost_mass"][-1] - H["mass"][0]) <= 1e-12 * H["mass"][0]
    drift = abs(H["total"][-1] - H["total"][0]) / H["total"][0]
    if COMM.rank == 0:
        print(f"\n{case}: 10000 steps to t = {H['time'][-1]:.3e} s, energy drift {100 * drift:.2f}%")
    assert drift < 0.05, drift


def test_run_input_errors():
    # a material with neither an EOS nor elasticity cannot run
    scene = Scene(2, Grid([0, 0], [1, 1], [4, 4]), [Material("c", density=1000.0)],
                  [Body("b", box=Box([0.1, 0.1], [0.5, 0.5]), material="c")], Run(t_end=1e-6)).validate()
    m = core.initialize(scene)
    with pytest.raises(DeckError) as e:
        core.make_solver(m)
    assert e.value.path == "materials[0]"
    # the deck's structure is checked by Run.validate ...
    with pytest.raises(DeckError) as e:
        Run(t_end=1.0, shape="cubic").validate()
    assert e.value.path == "run.shape"
    with pytest.raises(DeckError) as e:
        Run(t_end=1.0, fbar="yes").validate()
    assert e.value.path == "run.fbar"
    with pytest.raises(DeckError) as e:
        Run(t_end=1.0, transfer="flip").validate()
    assert e.value.path == "run.transfer" and "musl|apic" in str(e.value)
    with pytest.raises(DeckError) as e:
        Run(t_end="soon").validate()
    assert e.value.path == "run.t_end"
    # ... the values' ranges and combinations in one place, C's PSRunParamsCheck
    cases = [(dict(t_end=-1.0), "run.t_end", "allowed (0, inf)"),
             (dict(cfl=1.5), "run.cfl", "allowed (0, 1]"),
             (dict(artificial_viscosity={"c_linear": -1}), "run.artificial_viscosity.c_linear", "allowed [0, 100]"),
             (dict(transfer="apic", shape="gimp"), "run.transfer", "bspline2"),       # MLS-MPM's D_p = h^2/4 I
             (dict(transfer="apic", shape="bspline2", pic_fraction=0.1), "run.pic_fraction", "musl only"),
             (dict(dt_growth=0.5), "run.dt_growth", "allowed [1, 10]")]
    for kw, path, words in cases:
        scene.run = Run(**{"t_end": 1e-6, **kw}).validate()
        with pytest.raises(DeckError) as e:
            core.run_options(scene)
        assert e.value.path == path and words in str(e.value), (kw, str(e.value))


def test_run_option_errors_from_the_command_line(tmpdir_mpi):
    """A -run_<key> option is checked like the deck's value it overrides, before
    any work: exit 2, the key named, no traceback."""
    deck = os.path.join(tmpdir_mpi, "d.yaml")
    if COMM.rank == 0:
        with open(deck, "w") as f:
            yaml.safe_dump({"dimension": 2, "grid": {"lower": [0, 0], "upper": [1e-3, 1e-3], "cells": [4, 4]},
                            "materials": [{"name": "cu", "density": 8930.0,
                                           "eos": {"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02}}],
                            "bodies": [{"name": "b", "box": {"lower": [0, 0], "upper": [5e-4, 5e-4]}, "material": "cu"}],
                            "run": {"t_end": 1e-7}}, f)
    for opt, val, words in [("-run_cfl", "5", "run.cfl: 5 is out of range; allowed (0, 1]"),
                            ("-run_transfer", "apic", "run.transfer: apic (MLS-MPM"),
                            ("-run_shape", "cubic", "-run_shape: must be one of linear|gimp|bspline2")]:
        code, out, err = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "o"), opt, val])
        assert code == 2 and words in err and "Traceback" not in err, (opt, code, err)
        assert not os.path.exists(os.path.join(tmpdir_mpi, "o", "history.csv"))


def test_verify_measures_errors_and_plots(tmpdir_mpi):
    """`plyshock verify`'s measurement: exact-profile errors of one coarse run
    per problem, and the work-precision picture and run plots it draws."""
    from plyshock.verify import plot, run_one
    rows = []
    for problem in ("plate", "wave"):
        for h in (100e-6, 50e-6):
            l1, plat, wall, n, steps = run_one(problem, h, "bspline2")
            assert plat < 0.01 and l1 < 0.12 and steps > 0
            rows.append(dict(problem=problem, shape="bspline2", h=h, markers=n, steps=steps, wall_s=wall, L1=l1, plateau=plat))
    # finer is better for both problems at these sizes
    assert rows[1]["L1"] < rows[0]["L1"] and rows[3]["L1"] < rows[2]["L1"]
    if COMM.rank == 0:
        orders = plot(rows, os.path.join(tmpdir_mpi, "v.png"))
        assert os.path.getsize(os.path.join(tmpdir_mpi, "v.png")) > 10000 and all(o[0] > 0 for o in orders.values())
    COMM.Barrier()
    # a run's history and a step coloured by a field
    scene = strip(0.01, 2, 100e-6, [Body("b", box=Box([0.002, 0], [0.006, 2e-4]), material="cu", velocity=[300.0, 0])],
                  [CU], Run(t_end=2e-7))
    out = os.path.join(tmpdir_mpi, "run")
    run_scene(scene, out)
    if COMM.rank == 0:
        from plyshock.post import plot_field, plot_history
        assert os.path.getsize(plot_history(out, os.path.join(out, "h.png"))) > 10000
        assert os.path.getsize(plot_field(os.path.join(out, "markers_00001.h5"), os.path.join(out, "p.png"), "pressure", window=(400, 300))) > 1000
    COMM.Barrier()


@pytest.mark.parametrize("transfer", ["musl", "apic"])
def test_restart_continues_bitwise_and_on_another_rank_count(transfer, tmpdir_mpi):
    """musl: the Johnson-Cook plate deck; apic: its hydrodynamic variant (see
    test_apic_one_and_two_ranks_give_the_same_history)."""
    deck = os.path.join(tmpdir_mpi, "plate.yaml")
    _write_deck(deck, PLATE if transfer == "musl" else dict(PLATE, materials=HYDRO, contact={"type": "bonded"}))  # contact is MUSL only
    opts = APIC if transfer == "apic" else []
    full, half = os.path.join(tmpdir_mpi, "full"), os.path.join(tmpdir_mpi, "half")
    for args in (["-o", full], ["-o", half, "-run_t_end", "1e-6"]):
        rc, so, se = run_cli(["run", deck] + args + opts, ranks=2)
        assert rc == 0, se
    outs = {}
    for k in (2, 3):
        out = os.path.join(tmpdir_mpi, f"restart{k}")
        rc, so, se = run_cli(["run", deck, "-o", out, "--restart", os.path.join(half, "checkpoint.h5")] + opts, ranks=k)
        assert rc == 0, se
        outs[k] = out

    def state(d):
        with h5py.File(os.path.join(d, "checkpoint.h5"), "r") as f:
            g = f["checkpoint"]
            o = np.argsort(g["id"][:, 0])
            return {k: g[k][...] for k in g if k not in ("ranks", "state")}, o, g["state"][...]
    ref, _, sref = state(full)
    assert ("affine" in ref) == (transfer == "apic")      # APIC's C_p is part of the state
    same, _, s2 = state(outs[2])
    assert np.array_equal(sref, s2)                     # time, dt, step
    for k in ref:                                       # same rank count: bitwise, same order
        assert np.array_equal(ref[k], same[k]), k
    r, o_r, _ = state(full)
    x3, o3, s3 = state(outs[3])
    assert s3[0] == sref[0] and s3[3] == sref[3]
    for k in ("x", "v", "mass", "pressure", "energy"):  # another rank count: the same run to round-off
        a, b = r[k][o_r], x3[k][o3]
        assert np.allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(a).max()), k


def test_fbar_relieves_volumetric_locking_in_the_taylor_bar():
    """The copper Taylor bar at 1 mm cells: plastic flow is isochoric and locks
    GIMP markers, so the foot spreads too little (11.7 mm against the measured
    13.56 mm); the cell-averaged volumetric rate (run.fbar) widens it by more
    than 5% toward the measurement (12.6 mm; 13.53 mm at 0.5 mm)."""
    from plyshock.verify import TAYLOR, taylor
    plain, fbar = taylor(1e-3, fbar=False), taylor(1e-3, fbar=True)
    assert fbar["diameter"] > 1.05 * plain["diameter"], (plain["diameter"], fbar["diameter"])
    assert abs(fbar["diameter"] - TAYLOR["D"]) < abs(plain["diameter"] - TAYLOR["D"])
    assert plain["markers"] == fbar["markers"]


@pytest.mark.parametrize("rate", [1.0e3, 1.0e5])
def test_johnson_cook_kernel_follows_the_adiabatic_flow_curve(rate):
    """Isochoric uniaxial compression of one OFHC copper marker at a constant
    rate (1/s) to a true strain of 1, through the solver's own kernel: the von
    Mises stress follows the Johnson-Cook curve (A + B eps_p^n)(1 + C ln rate)
    (1 - T*^m) with eps_p = eps - sigma/(3G) and the adiabatic temperature
    T = T_room + 0.9 int sigma d eps_p / (rho c_v), integrated here
    to 1e-5; the kernel (explicit in eps_p and T, 20,000 steps) agrees to 0.1%."""
    if COMM.rank:
        return
    cu = Material("cu", preset="OFHC-copper").validate("m")
    n, dt = 20000, 1.0 / (20000 * rate)
    L = np.zeros((n, 3, 3))
    L[:, 0, 0], L[:, 1, 1], L[:, 2, 2] = -rate, rate / 2, rate / 2
    r = core.drive_material(cu, L, dt)
    dev = r["stress"] - np.einsum("nii->n", r["stress"])[:, None, None] / 3 * np.eye(3)
    seq = np.sqrt(1.5 * np.einsum("nij,nij->n", dev, dev))
    # reference: the same curve, implicit in eps_p (bisection on
    # eps - eps_p = Y(eps_p, T) / 3G each strain step of 5e-4), trapezoidal in T
    jc = cu.strength
    A, B, nn, C, m, Tm = (jc[k] for k in ("A", "B", "n", "C", "m", "T_melt"))
    G, rho, cv, T0 = cu.shear_modulus, cu.density, cu.specific_heat, 294.0
    flow = lambda ep, T: (A + B * ep**nn) * (1 + C * np.log(rate)) * (1 - ((T - T0) / (Tm - T0))**m)
    nr = 2000
    ep, T, y, ref = 0.0, T0, 0.0, np.empty(nr)
    for k in range(nr):
        eps = (k + 1) / nr
        lo, hi = ep, eps
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if eps - mid > flow(mid, T) / (3 * G) else (lo, mid)
        y_new = min(3 * G * eps, flow(hi, T))
        T += 0.9 * 0.5 * (y + y_new) * (hi - ep) / (rho * cv)
        ep, y, ref[k] = hi, y_new, y_new
    for strain in (0.05, 0.2, 0.5, 1.0):
        k, kr = round(strain * n) - 1, round(strain * nr) - 1
        assert seq[k] == pytest.approx(ref[kr], rel=1e-3), (rate, strain, seq[k], ref[kr])


def test_spall_pressure_releases_tension_and_books_only_the_work_done():
    """Hydrodynamic copper with spall_pressure -1 GPa, stretched in uniaxial
    strain at 1e4/s to J = 1.015 and squeezed back to J = 0.985 through the
    solver's kernel.  Until p would fall below -1 GPa it is the EOS without
    spall, step for step; beyond, it carries no tension (p = 0, stress 0);
    squeezed, it carries pressure again.  At every step its internal energy
    changes by exactly the work of the pressures it carried,
    -(p_prev + p) / 2 tr(D) dt / rho, so a spalled marker gains no energy."""
    if COMM.rank:
        return
    rate, dt, n = 1.0e4, 1.0e-9, 1500
    L = np.zeros((3 * n, 3, 3))
    L[:n, 0, 0], L[n:, 0, 0] = rate, -rate
    plain = core.drive_material(CU.validate("m"), L, dt)
    eos = dict(CU.eos, spall_pressure=-1.0e9)
    r = core.drive_material(Material("cu", density=CU.density, eos=eos).validate("m"), L, dt)
    p, J = r["pressure"], r["J"]
    k = int(np.argmax(plain["pressure"] < -1.0e9))
    assert 0.4 * n < k < n, k                          # the spall strain, 1 GPa / (rho c0^2) = 0.72%
    np.testing.assert_array_equal(p[:k], plain["pressure"][:k])
    assert np.all(p[k:n] == 0.0) and np.all(r["stress"][k:n] == 0.0)
    assert J[-1] < 0.986 and p[-1] > 1.5e9
    de, dw = energy_and_work_per_step(r, L, dt, CU.density)
    np.testing.assert_allclose(de, dw, rtol=0, atol=1e-9 * np.abs(de).max())
    assert np.all(de[k + 1:n] == 0.0)                # spalled: no work at all


def test_a_johnson_cook_failed_marker_carries_no_deviator_or_tension_and_books_its_work():
    """OFHC copper with Johnson-Cook failure at a constant plastic strain of
    0.1 (D1 = 0.1, D2..D5 = 0), stretched in uniaxial strain at 1e4/s to
    J = 1.2 and squeezed back to J = 0.95 through the solver's kernel: damage
    grows as eps_p / 0.1 and reaches 1 at J = 1.165; from then on the marker
    carries no deviator and no tension (stress 0 while stretched) but carries
    pressure again when squeezed; and at every step, the failing one
    included, its internal energy changes by exactly the work of the Cauchy
    stress it carried, (sigma_prev + sigma) : L dt / (2 rho)."""
    if COMM.rank:
        return
    m = Material("cu", preset="OFHC-copper",
                 failure={"type": "johnson-cook", "D1": 0.1, "D2": 0.0, "D3": 0.0, "D4": 0.0, "D5": 0.0}).validate("m")
    rate, dt, n = 1.0e4, 1.0e-8, 2000
    L = np.zeros((n + 2500, 3, 3))
    L[:n, 0, 0], L[n:, 0, 0] = rate, -rate
    r = core.drive_material(m, L, dt)
    s, J, p, D = r["stress"], r["J"], r["pressure"], r["damage"][:, 0]
    k = int(np.argmax(D >= 1.0))
    assert 0.5 * n < k < n and 1.15 < J[k] < 1.18, (k, J[k])
    assert np.all(np.diff(D[:k + 1]) >= 0) and p[k - 1] < -1e10      # failed in tension
    assert np.all(s[k:n] == 0.0)
    dev = s - np.einsum("nii->n", s)[:, None, None] / 3 * np.eye(3)
    assert np.abs(dev[k:]).max() <= 1e-12 * np.abs(p).max()
    assert J[-1] < 0.96 and p[-1] > 5e9
    de, dw = energy_and_work_per_step(r, L, dt, m.density)
    np.testing.assert_allclose(de, dw, rtol=0, atol=1e-9 * np.abs(de).max())


@pytest.mark.parametrize("run,case", [(dict(transfer="apic", shape="bspline2"), "johnson-cook"),
                                      (dict(transfer="musl", shape="gimp", fbar=True), "johnson-cook"),
                                      (dict(transfer="musl", shape="bspline2"), "hydro"),
                                      (dict(transfer="musl", shape="gimp"), "elastic")])
def test_four_lane_kernel_is_bitwise_the_scalar_kernel(run, case):
    """3D markers of one isotropic material go through the constitutive kernel
    four at a time (materials/update4.c); the option -run_lanes 1 forces the
    scalar kernel.  A bar striking a wall obliquely at 300 m/s ends bitwise
    the same both ways, marker by marker on each rank: Johnson-Cook copper
    (plastic flow, heating, artificial viscosity, rotation), hydrodynamic
    copper that spalls below -0.3 GPa, or an elastic-plastic solid without an
    EOS model, whose pressure, viscosity and energy PSMarkerUpdate4Elastic
    computes in lanes."""
    from petsc4py import PETSc
    from plyshock.scene import Cylinder
    material = {"johnson-cook": Material("m", preset="OFHC-copper"),
                "hydro": Material("m", density=CU.density, eos=dict(CU.eos, spall_pressure=-3e8)),
                "elastic": Material("m", density=2700, elastic={"type": "isotropic", "E": 70e9, "nu": 0.33},
                                    strength={"type": "elastic-plastic", "yield_stress": 3e8})}[case]
    scene = Scene(3, Grid([0, 0, 0], [4e-3, 4e-3, 6e-3], [8, 8, 12], {"x-": "symmetry", "y-": "symmetry", "z-": "symmetry"}),
                  [material],
                  [Body("bar", cylinder=Cylinder([0, 0, 0], [0, 0, 1], 1.5e-3, 4e-3), material="m",
                        velocity=[30, 10, -300], subdivision=2)],
                  Run(t_end=3e-6, history_interval=100000, **run)).validate()
    names = ["x", "v", "F", "stress", "sdev", "pressure", "q", "energy", "volume"] + \
        {"johnson-cook": ["plastic_strain", "temperature"], "hydro": [], "elastic": ["plastic_strain"]}[case]
    out = []
    for lanes in (4, 1):
        PETSc.Options().setValue("run_lanes", lanes)
        try:
            m = core.initialize(scene)
            S = core.make_solver(m)
            while S.time < 3e-6 * (1 - 1e-12):
                S.step()
        finally:
            PETSc.Options().delValue("run_lanes")
        f = core.local_fields(m, ["id"] + names)
        o = np.argsort(f["id"][:, 0])
        out.append({k: v[o] for k, v in f.items()})
    assert len(out[0]["id"]) >= 4
    if case != "hydro":
        assert COMM.allreduce(float(out[0]["plastic_strain"].max(initial=0)), op=MPI.MAX) > 0.05
    else:
        assert COMM.allreduce(int(np.sum(out[0]["pressure"] == 0.0)), op=MPI.SUM) > 10   # spalled
    # some markers in compression (viscosity on), some not, in the same run
    nq = COMM.allreduce(np.array([np.sum(out[0]["q"] > 0), np.sum(out[0]["q"] == 0)]), op=MPI.SUM)
    assert nq.min() > 10, nq
    for k in ["id"] + names:
        assert np.array_equal(out[0][k], out[1][k]), (k, np.abs(out[0][k] - out[1][k]).max())


@pytest.mark.parametrize("preset", ["OFHC-copper", "OFHC-copper-ZA", "OFHC-copper-MTS"])
def test_taylor_bar_matches_an_independent_lagrangian_solution_of_the_same_model(preset):
    """The copper Taylor bar (190 m/s, frictionless wall) with each flow-stress
    model (Johnson-Cook, Zerilli-Armstrong fcc, MTS) by plyshock (3D quarter
    model, apic, bspline2, F-bar) and by taylor_rz (2D axisymmetric Lagrangian
    finite elements, no shared code), both at test size: plyshock at 0.5 mm
    cells (two cells across the foot's rim), the reference at 8 x 54 zones.
    The lengths agree within 1.5% (measured +0.2%, 0.0%, 0.0%) and the feet
    within 7% (measured -4.5%, -3.6%, -3.9%): at this coarse size the MPM foot
    is still widening with refinement (Johnson-Cook 13.8 mm at 0.5 mm, 14.3 mm
    at 0.25 mm).  The project's criterion, 2% in length and 3% in foot at
    plyshock's finest grid against the finest reference, is decided by
    `scripts/verify --taylor` (README).  The gap to the 1983 test is the
    model's, the same for both solutions."""
    from plyshock import taylor_rz
    from plyshock.verify import taylor
    mpm = taylor(0.5e-3, shape="bspline2", transfer="apic", material=preset)
    ref = COMM.bcast(taylor_rz.solve(8, 54, material=preset) if COMM.rank == 0 else None)
    assert ref["kinetic_left"] < 0.01 and 0.95 < ref["energy_ratio"] <= 1.0, ref
    assert mpm["kinetic_left"] < 0.01, mpm
    assert mpm["length"] == pytest.approx(ref["length"], rel=0.015), (mpm["length"], ref["length"])
    assert mpm["diameter"] == pytest.approx(ref["diameter"], rel=0.07), (mpm["diameter"], ref["diameter"])
