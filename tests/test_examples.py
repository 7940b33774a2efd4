"""The method's two example scenes, at small size on 2 ranks: exact ply and
body masses, body momenta, and the orientation pictures (rendered off screen)."""
import os

import h5py
import numpy as np
from mpi4py import MPI

import oblique_plate_2d
import sphere_plate_3d
import sphere_plate_axi
from plyshock import core
from helpers import gather

COMM = MPI.COMM_WORLD


def picture_ok(png, min_colours=5):
    """The PNG exists and is not blank: several distinct colours (plies, bodies)."""
    import matplotlib.image as mpimg
    img = mpimg.imread(png)[..., :3]
    colours = np.unique((img.reshape(-1, 3) * 255).astype(np.uint8), axis=0)
    return img.std() > 0.01 and len(colours) >= min_colours


def render(m, tmpdir, name, zoom):
    path = os.path.join(tmpdir, name + ".h5")
    core.write_markers(m, path, m.scene.to_yaml())
    ok = None
    if COMM.rank == 0:
        from plyshock.post import plot_markers
        png = plot_markers(path, os.path.join(tmpdir, name + ".png"), zoom=zoom, window=(640, 480))
        ok = picture_ok(png)
    return COMM.bcast(ok, root=0)


def test_oblique_plate_2d(tmpdir_mpi):
    scene = oblique_plate_2d.setup(cells=(96, 64)).validate()
    m = core.initialize(scene)
    f = gather(m, ["mass", "ply", "body", "v"])
    for k in range(4):                      # each ply: rho L t, per metre of depth, exact
        M = f["mass"][(f["body"][:, 0] == 0) & (f["ply"][:, 0] == k), 0].sum()
        assert abs(M - 1570.0 * 0.040 * 0.5e-3) <= 1e-12 * M
    fly = f["body"][:, 0] == 1
    M = f["mass"][fly, 0].sum()
    assert abs(M - 7810.0 * 0.008 * 0.003) <= 1e-12 * M
    p = (f["mass"][fly] * f["v"][fly]).sum(axis=0)
    assert np.allclose(p, [0.0, -400.0 * M], rtol=1e-13, atol=0)
    assert np.all(f["v"][~fly] == 0.0)
    assert render(m, tmpdir_mpi, "oblique", oblique_plate_2d.ZOOM)


def test_sphere_plate_3d(tmpdir_mpi):
    scene = sphere_plate_3d.setup(cell=1.0e-3).validate()
    m = core.initialize(scene)
    f = gather(m, ["mass", "ply", "body", "v"])
    for k in range(4):                      # the quarter plate, exact
        M = f["mass"][(f["body"][:, 0] == 0) & (f["ply"][:, 0] == k), 0].sum()
        assert abs(M - 1570.0 * 0.025 * 0.025 * 0.5e-3) <= 1e-12 * M
    ball = f["body"][:, 0] == 1
    M = f["mass"][ball, 0].sum()
    exact = 8930.0 * np.pi * 3e-3**3 / 3.0       # a quarter of 4/3 pi r^3
    assert abs(M - exact) <= 1e-5 * exact
    p = (f["mass"][ball] * f["v"][ball]).sum(axis=0)
    assert np.allclose(p, [0.0, 0.0, -600.0 * M], rtol=1e-13, atol=0)
    # both bodies are cut by the symmetry faces, and the clipped volume is reported
    assert set(m.clipped) == {"plate", "sphere"}
    assert np.isclose(m.clipped["plate"], 0.75 * 0.05 * 0.05 * 2e-3, rtol=1e-12)
    assert render(m, tmpdir_mpi, "sphere", sphere_plate_3d.ZOOM)


def _check_impact(out, scene, projectile, v0, tmp):
    """Mass and markers conserved or booked, momentum conserved, the
    projectile slowed, plies damaged near the impact with their axes turned
    and orthonormal, pictures drawn."""
    dim = scene.dimension
    H = np.genfromtxt(os.path.join(tmp, "history.csv"), delimiter=",", names=True)
    assert abs(H["mass"][-1] + H["lost_mass"][-1] - H["mass"][0]) <= 1e-12 * H["mass"][0]
    # no external force along the impact: free faces in 2D; in 3D the symmetry
    # faces x = 0, y = 0 act on px, py only (the sums of booked removals are added back)
    k = "py" if dim == 2 else "pz"
    assert H["lost_mass"][-1] == 0.0
    # 1e-10 in one field; the sphere in contact with the plate (the default) drifts to 2.0e-10, with
    # the plies' cohesive interfaces besides (five fields) to 3.9e-9 (measured; the force dropped on
    # nodes lighter than run.mass_threshold, docs/contact.md): 1e-8
    assert abs(H[k][-1] - H[k][0]) <= 1e-8 * abs(H[k][0]), (H[k][0], H[k][-1])
    B = np.genfromtxt(os.path.join(tmp, "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
    pr = B[B["body"] == projectile]
    vz = ("vy" if dim == 2 else "vz")
    assert np.isclose(pr[vz][0], -v0, rtol=1e-12)
    assert -v0 < pr[vz][-1] < 0.0                  # slowed by the plate, not stopped or reversed
    steps = sorted(f for f in os.listdir(tmp) if f.startswith("markers_"))
    with h5py.File(os.path.join(tmp, steps[0]), "r") as f0, h5py.File(os.path.join(tmp, steps[-1]), "r") as f1:
        n0 = len(f0["markers/id"])
        assert len(f1["markers/id"]) + int(round(H["markers"][0] - H["markers"][-1])) == n0
        assert n0 == int(H["markers"][0])
        ply = f1["markers/ply"][...]
        dmg = f1["markers/damage"][...]
        assert dmg.shape == (len(ply), 4) and np.all((dmg >= 0) & (dmg <= 1))
        assert dmg[ply >= 0].max() == 1.0              # the impact fails plies
        assert dmg[ply < 0].max() == 0.0               # projectile markers carry no ply damage
        A = np.stack([f1[f"markers/axis{k}"][...] for k in (1, 2, 3)], axis=1)
        assert np.abs(np.einsum("nij,nkj->nik", A, A) - np.eye(3)).max() <= 1e-12
        # axes turned with the material: some fibres by more than 5 degrees (matched by id)
        i0, i1 = f0["markers/id"][...], f1["markers/id"][...]
        a0 = dict(zip(i0.tolist(), f0["markers/axis1"][...]))
        turn = np.array([np.degrees(np.arccos(min(1.0, abs(float(np.dot(a0[i], a)))))) for i, a, p in
                         zip(i1.tolist(), f1["markers/axis1"][...], ply) if p >= 0])
        assert turn.max() > 5.0
        n1 = len(i1)
    # ParaView's series describes the four damage variables as an N x 4 matrix
    xdmf = open(os.path.join(tmp, "markers.xdmf")).read()
    assert f'Name="damage" AttributeType="Matrix" Center="Node"><DataItem Dimensions="{n1} 4"' in xdmf
    return turn


def test_oblique_plate_2d_impact_end_to_end(tmpdir_mpi):
    from plyshock.cli import impact
    scene = oblique_plate_2d.setup(cells=(96, 64), t_end=6e-6, output_interval=3e-6).validate()
    out = impact(scene, tmpdir_mpi, oblique_plate_2d.ZOOM, "flyer")
    _check_impact(out, scene, "flyer", 400.0, tmpdir_mpi)
    names = sorted(os.path.basename(p) for p in out["pngs"])
    assert names == ["after.png", "before.png", "damage.png", "velocity.png"]
    ok = all(picture_ok(p, 3) for p in out["pngs"]) if COMM.rank == 0 else None
    assert COMM.bcast(ok, root=0)


def test_sphere_plate_3d_impact_end_to_end(tmpdir_mpi):
    from plyshock.cli import impact
    scene = sphere_plate_3d.setup(cell=1.25e-3, subdivision=2, t_end=6e-6, output_interval=3e-6).validate()
    out = impact(scene, tmpdir_mpi, sphere_plate_3d.ZOOM, "sphere", sphere_plate_3d.CUT)
    _check_impact(out, scene, "sphere", 600.0, tmpdir_mpi)
    assert len(out["pngs"]) == 9                   # with delamination.png and delamination_cut.png
    # the plies meet at cohesive interfaces: under the sphere they open (D = 1),
    # far from it they hold (D = 0); the laws took energy, none negative
    H = np.genfromtxt(os.path.join(tmpdir_mpi, "history.csv"), delimiter=",", names=True)
    assert H["interface_energy"][-1] > 0 and np.all(np.diff(H["interface_energy"]) >= 0)
    steps = sorted(f for f in os.listdir(tmpdir_mpi) if f.startswith("markers_"))
    with h5py.File(os.path.join(tmpdir_mpi, steps[-1]), "r") as f:
        D, x, ply = f["markers/interface_damage"][...], f["markers/x"][...], f["markers/ply"][...]
    r = np.hypot(x[:, 0], x[:, 1])
    far = np.mean(D[(ply >= 0) & (r > 20e-3)] > 0.5)       # measured 0.3%: the coarse grid spreads the opening
    if COMM.rank == 0:
        print(f"\n3D sphere, 1.25 mm cells: interface damage > 0.5 on {100 * far:.1f}% of the ply markers beyond 20 mm")
    assert D[(ply >= 0) & (r < 3e-3)].max() == 1.0 and far < 0.1, far
    assert D[ply < 0].max() == 0.0
    ok = all(picture_ok(p, 3) for p in out["pngs"]) if COMM.rank == 0 else None
    assert COMM.bcast(ok, root=0)


# ---------------------------------------------------------------- in cells --
# Issue 12's examples with the Eulerian host: a blast in a closed chamber on a
# panel, and the oblique plate in air.  The energy bounds are what the solver
# gives today, measured (see the README's section on cells): the total less the
# booked coupling work (the work of fitting cell materials beside the markers)
# dips by about 3% in the first microseconds and stays there.
ENERGY_BOUND = 0.04          # |total - coupling_work - total(0)| / total(0)


def _cells_history(tmp):
    """history.csv, with mass + lost_mass constant to 1e-12 of the mass on every row."""
    H = np.genfromtxt(os.path.join(tmp, "history.csv"), delimiter=",", names=True)
    booked = H["mass"] + H["lost_mass"]
    assert np.abs(booked - booked[0]).max() <= 1e-12 * booked[0], np.abs(booked - booked[0]).max() / booked[0]
    assert {"remap_heat", "coupling_work"} <= set(H.dtype.names)
    return H


def _picture_stats(png):
    import matplotlib.image as mpimg
    img = mpimg.imread(png)[..., :3]
    return img.mean(axis=(0, 1)), img.std()


def test_blast_panel_2d_end_to_end(tmpdir_mpi):
    """The blast example to 30 us (the panel's fastest motion), 2 ranks:
    the initial energy is the charge's p V / (gamma - 1) and the air's, exact
    to the disk's volume tolerance; mass booked exactly; the chamber's walls
    let nothing out but discarded traces; the panel pushed down (its centre
    faster than its mean), its supports held on the floor; energy within
    ENERGY_BOUND; the pictures drawn, cells fields differing."""
    import blast_panel_2d as bp
    from plyshock.cli import impact
    scene = bp.setup(t_end=30e-6, output_interval=15e-6).validate()
    out = impact(scene, tmpdir_mpi, bp.ZOOM, "panel", cells=bp.CELLS)
    H = _cells_history(tmpdir_mpi)
    # t = 0: the charge (half disk, 50 MPa) and the air (101325 Pa) in the rest of the chamber, minus the markers' area
    E_charge = bp.charge_energy(scene)
    assert abs(E_charge - 50e6 * 0.5 * np.pi * 4e-3 ** 2 / 0.4) < 1e-9 * E_charge
    A_air = 0.05 * 0.04 - 0.5 * np.pi * 4e-3 ** 2 - 0.040 * 2e-3 - 0.008 * 0.010
    E0 = E_charge + 101325.0 / 0.4 * A_air
    assert abs(H["internal"][0] - E0) <= 1e-6 * E0, (H["internal"][0], E0)
    assert H["kinetic"][0] == 0.0
    # closed chamber: only traces discarded by the remap are booked, and they are tiny
    assert H["lost_mass"][-1] < 1e-6 * H["mass"][0]
    # energy: the total less the booked coupling work, within the bound on every row
    rel = (H["total"] - H["coupling_work"] - H["total"][0]) / H["total"][0]
    assert np.abs(rel).max() < ENERGY_BOUND, np.abs(rel).max()
    assert H["coupling_work"][-1] < 1e-3 * H["total"][0]
    # the panel moves in the blast direction (-y): mean speed peaks at 10.8 m/s at 25 us on these 1 mm cells
    B = np.genfromtxt(os.path.join(tmpdir_mpi, "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
    P, S = B[B["body"] == "panel"], B[B["body"] == "support"]
    assert P["vy"][0] == 0.0 and -13.0 < P["vy"].min() < -8.0, P["vy"].min()
    assert np.abs(S["vy"]).max() < 0.1 * np.abs(P["vy"]).max()       # the supports stand on the floor
    G = np.genfromtxt(os.path.join(tmpdir_mpi, "gauges.csv"), delimiter=",", names=True)
    centre = G[G["gauge"] == 0]
    assert centre["vy"].min() < 1.5 * P["vy"].min()                  # the centre, under the charge, moves fastest
    assert centre["y"][-1] < centre["y"][0] - 1e-4                   # and has moved down by more than 0.1 mm
    names = sorted(os.path.basename(p) for p in out["pngs"])
    assert names == ["after.png", "before.png", "cells_pressure.png", "cells_products.png", "damage.png", "history.png",
                     "velocity.png"]
    res = None
    if COMM.rank == 0:
        ok = all(picture_ok(p, 3) for p in out["pngs"])
        frames = sorted(os.listdir(os.path.join(tmpdir_mpi, "frames")))
        (m1, s1), (m2, s2) = (_picture_stats(os.path.join(tmpdir_mpi, f"cells_{n}.png")) for n in ("pressure", "products"))
        res = (ok, frames, float(np.abs(m1 - m2).max()))
    ok, frames, diff = COMM.bcast(res, root=0)
    assert ok and diff > 0.02, diff
    assert frames == [f"{n}_{k:05d}.png" for n in ("pressure", "products") for k in range(3)]
    xdmf = open(os.path.join(tmpdir_mpi, "cells.xdmf")).read()
    assert 'Name="volume_fraction_products"' in xdmf and 'Name="volume_fraction_air"' in xdmf


def test_oblique_plate_2d_in_air_end_to_end(tmpdir_mpi):
    """The oblique plate with --air at its default size (96 x 64) to 8 us, 2 ranks: the air's
    initial energy, every cell of pure air at 101325 Pa; mass booked
    exactly; the flyer slowed, and by the air a little more than in vacuum;
    the plies failed near the impact; energy within ENERGY_BOUND; cells and
    markers drawn together."""
    from plyshock.cli import impact
    from plyshock.post import read_cells
    scene = oblique_plate_2d.setup(cells=(96, 64), air=True).validate()           # the example's --air default
    assert [b.name for b in scene.bodies] == ["air", "plate", "flyer"] and scene.cell_materials == [2]
    out = impact(scene, tmpdir_mpi, oblique_plate_2d.ZOOM, "flyer", cells=oblique_plate_2d.CELLS,
                 cells_zoom=oblique_plate_2d.CELLS_ZOOM)
    H = _cells_history(tmpdir_mpi)
    # the air fills the grid less the markers' area: to 1e-4 (measured 1.1e-5: the oblique plate's
    # cells are shared between the air's exact fractions and the markers' deposited boxes)
    A_air = 0.060 * 0.040 - 0.040 * 2e-3 - 0.008 * 0.003
    assert abs(H["internal"][0] - 101325.0 / 0.4 * A_air) <= 1e-4 * H["internal"][0]
    rel = (H["total"] - H["coupling_work"] - H["total"][0]) / H["total"][0]
    assert np.abs(rel).max() < ENERGY_BOUND, np.abs(rel).max()
    # the fit's work on the air beside the markers (measured 5e-5 of the total: where flyer and plate
    # meet the crowded-out air is discarded, not crushed; bonded it was 1.3%; see the README)
    assert H["coupling_work"][-1] < 0.02 * H["total"][0], H["coupling_work"][-1]
    B = np.genfromtxt(os.path.join(tmpdir_mpi, "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
    fl = B[B["body"] == "flyer"]
    assert np.isclose(fl["vy"][0], -400.0, rtol=1e-12) and -400.0 < fl["vy"][-1] < 0.0
    # the air slows the flyer a little more than the plate alone does: the same scene in vacuum (in
    # contact, as in air) ends 0.16 m/s faster (the air's push, about 0.4 MPa ahead and 15 kPa in the
    # wake of an 8 x 3 mm steel flyer over 8 us, gives about 0.13 m/s)
    from plyshock.cli import _run
    vac = oblique_plate_2d.setup(cells=(96, 64)).validate()
    _run(vac, vac.to_yaml(), os.path.join(tmpdir_mpi, "vacuum"))
    V = np.genfromtxt(os.path.join(tmpdir_mpi, "vacuum", "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
    dv = fl["vy"][-1] - V[V["body"] == "flyer"]["vy"][-1]
    assert 0.05 < dv < 1.0, dv
    steps = sorted(f for f in os.listdir(tmpdir_mpi) if f.startswith("markers_"))
    res = None
    if COMM.rank == 0:
        with h5py.File(os.path.join(tmpdir_mpi, steps[-1]), "r") as f:
            dmg, ply = f["markers/damage"][...], f["markers/ply"][...]
        c0 = read_cells(os.path.join(tmpdir_mpi, steps[0]), "pressure")["values"]
        f0 = read_cells(os.path.join(tmpdir_mpi, steps[0]), "volume_fraction:air")["values"]
        pure = np.abs(f0 - 1.0) < 1e-12
        res = (float(dmg[ply >= 0].max()), float(dmg[ply < 0].max()), int(pure.sum()),
               float(np.abs(c0[pure] - 101325.0).max()), all(picture_ok(p, 3) for p in out["pngs"]))
    dmax, dfly, npure, perr, ok = COMM.bcast(res, root=0)
    assert dmax == 1.0 and dfly == 0.0
    assert npure > 0.9 * 96 * 64 and perr <= 1e-9 * 101325.0
    names = sorted(os.path.basename(p) for p in out["pngs"])
    assert names == ["after.png", "before.png", "cells_air.png", "cells_pressure.png", "damage.png", "history.png",
                     "velocity.png"]
    assert ok


def test_sphere_plate_axi_end_to_end(tmpdir_mpi):
    """The axisymmetric example (a copper sphere onto a steel plate, in
    contact) coarse (0.5 mm cells) to 4 us on 2 ranks: the sphere's full-revolution mass
    4/3 pi R^3 rho, mass and axial momentum conserved (free faces; the axis acts
    on v_r only), the sphere slowed, the plate plastically struck, the total
    energy never gained and lost only to the 1% PIC share (measured -9.3%;
    0.0 PIC: -2.2%), and the pictures drawn
    (before, after, velocity by impact(); pressure, plastic strain by the
    example's draw_fields)."""
    from plyshock.cli import impact
    scene = sphere_plate_axi.setup(cell=0.5e-3, t_end=4e-6, output_interval=2e-6).validate()
    out = impact(scene, tmpdir_mpi, sphere_plate_axi.ZOOM, "sphere")
    sphere_plate_axi.draw_fields(tmpdir_mpi)
    H = np.genfromtxt(os.path.join(tmpdir_mpi, "history.csv"), delimiter=",", names=True)
    B = np.genfromtxt(os.path.join(tmpdir_mpi, "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
    sp = B[B["body"] == "sphere"]
    M = 8930.0 * 4.0 / 3.0 * np.pi * 3e-3**3
    assert abs(sp["mass"][0] - M) <= 2e-6 * M
    assert H["lost_mass"][-1] == 0.0
    assert abs(H["mass"][-1] - H["mass"][0]) <= 1e-12 * H["mass"][0]
    # sphere and plate in contact: a field's nodes lighter than run.mass_threshold drop their force
    # (tests/test_contact.py), measured 2.4e-10 of the axial momentum (bonded: below 1e-10)
    assert abs(H["py"][-1] - H["py"][0]) <= 1e-9 * abs(H["py"][0])
    assert np.isclose(sp["vy"][0], -600.0, rtol=1e-12) and -600.0 < sp["vy"][-1] < -100.0
    assert 0.85 < H["total"][-1] / H["total"][0] < 1.005
    steps = sorted(f for f in os.listdir(tmpdir_mpi) if f.startswith("markers_"))
    with h5py.File(os.path.join(tmpdir_mpi, steps[-1]), "r") as f:
        plate = f["markers/body"][...] == 0
        assert f["markers/plastic_strain"][...][plate].max() > 0.1
    pngs = out["pngs"] + [os.path.join(tmpdir_mpi, n + ".png") for n in ("pressure", "plastic")]
    assert sorted(os.path.basename(p) for p in pngs) == ["after.png", "before.png", "plastic.png", "pressure.png", "velocity.png"]
    ok = all(picture_ok(p, 3) for p in pngs) if COMM.rank == 0 else None
    assert COMM.bcast(ok, root=0)
