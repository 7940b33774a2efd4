"""The method's two example scenes, at small size on 2 ranks: exact ply and
body masses, body momenta, and the orientation pictures (rendered off screen)."""
import os

import h5py
import numpy as np
from mpi4py import MPI

import oblique_plate_2d
import sphere_plate_3d
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
    assert abs(H[k][-1] - H[k][0]) <= 1e-10 * abs(H[k][0]), (H[k][0], H[k][-1])
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
    assert len(out["pngs"]) == 7
    ok = all(picture_ok(p, 3) for p in out["pngs"]) if COMM.rank == 0 else None
    assert COMM.bcast(ok, root=0)
