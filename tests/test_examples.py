"""The method's two example scenes, at small size on 2 ranks: exact ply and
body masses, body momenta, and the orientation pictures (rendered off screen)."""
import os

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
