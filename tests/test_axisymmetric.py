"""Axisymmetric 2D (geometry: axisymmetric; x = r >= 0, y = z, the x- face the
axis): the deck's checks, the exact insertion's full-revolution masses
(Pappus: each clipped piece's volume is its area times 2 pi times its
centroid radius), the hoop terms of the kinematics and the internal force,
and the Taylor bar against the 3D quarter model."""
import copy
import os

import h5py
import numpy as np
import pytest
import yaml
from mpi4py import MPI

from plyshock import Body, Box, DeckError, Grid, Material, Scene, Sphere
from plyshock import core
from plyshock.deck import load_text
from conftest import clean, run_cli, write_deck
from helpers import gather as _gather

COMM = MPI.COMM_WORLD

RHO_CU = 8930.0   # OFHC copper preset (Steinberg), kg/m^3

DECK = {
    "dimension": 2, "geometry": "axisymmetric",
    "grid": {"lower": [0, 0], "upper": [0.008, 0.012], "cells": [16, 24], "boundary": {"x-": "symmetry"}},
    "materials": [{"name": "cu", "preset": "OFHC-copper"},
                  {"name": "cfrp", "preset": "IM7/8552"},
                  {"name": "quasi", "density": 1600,
                   "elastic": {"type": "orthotropic", "E1": 50e9, "E2": 50e9, "E3": 10e9, "G12": 50e9 / 2.6,
                               "G13": 4e9, "G23": 4e9, "nu12": 0.3, "nu13": 0.25, "nu23": 0.25}}],
    "bodies": [{"name": "bar", "material": "cu", "box": {"lower": [0, 0.001], "upper": [0.0037, 0.0063]}}],
    "contact": {"type": "bonded"},     # the laminates added below bonded to the bar
}


def _load(d):
    return load_text(yaml.safe_dump(d))


def _edit(fn):
    d = copy.deepcopy(DECK)
    fn(d)
    return d


def _lam(material, axis3=(0.0, 0.011), rotations=None):
    plies = [{"material": material, "thickness": 1e-3, "rotations": rotations or [[3, 0]]}]
    return {"name": "lam", "laminate": {"frame": {"origin": [0.0, 0.008], "axis3": list(axis3), "plane13": [0.005, 0.008]},
                                        "size": [0.006], "plies": plies}}


def _lam_cohesive():
    lam = _lam("cu")
    lam["laminate"]["plies"] = lam["laminate"]["plies"] * 2
    lam["laminate"]["interface"] = {"type": "cohesive", "normal_strength": 50e6, "shear_strength": 80e6, "G_I": 300.0, "G_II": 800.0}
    return lam


# -------------------------------------------------------------- validation --
def test_valid_decks():
    assert _load(DECK).axisymmetric
    assert not _load(_edit(lambda d: d.pop("geometry"))).axisymmetric
    assert not _load(_edit(lambda d: d.update(geometry="plane-strain"))).axisymmetric
    # an isotropic laminate, and one transversely isotropic about its stacking axis (z)
    _load(_edit(lambda d: d["bodies"].append(_lam("cu"))))
    _load(_edit(lambda d: d["bodies"].append(_lam("quasi", rotations=[[3, 30]]))))
    _load(_edit(lambda d: (d.pop("contact"), d["bodies"].append(_lam("cu")))))     # two bodies in contact
    _load(_edit(lambda d: (d.pop("contact"), d["bodies"].append(_lam_cohesive()))))  # and cohesive ply interfaces


BAD = [
    (lambda d: d.update(geometry="axi"), "geometry", "plane-strain|axisymmetric"),
    (lambda d: d.update(geometry=3), "geometry", "plane-strain|axisymmetric"),
    (lambda d: d.update(dimension=3), "geometry", "needs dimension 2"),
    (lambda d: d["grid"].update(lower=[-0.001, 0]), "grid.lower[0]", "allowed [0, inf]"),
    (lambda d: d["grid"]["boundary"].update({"x-": "free"}), "grid.boundary.x-", "allowed: symmetry"),
    (lambda d: d["grid"].update(boundary={}), "grid.boundary.x-", "allowed: symmetry"),
    # a UD ply is transversely isotropic about its fibre, not the stacking axis
    (lambda d: d["bodies"].append(_lam("cfrp")), "bodies[1].laminate.plies[0].material", "transversely isotropic about the stacking axis"),
    (lambda d: d["bodies"].append(_lam("cu", axis3=(0.002, 0.011))), "bodies[1].laminate.frame.axis3", "must be the z axis"),
    (lambda d: d["bodies"].append(_lam("quasi", rotations=[[1, 20]])), "bodies[1].laminate.plies[0].rotations", "rotations about axis 3 only"),
    (lambda d: d["bodies"][0].update(representation="cells"), "bodies[0].representation", "allowed: markers"),
    (lambda d: d.update(run={"t_end": 1e-6, "transfer": "apic", "shape": "bspline2"}), "run.transfer", "allowed: musl"),
]


@pytest.mark.parametrize("edit,path,allowed", BAD)
def test_bad_input_named(edit, path, allowed):
    with pytest.raises(DeckError) as e:
        s = _load(_edit(edit))
        core.run_options(s)        # the run's options (transfer) are checked with the solver's, before any work
    assert e.value.path == path
    assert allowed in str(e.value)


def test_bad_geometry_exits_2_before_any_work(tmpdir_mpi):
    deck = write_deck(os.path.join(tmpdir_mpi, "bad.yaml"), _edit(lambda d: d["grid"]["boundary"].update({"x-": "fixed"})))
    out = os.path.join(tmpdir_mpi, "m.h5")
    rc, so, se = run_cli(["init", deck, "-o", out], ranks=2)
    assert rc == 2 and clean(se)
    assert "plyshock: error: grid.boundary.x-:" in se and "allowed: symmetry" in se
    assert not os.path.exists(out)


def gather(m, names):
    """All ranks' fields; scalars flat, vectors (n, dim)."""
    return {k: (v.ravel() if v.shape[1] == 1 else v) for k, v in _gather(m, names).items()}


# --------------------------------------------------------------- insertion --
def _scene(bodies, cells=(16, 24), upper=(0.008, 0.012), subdivision=1):
    for b in bodies:
        b.subdivision = subdivision
    return Scene(2, Grid([0.0, 0.0], list(upper), list(cells), {"x-": "symmetry"}), [Material("cu", preset="OFHC-copper")],
                 bodies, geometry="axisymmetric").validate()


@pytest.mark.parametrize("subdivision", [1, 2])
def test_cylinder_mass_exact(subdivision):
    """A box in r-z (radius and height off the cell faces) is a solid cylinder:
    total mass rho pi R^2 H to round-off; every marker's volume is 2 pi r_c
    times its piece's area."""
    R, z0, z1 = 0.0037, 0.0013, 0.0071
    m = core.initialize(_scene([Body("bar", material="cu", box=Box([0.0, z0], [R, z1]))], subdivision=subdivision))
    f = gather(m, ["x", "mass", "volume"])
    M = f["mass"].sum()
    assert M == pytest.approx(RHO_CU * np.pi * R**2 * (z1 - z0), rel=1e-13)
    assert np.allclose(f["mass"], RHO_CU * f["volume"], rtol=1e-15)
    # interior markers: full sub-cells, area h^2/s^2, at the sub-cell centre
    h = 0.0005 / subdivision
    x = f["x"].reshape(-1, 2)
    full = np.isclose(f["volume"] / (2 * np.pi * x[:, 0]), h * h, rtol=1e-12)
    assert full.sum() > 0.5 * len(full)
    # the first moment (centre of mass along z) is the cylinder's
    assert np.sum(f["mass"] * x[:, 1]) / M == pytest.approx(0.5 * (z0 + z1), rel=1e-13)


def test_sphere_mass_pappus():
    """A disk on the axis is a sphere: 4/3 pi R^3 within the curved
    insertion's tolerance (volume_tolerance 1e-6 of the section's area)."""
    R, zc = 0.0031, 0.0061
    m = core.initialize(_scene([Body("ball", material="cu", sphere=Sphere([0.0, zc], R))], subdivision=2))
    f = gather(m, ["x", "mass"])
    M = f["mass"].sum()
    assert M == pytest.approx(RHO_CU * 4.0 / 3.0 * np.pi * R**3, rel=2e-6)
    assert np.sum(f["mass"] * f["x"].reshape(-1, 2)[:, 1]) / M == pytest.approx(zc, rel=1e-6)


def test_insertion_same_on_1_and_2_ranks(tmpdir_mpi):
    d = _edit(lambda d: d["bodies"].append({"name": "ball", "material": "cu", "sphere": {"center": [0.0, 0.0095], "radius": 0.002},
                                            "subdivision": 2}))
    deck = write_deck(os.path.join(tmpdir_mpi, "axi.yaml"), d)
    sets = []
    for k in (1, 2):
        out = os.path.join(tmpdir_mpi, f"m{k}.h5")
        rc, so, se = run_cli(["init", deck, "-o", out], ranks=k)
        assert rc == 0, se
        with h5py.File(out, "r") as f:
            g = f["markers"]
            o = np.argsort(g["id"][...])
            sets.append({n: g[n][...][o] for n in ("id", "x", "mass", "volume")})
    for n in sets[0]:
        assert np.array_equal(sets[0][n], sets[1][n]), n
    R = 0.0037
    bar = RHO_CU * np.pi * R**2 * 0.0053
    assert sets[0]["mass"].sum() == pytest.approx(bar + RHO_CU * 4 / 3 * np.pi * 0.002**3, rel=2e-6)


# ------------------------------------------------------ kinematics, force --
E_EL, NU_EL, RHO_EL = 200e9, 0.3, 7800.0            # an isotropic elastic solid (steel-like)
K_EL, G_EL = E_EL / (3 * (1 - 2 * NU_EL)), E_EL / (2 * (1 + NU_EL))


def _cylinder(shape, R=6e-3, h=0.25e-3, nz=4):
    """An elastic solid cylinder r < R, infinite along z (symmetry faces at
    both z ends): the grid reaches 8 h beyond R."""
    from plyshock import Run
    nr = round(R / h) + 8
    scene = Scene(2, Grid([0.0, 0.0], [nr * h, nz * h], [nr, nz], {"x-": "symmetry", "y-": "symmetry", "y+": "symmetry"}),
                  [Material("el", density=RHO_EL, elastic={"type": "isotropic", "E": E_EL, "nu": NU_EL})],
                  [Body("cyl", material="el", box=Box([0.0, 0.0], [R, nz * h]), subdivision=2)],
                  Run(t_end=1.0, shape=shape, history_interval=100000), geometry="axisymmetric").validate()
    m = core.initialize(scene)
    return m, core.make_solver(m)


def _set(m, name, fn):
    a = m.sw.getField(name)
    n = m.sw.getLocalSize()
    v = np.asarray(a).reshape(n, -1) if n else np.zeros((0, 1))
    fn(v)
    m.sw.restoreField(name)


@pytest.mark.parametrize("shape", ["linear", "gimp", "bspline2"])
def test_uniform_radial_rate_gives_the_hoop_rate_and_the_closed_form_pressure(shape):
    """v_r = a r, v_z = 0 in an elastic cylinder: D = diag(a, 0, a) (L_rr =
    dv_r/dr = a, hoop L_tt = v_r / r = a).  After the first step (dt) every
    interior marker has F_tt - 1 = a dt (= V / (V0 det F_rz) - 1: the hoop
    stretch the volume carries), r/r0 = F_tt, and the closed-form pressure
    p = -K tr(D) dt = -2 K a dt (hypoelastic, compression positive) and
    sigma_tt - sigma_zz = 2 G a dt.  Interior: 3 cells from the axis and the
    free surface (the projection of v_r is exact for a linear field in the
    bulk up to h^2/(6 r^2), the r-weighted masses' bias)."""
    a, R, h = -200.0, 6e-3, 0.25e-3
    m, S = _cylinder(shape, R, h)
    x0 = core.local_fields(m, ["x"])["x"].copy()

    def radial(v):
        v[:, 0] = a * x0[:, 0]
        v[:, 1] = 0.0
    _set(m, "v", radial)
    S.step()
    dt = S.time
    f = core.local_fields(m, ["x", "F", "volume", "volume0", "pressure", "stress"])
    assert len(f["x"]) == len(x0)         # nothing migrated: the same markers in the same order
    inner = (x0[:, 0] > 3 * h) & (x0[:, 0] < R - 3 * h)
    F = f["F"]
    Ftt = f["volume"][:, 0] / (f["volume0"][:, 0] * (F[:, 0] * F[:, 3] - F[:, 1] * F[:, 2]))
    n = MPI.COMM_WORLD.allreduce(int(inner.sum()))
    assert n > 100
    rate_tt = (Ftt[inner] - 1.0) / dt
    rate_rr = (F[inner, 0] - 1.0) / dt
    # the error relative to a, scaled by the projection's bias (h/r)^2
    rh2 = (x0[inner, 0] / h) ** 2
    k_tt = MPI.COMM_WORLD.allreduce(float((np.abs(rate_tt / a - 1) * rh2).max(initial=0)), op=MPI.MAX)
    k_rr = MPI.COMM_WORLD.allreduce(float((np.abs(rate_rr / a - 1) * rh2).max(initial=0)), op=MPI.MAX)
    assert k_tt < 0.3 and k_rr < 0.3, (k_tt, k_rr)
    # the hoop stretch is the radius' stretch: F_tt = r / r0
    assert np.allclose(Ftt[inner], f["x"][inner, 0] / x0[inner, 0], rtol=1e-6, atol=0)
    p_exact = -2.0 * K_EL * a * dt
    err_p = MPI.COMM_WORLD.allreduce(float(np.abs(f["pressure"][inner, 0] / p_exact - 1).max(initial=0)), op=MPI.MAX)
    assert err_p < 0.3 / 9 + 1e-3, err_p
    s = f["stress"]            # xx (rr), yy (zz), zz (tt), xy
    err_s = np.abs((s[inner, 2] - s[inner, 1]) / (2 * G_EL * a * dt) - 1).max(initial=0)
    assert MPI.COMM_WORLD.allreduce(float(err_s), op=MPI.MAX) < 0.3 / 9 + 1e-3


@pytest.mark.parametrize("shape", ["linear", "gimp", "bspline2"])
def test_uniform_pressure_is_in_equilibrium_inside_only_with_the_hoop_force(shape):
    """A cylinder at rest under a uniform pressure p0 (sigma = -p0 I): div sigma
    = d sigma_rr/dr + (sigma_rr - sigma_tt)/r = 0 inside, so after one step the
    interior stays at rest while the free surface r = R moves out.  Without the
    hoop force -V sigma_tt N / r the r-weighted volumes leave a radial force
    at every interior node (of order p0 V / r); with it the interior velocity
    is below 1e-9 of the surface's: the markers at the sub-cell centres
    integrate d(r N_i)/dr exactly.  Quadratic B-splines do so only 1.5 cells
    from the axis and beyond: a node whose spline reaches past r = 0 loses
    part of its quadrature, so their interior starts at 3 h; the same lack
    of a boundary form at the plane symmetry faces z = 0 and z = 4 h moves
    v_z there (measured: 6.5% of the surface's v_r), so only v_r is checked
    for them."""
    R, h, p0 = 6e-3, 0.25e-3, 1e9
    m, S = _cylinder(shape, R, h)

    def stress(s):
        s[:, :3] = -p0
        s[:, 3] = 0.0
    _set(m, "stress", stress)
    _set(m, "pressure", lambda p: p.__setitem__(slice(None), p0))
    x0 = core.local_fields(m, ["x"])["x"].copy()
    S.step()
    v = core.local_fields(m, ["v"])["v"]
    assert len(v) == len(x0)
    comm = MPI.COMM_WORLD
    vs = comm.allreduce(float(v[x0[:, 0] > R - h, 0].max(initial=0)), op=MPI.MAX)
    inner = (x0[:, 0] < R - 4 * h) & (x0[:, 0] > (3 * h if shape == "bspline2" else 0.0))
    # bspline2: v_r only (the same splines' residual at the symmetry faces z = 0, 4 h moves v_z,
    # a plane direction: not the hoop term's)
    vi = comm.allreduce(float(np.abs(v[inner][:, :1 if shape == "bspline2" else 2]).max(initial=0)), op=MPI.MAX)
    assert vs > 0.1, vs           # the surface accelerates outward: p0 dt / (rho h) is about 1 m/s
    assert vi < 1e-9 * vs, (vi, vs)


def test_totals_are_the_full_revolutions(tmpdir_mpi):
    """history.csv's mass and kinetic energy are the whole body's: a solid
    cylinder moving along z at 100 m/s has M = rho pi R^2 H and
    KE = M v^2 / 2, and py (the axial momentum) -M v; px holds sum m_p v_r,
    not a component of the revolution's momentum (which has no radial
    part): zero here."""
    import csv
    from plyshock import Run
    R, H, v = 3.3e-3, 4.1e-3, 100.0
    scene = Scene(2, Grid([0.0, 0.0], [5e-3, 6e-3], [10, 12], {"x-": "symmetry"}), [Material("cu", preset="OFHC-copper")],
                  [Body("bar", material="cu", box=Box([0.0, 1e-3], [R, 1e-3 + H]), velocity=[0.0, -v], subdivision=2)],
                  Run(t_end=2e-7), geometry="axisymmetric").validate()
    m = core.initialize(scene)
    core.run(m, tmpdir_mpi, scene.to_yaml())
    M = RHO_CU * np.pi * R**2 * H
    if COMM.rank == 0:
        with open(os.path.join(tmpdir_mpi, "history.csv")) as f:
            rows = list(csv.DictReader(f))
        r0 = rows[0]
        assert float(r0["mass"]) == pytest.approx(M, rel=1e-13)
        assert float(r0["kinetic"]) == pytest.approx(0.5 * M * v * v, rel=1e-13)
        assert float(r0["py"]) == pytest.approx(-M * v, rel=1e-13)
        assert float(r0["px"]) == 0.0
        assert float(rows[-1]["total"]) == pytest.approx(float(r0["total"]), rel=1e-3)


def test_run_same_on_1_and_2_ranks(tmpdir_mpi):
    """A short axisymmetric impact (the bar at 190 m/s onto the wall z = 0) by
    `plyshock run` on 1 and 2 ranks: the same markers (ids) and states to
    round-off (the ghost sums add in another order)."""
    d = _edit(lambda d: d["grid"]["boundary"].update({"y-": "symmetry"}))
    d["bodies"][0].update(velocity=[0, -190.0], subdivision=2)
    d["bodies"][0]["box"]["lower"] = [0, 0]
    d["run"] = {"t_end": 3e-6, "shape": "bspline2", "fbar": True, "pic_fraction": 0.01}
    deck = write_deck(os.path.join(tmpdir_mpi, "run.yaml"), d)
    res = []
    for k in (1, 2):
        out = os.path.join(tmpdir_mpi, f"r{k}")
        rc, so, se = run_cli(["run", deck, "-o", out], ranks=k)
        assert rc == 0, se
        last = sorted(f for f in os.listdir(out) if f.startswith("markers_"))[-1]
        with h5py.File(os.path.join(out, last), "r") as f:
            g = f["markers"]
            o = np.argsort(g["id"][...])
            res.append({n: g[n][...][o] for n in ("id", "x", "v", "pressure", "volume")})
        res[-1]["history"] = np.genfromtxt(os.path.join(out, "history.csv"), delimiter=",", names=True)
    a, b = res
    assert np.array_equal(a["id"], b["id"])
    assert np.abs(a["x"] - b["x"]).max() <= 1e-12 * 0.012
    assert np.abs(a["v"] - b["v"]).max() <= 1e-8 * 190.0
    assert np.abs(a["pressure"] - b["pressure"]).max() <= 1e-8 * np.abs(a["pressure"]).max()
    assert np.abs(a["volume"] / b["volume"] - 1).max() <= 1e-12
    for c in ("mass", "kinetic", "internal", "total"):
        assert a["history"][c] == pytest.approx(b["history"][c], rel=1e-9), c


# ------------------------------------------------------------- Taylor bar --
def test_taylor_bar_axisymmetric_matches_the_3d_quarter_model():
    """The copper Taylor bar (Johnson-Cook, 190 m/s, frictionless wall) in
    axisymmetric 2D (musl, bspline2, F-bar, 1% PIC) against the 3D quarter
    model (apic, bspline2, F-bar: the README's verified bar), both at 0.5 mm
    cells, run here one after the other: final length within 2% and foot
    diameter within 3% (measured -0.1% and -0.2%; at 0.25 mm -0.1% and +0.2%),
    at a fraction of the run time (measured 10-55x less on this shared
    machine; asserted > 3x, timings move with the load).  Both are also near
    taylor_rz's axisymmetric Lagrangian solution of the same model."""
    from plyshock.verify import taylor, taylor_axi
    axi = taylor_axi(0.5e-3)
    q3d = taylor(0.5e-3, shape="bspline2", transfer="apic")
    if COMM.rank == 0:
        print(f"\nTaylor bar at 0.5 mm: axisymmetric length {axi['length'] * 1e3:.3f} mm, foot {axi['diameter'] * 1e3:.3f} mm, "
              f"{axi['markers']} markers, {axi['steps']} steps, {axi['wall_s']:.1f} s; 3D quarter {q3d['length'] * 1e3:.3f} mm, "
              f"{q3d['diameter'] * 1e3:.3f} mm, {q3d['markers']} markers, {q3d['steps']} steps, {q3d['wall_s']:.1f} s; "
              f"ratio {q3d['wall_s'] / axi['wall_s']:.1f}", flush=True)
    assert axi["kinetic_left"] < 0.01 and q3d["kinetic_left"] < 0.01
    assert axi["length"] == pytest.approx(q3d["length"], rel=0.02)
    assert axi["diameter"] == pytest.approx(q3d["diameter"], rel=0.03)
    assert q3d["wall_s"] > 3.0 * axi["wall_s"]


# --------------------------------------------------------- the Noh problem --
def test_cylindrical_noh_problem(tmpdir_mpi):
    """The cylindrical Noh problem (W. F. Noh, J. Comput. Phys. 72, 78-120,
    1987; issue 14's radial check): an ideal gas, gamma = 5/3, rho0 = 1 kg/m^3,
    cold, everywhere moving toward the axis at v0 = 1000 m/s; a thin slab in z
    (symmetry faces at both z ends) makes it 1D in r.  Exact at time t: a
    shock at r_s = (gamma - 1)/2 v0 t = v0 t / 3; behind it the gas at rest
    with rho = rho0 ((gamma + 1)/(gamma - 1))^2 = 16 rho0, e = v0^2/2 and
    p = (gamma - 1) rho e = 16/3 rho0 v0^2; ahead of it the cold gas still at
    v0 inward with rho = rho0 (1 + v0 t / r) (the hoop convergence only:
    without L_tt = v_r / r it would stay rho0, 55% low at 2-3 r_s).  The outer
    face is free: its gas moves in unopposed (no pressure) and is still at
    r > 0.6 m when the shock is at 0.133 m, far from the checks.
    The cold gas takes p0 = 1e-6 of the shocked pressure (an ideal-gas body
    needs p > 0); the run guard dt_floor is off: the first step is set by
    v0 alone (c0 = 3 m/s), and the next, once the markers next to the axis
    are crushed (their viscous CFL term), thousands of times shorter
    (measured 3,400x at 5 mm cells), which the guard takes for a failure.
    At 2.5 mm cells (400 x 2, 2 x 2 markers per cell, gimp, musl, the default
    artificial viscosity 0.2/2.0), t = 0.4 ms, 1,140 steps, measured:
    post-shock density (sum m / sum V over 0.3-0.8 r_s) 15.73 (-1.7%; 14.56 at
    5 mm, 16.38 at 1.25 mm), pressure (volume mean) -3.2%, mean v_r -3 m/s; pre-shock
    density at 2-3 r_s within 2e-4 of rho0 (1 + v0 t / r); the shock (the
    outermost crossing of the mid-value 10 rho0 between 16 and the 4 ahead of
    it, in cell bins) 0.9 cells ahead of v0 t / 3 (1.6 at 5 mm, -0.6 at 1.25
    mm); mass exact; the total energy 0.74% low (0.65%, 0.77% at 5 and
    1.25 mm: it grows with the shocked mass, about 2.3% of the shocked gas's
    energy, and does not shrink with h).  Asserted: 10%, 10%, 2% of v0,
    1%, 2 cells, 1e-12, 2%.  Excluded: r < 0.3 r_s, Noh's wall heating (the
    viscosity's excess entropy at the axis: the density dips to 2 rho0 on the
    first cells)."""
    import csv
    from plyshock import Run
    R, v0, rho0, gamma, t_end = 1.0, 1000.0, 1.0, 5.0 / 3.0, 0.4e-3
    nr, nz = 400, 2
    h = R / nr
    p_post = (gamma - 1) * 16 * rho0 * 0.5 * v0**2
    scene = Scene(2, Grid([0.0, 0.0], [R, nz * h], [nr, nz], {"x-": "symmetry", "y-": "symmetry", "y+": "symmetry"}),
                  [Material("gas", density=rho0, eos={"type": "ideal-gas", "gamma": gamma})],
                  [Body("gas", material="gas", box=Box([0.0, 0.0], [R, nz * h]), velocity=[-v0, 0.0], subdivision=2,
                        pressure=1e-6 * p_post)],
                  Run(t_end=t_end, shape="gimp", dt_floor=0.0), geometry="axisymmetric").validate()
    m = core.initialize(scene)
    S = core.run(m, tmpdir_mpi, scene.to_yaml())
    assert S.time == pytest.approx(t_end, rel=1e-12)
    f = gather(m, ["x", "v", "mass", "volume", "pressure"])
    x = f["x"].reshape(-1, 2)
    r, vr, mass, vol, p = x[:, 0], f["v"].reshape(-1, 2)[:, 0], f["mass"], f["volume"], f["pressure"]
    rho = mass / vol
    rs = v0 * t_end / 3
    post = (r > 0.3 * rs) & (r < 0.8 * rs)
    pre = (r > 2 * rs) & (r < 3 * rs)
    rho_post = mass[post].sum() / vol[post].sum()
    p_mean = np.sum(p[post] * vol[post]) / vol[post].sum()
    err_pre = np.abs(rho[pre] / (rho0 * (1 + v0 * t_end / r[pre])) - 1).max()
    # the shock: cell-binned density (sum m / sum V), the outermost bin above the mid-value, interpolated
    nb = int(1.5 * rs / h)
    k = np.floor(r / h).astype(int)
    inb = k < nb
    brho = np.bincount(k[inb], mass[inb], nb) / np.bincount(k[inb], vol[inb], nb)
    mid = 0.5 * (16 + 4) * rho0
    j = np.nonzero(brho > mid)[0].max()
    r_shock = (j + 0.5) * h + (brho[j] - mid) / (brho[j] - brho[j + 1]) * h
    if COMM.rank == 0:
        with open(os.path.join(tmpdir_mpi, "history.csv")) as fh:
            rows = list(csv.DictReader(fh))
        h0, h1 = rows[0], rows[-1]
        dm = float(h1["mass"]) / float(h0["mass"]) - 1
        de = float(h1["total"]) / float(h0["total"]) - 1
        print(f"\nNoh (cylindrical) at {h * 1e3:.2f} mm, {len(r)} markers, {S.step_count} steps: post-shock rho {rho_post:.3f} "
              f"(16), p {p_mean / p_post - 1:+.3f}, v_r {vr[post].mean():.2f} m/s; pre-shock max error {err_pre:.1e}; "
              f"shock {r_shock:.4f} m ({rs:.4f}, {(r_shock - rs) / h:+.2f} cells); mass {dm:.1e}, total energy {de:+.2e}",
              flush=True)
        assert float(h0["mass"]) == pytest.approx(np.pi * R**2 * nz * h * rho0, rel=1e-12)
        assert abs(dm) < 1e-12
        assert abs(de) < 0.02
    assert post.sum() > 100 and pre.sum() > 100
    assert rho_post == pytest.approx(16 * rho0, rel=0.10)
    assert p_mean == pytest.approx(p_post, rel=0.10)
    assert abs(vr[post].mean()) < 0.02 * v0
    assert err_pre < 0.01
    assert abs(r_shock - rs) < 2 * h
