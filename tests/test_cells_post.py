"""`plyshock plot --cells`: a run step's cell field drawn under its markers.

The files are written here by h5py in the run's layout (markers_NNNNN.h5 with
the deck recorded, grid_NNNNN.h5 with /cells as in issue 12's contract), with
fields whose pictures are known: the colours drawn are the colour map's ends
in the known proportions, a layer of a 3D grid is the one asked for, cells
without cell material are grey, and bad values of the options are named
errors (exit 2).  The pictures are rendered on rank 0; every rank asserts."""
import os

import h5py
import numpy as np
import yaml
from mpi4py import MPI

from conftest import clean, run_cli

COMM = MPI.COMM_WORLD
MAGMA_TOP = (252, 253, 191)        # matplotlib's magma at 1 and 0 (the cells' colour map), 8 bit
MAGMA_BOTTOM = (0, 0, 4)
GREY = (211, 211, 211)             # lightgray: no cell material


def write_step(d, dim, lower, upper, vf, names, pressure=None, density=None, markers=((0.0,) * 3,), n=3, t=1.5e-6):
    """markers_0000n.h5 and grid_0000n.h5 in d, as a run writes them (the
    fields a picture reads).  vf is (ny, nx, nmat) or (nz, ny, nx, nmat)."""
    cells = list(vf.shape[:-1][::-1])
    deck = yaml.safe_dump({"dimension": dim, "grid": {"lower": list(lower), "upper": list(upper), "cells": cells}})
    x = np.array([m[:dim] for m in markers], float)
    mpath = os.path.join(d, f"markers_{n:05d}.h5")
    with h5py.File(mpath, "w") as f:
        f.attrs["time"] = t
        f.attrs["deck"] = deck
        g = f.create_group("markers")
        g["x"] = x
        g["v"] = np.zeros_like(x)
        g["id"] = np.arange(len(x), dtype=np.int64)
        g["body"] = np.zeros(len(x), np.int32)
        g["ply"] = -np.ones(len(x), np.int32)
        g["material"] = np.zeros(len(x), np.int32)
        g["mass"] = np.ones(len(x))
        g["volume"] = np.full(len(x), 1e-9)
        g.attrs["body_names"] = ["plate"]
        g.attrs["material_names"] = ["al"]
    shape = vf.shape[:-1]
    with h5py.File(os.path.join(d, f"grid_{n:05d}.h5"), "w") as f:
        f.attrs["time"] = t
        c = f.create_group("cells")
        c["volume_fraction"] = vf
        c["volume_fraction"].attrs["materials"] = names
        c["density"] = np.zeros(shape) if density is None else density
        c["pressure"] = np.zeros(shape) if pressure is None else pressure
        c["specific_energy"] = np.ones(shape)
        c["velocity"] = np.zeros(shape + (dim,))
    return mpath


def colours(png):
    """Pixel counts near the colour map's top and bottom colours and grey, and the image."""
    import matplotlib.image as mpimg
    img = (mpimg.imread(png)[..., :3] * 255).round().astype(int)

    def near(c):
        return int((np.abs(img - np.array(c)).max(axis=-1) <= 6).sum())
    return {"top": near(MAGMA_TOP), "bottom": near(MAGMA_BOTTOM), "grey": near(GREY), "img": img}


def blast_2d(d):
    """A 20 x 10 mm grid of 1 mm cells: a charge (hp) in x < 5 mm at 100 MPa,
    air at 0.1 MPa beyond (its density rising with y), no cell material in
    12 <= x < 14 mm (a marker body)."""
    ny, nx = 10, 20
    vf = np.zeros((ny, nx, 2))
    vf[:, :5, 1] = 1.0
    vf[:, 5:, 0] = 1.0
    vf[:, 12:14, :] = 0.0
    p = np.where(vf[..., 1] > 0, 1e8, 1e5)
    rho = np.where(vf[..., 1] > 0, 50.0, 1.2 * (1.0 + 4.0 * np.arange(ny))[:, None])     # air: denser up the grid
    rho[:, 12:14] = p[:, 12:14] = 0.0
    return write_step(d, 2, (0.0, 0.0), (0.02, 0.01), vf, ["air", "hp"], pressure=p, density=rho,
                      markers=[(0.013, 0.001 + 0.002 * k) for k in range(5)])


def plot(args):
    rc, out, err = run_cli(["plot"] + args)
    assert rc == 0 and clean(err), err
    return rc


def test_cells_2d_colours_and_proportions(tmpdir_mpi):
    """volume_fraction:hp and :air draw the map's top colour over 5 and 13 of
    the 20 columns (the rest of air's: 2 empty columns at 0); pressure draws
    the 2 empty columns grey, volume fraction never; pressure and density
    differ in their picture."""
    m = blast_2d(tmpdir_mpi) if COMM.rank == 0 else None
    m = COMM.bcast(m, root=0)
    pngs = {k: os.path.join(tmpdir_mpi, k.replace(":", "_") + ".png")
            for k in ("volume_fraction:hp", "volume_fraction:air", "pressure", "density")}
    for k, png in pngs.items():
        plot([m, "--png", png, "--cells", k])
    res = None
    if COMM.rank == 0:
        c = {k: colours(png) for k, png in pngs.items()}
        res = dict(hp=c["volume_fraction:hp"]["top"], air=c["volume_fraction:air"]["top"],
                   grey_p=c["pressure"]["grey"], top_p=c["pressure"]["top"], grey_vf=c["volume_fraction:hp"]["grey"],
                   diff=float(np.abs(c["pressure"]["img"] - c["density"]["img"]).mean()))
    res = COMM.bcast(res, root=0)
    # top colour over 5 columns for hp, 13 for air (5 markers and the bar's top are a few hundred pixels)
    assert res["hp"] > 50000
    assert abs(res["air"] / res["hp"] - 13 / 5) < 0.05 * 13 / 5, res
    # pressure: the hp columns at the top, the empty columns grey (2 of 5)
    assert abs(res["grey_p"] / res["top_p"] - 2 / 5) < 0.05 * 2 / 5, res
    assert res["grey_vf"] < 0.01 * res["grey_p"]      # volume fraction draws no grey (a few anti-aliased marker pixels)
    assert res["diff"] > 1.0          # pressure and density pictures differ (mean |difference| in 8-bit levels)


def test_cells_2d_read_values(tmpdir_mpi):
    """read_cells gives the dataset's values, NaN where no cell material is
    (except for volume fraction), and the step's geometry from the deck."""
    from plyshock.post import read_cells
    if COMM.rank == 0:
        m = blast_2d(tmpdir_mpi)
        c = read_cells(m, "pressure")
        assert c["values"].shape == (10, 20) and np.all(np.isnan(c["values"][:, 12:14]))
        assert np.all(c["values"][:, :5] == 1e8) and np.all(c["values"][:, 5:12] == 1e5)
        assert np.allclose(c["h"], [1e-3, 1e-3], rtol=1e-14) and c["time"] == 1.5e-6
        v = read_cells(m, "volume_fraction:air")["values"]
        assert np.all(v[:, 12:14] == 0.0) and v.sum() == 13 * 10
        assert read_cells(m, "volume_fraction:hp")["title"] == "volume fraction of hp (-)"


def test_cells_3d_layer(tmpdir_mpi):
    """3D: the layer of cells at the y of the --zoom slab's middle is drawn in
    the x-z cut: hp fills only the layer 2 <= y < 3 mm, so a slab there draws
    the map's top colour over the cut and a slab in the first layer none."""
    m = None
    if COMM.rank == 0:
        nz, ny, nx = 6, 4, 8
        vf = np.zeros((nz, ny, nx, 2))
        vf[..., 0] = 1.0
        vf[:, 2, :, :] = [0.0, 1.0]
        m = write_step(tmpdir_mpi, 3, (0.0, 0.0, 0.0), (0.008, 0.004, 0.006), vf, ["air", "hp"],
                       markers=[(0.004, 0.0025, 0.003)])
    m = COMM.bcast(m, root=0)
    a, b = os.path.join(tmpdir_mpi, "in.png"), os.path.join(tmpdir_mpi, "out.png")
    plot([m, "--png", a, "--cells", "volume_fraction:hp", "--view", "xz", "--zoom", "0", "0.002", "0", "0.008", "0.003", "0.006"])
    plot([m, "--png", b, "--cells", "volume_fraction:hp", "--view", "xz", "--zoom", "0", "0", "0", "0.008", "0.001", "0.006"])
    res = COMM.bcast((colours(a)["top"], colours(b)["top"], colours(b)["bottom"]) if COMM.rank == 0 else None, root=0)
    assert res[0] > 100000 and res[1] < 1000 and res[2] > 100000, res


def test_cells_bad_input(tmpdir_mpi):
    """Each bad value is one `plyshock: error:` line naming the option and what is allowed; exit 2, no picture."""
    m = COMM.bcast(blast_2d(tmpdir_mpi) if COMM.rank == 0 else None, root=0)
    png = os.path.join(tmpdir_mpi, "bad.png")
    cases = [
        (["--cells", "temperature"], "--cells: 'temperature' is not a cell field; allowed: volume_fraction:MATERIAL, density, pressure"),
        (["--cells", "volume_fraction"], "--cells: volume_fraction needs a material"),
        (["--cells", "volume_fraction:steel"], "--cells: no cell material 'steel' in "),
        (["--cells", "volume_fraction:steel"], "; allowed: volume_fraction:air|volume_fraction:hp, density"),
        (["--cells", "density:air"], "--cells: 'density:air': only volume_fraction takes a material"),
        (["--cells", "velocity_z"], "--cells: velocity_z in a 2D run"),
        (["--cells", "pressure", "--cells-range", "5", "1"], "--cells-range: 5 1: allowed two finite numbers LO < HI"),
        (["--cells", "pressure", "--cells-log", "--cells-range", "0", "1"], "--cells-range: 0 1: with --cells-log allowed 0 < LO < HI"),
        (["--cells", "velocity_x", "--cells-log"], "--cells-log: a logarithmic scale of velocity_x"),
        (["--cells-log"], "--cells-log: applies to --cells only"),
    ]
    for args, words in cases:
        rc, out, err = run_cli(["plot", m, "--png", png] + args)
        assert rc == 2 and clean(err) and err.startswith("plyshock: error: --") and words in err, (args, err)
        assert len(err.strip().splitlines()) == 1, err
    # a marker file without its grid file (plyshock init writes none), and a grid file without /cells
    if COMM.rank == 0:
        os.rename(os.path.join(tmpdir_mpi, "grid_00003.h5"), os.path.join(tmpdir_mpi, "gone.h5"))
    rc, out, err = run_cli(["plot", m, "--png", png, "--cells", "pressure"])
    assert rc == 2 and clean(err) and "plyshock: error: --cells: needs the grid file of a run's step" in err, err
    if COMM.rank == 0:
        with h5py.File(os.path.join(tmpdir_mpi, "grid_00003.h5"), "w") as f:
            f.attrs["time"] = 1.5e-6
            f["grid/mass"] = np.zeros((3, 3))
    rc, out, err = run_cli(["plot", m, "--png", png, "--cells", "pressure"])
    assert rc == 2 and clean(err) and "has no /cells: the run has no body in cells" in err, err
    assert COMM.bcast(not os.path.exists(png) if COMM.rank == 0 else None, root=0)
    # --help says what --cells takes
    rc, out, err = run_cli(["plot", "--help"])
    assert rc == 0 and "--cells FIELD[:MATERIAL]" in out and "volume_fraction:MATERIAL" in out


def test_captions_state_the_real_marker_counts():
    """Issue 16 item 4: a picture's caption gives the file's marker count, and
    when a zoom box or a cut shows only some, how many of how many (the oblique
    example's "before" once said 3686 markers of a file holding 8418)."""
    from plyshock.post import _count
    keep = np.ones(8418, bool)
    assert _count(keep) == "8,418 markers"
    keep[3686:] = False
    assert _count(keep) == "3,686 of 8,418 markers shown"
