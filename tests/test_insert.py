"""Exact insertion, on the rank count the suite runs with (2): mass and centroid
of every ply against an independent Qhull clip, markers inside their ply and
cell and on the rank owning that cell, unique ids, curved bodies to tolerance,
slivers, priorities."""
import numpy as np
import pytest

from plyshock import Body, Box, Cylinder, Frame, Grid, Laminate, Material, Scene, Sphere
from plyshock import core
from helpers import gather, laminate_frame, ply_bounds, random_laminate_scene
from reference import box_halfspaces, convex_moments, oriented_halfspaces

REL = 1e-12      # mass of a ply, relative
CEN = 1e-12      # centroid of a ply and marker containment, relative to the domain size


def decode_cells(scene, ids, body, s):
    """Cell index (n, dim) of each marker from its id (see src/insert.c)."""
    P = max([len(b.laminate.plies) for b in scene.bodies if b.kind == "laminate"] + [0]) + 1
    S = ids // P // len(scene.bodies)
    nx = scene.grid.cells[0] * s
    ny = scene.grid.cells[1] * s
    I = np.stack([S % nx, (S // nx) % ny, S // (nx * ny)], axis=1)[:, : scene.dimension]
    return I // s


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("seed", range(5))
def test_plies_exact_mass_centroid_and_containment(dim, seed, comm):
    rng = np.random.default_rng(100 * dim + seed)
    scene = random_laminate_scene(dim, rng, boundary_kind="mixed")
    m = core.initialize(scene)
    f = gather(m, ["x", "mass", "volume", "ply", "id", "body", "material"])
    body = scene.bodies[0]
    rho = scene.materials[0].density
    size = max(np.subtract(scene.grid.upper, scene.grid.lower))
    o, axes = laminate_frame(body, dim)
    A0, b0 = box_halfspaces(scene.grid.lower, scene.grid.upper)
    nonempty = 0
    for k in range(len(body.laminate.plies)):
        lo, hi = ply_bounds(body, k, dim)
        A1, b1 = oriented_halfspaces(o, axes, lo, hi)
        V, c = convex_moments(np.r_[A0, A1], np.r_[b0, b1])
        sel = f["ply"][:, 0] == k
        M = f["mass"][sel, 0].sum()
        if V == 0.0:
            assert M == 0.0
            continue
        nonempty += 1
        assert abs(M - rho * V) <= REL * rho * V, (k, M, rho * V)
        cm = (f["mass"][sel] * f["x"][sel]).sum(axis=0) / M
        assert np.abs(cm - c).max() <= CEN * size, (k, cm, c)
        # every marker inside its own ply (frame coordinates within the ply's bounds)
        q = (f["x"][sel] - o) @ axes.T
        assert np.all(q >= np.array(lo) - CEN * size) and np.all(q <= np.array(hi) + CEN * size)
    assert nonempty > 0
    # mass = rho V for each marker, and a positive volume
    assert np.all(f["volume"][:, 0] > 0)
    assert np.allclose(f["mass"][:, 0], rho * f["volume"][:, 0], rtol=1e-15, atol=0)
    # every marker inside its own cell (decoded from its id)
    cell = decode_cells(scene, f["id"][:, 0], 0, body.subdivision)
    h = np.array(scene.grid.h)
    clo = np.array(scene.grid.lower) + cell * h
    assert np.all(f["x"] >= clo - CEN * size) and np.all(f["x"] <= clo + h + CEN * size)
    # ids unique over all ranks
    assert len(np.unique(f["id"][:, 0])) == len(f["id"])


@pytest.mark.parametrize("dim", [2, 3])
def test_markers_live_on_the_rank_owning_their_cell(dim, comm):
    rng = np.random.default_rng(7 + dim)
    scene = random_laminate_scene(dim, rng, cells_range=(8, 14))
    m = core.initialize(scene)
    f = core.local_fields(m, ["id"])
    cs, ce = m.cs.owned_cells(m.da)
    cell = decode_cells(scene, f["id"][:, 0], 0, scene.bodies[0].subdivision)
    assert np.all(cell >= np.array(cs[:dim])) and np.all(cell < np.array(ce[:dim]))
    # the ranks between them own every cell once
    n_owned = np.prod(np.subtract(ce, cs)[:dim])
    assert comm.allreduce(int(n_owned)) == int(np.prod(scene.grid.cells))
    # no marker lost: the serial count (plyshock check) equals the insertion
    counts, _ = core.count_markers(scene, m.cs)
    assert counts.sum() == m.stats["markers"] == comm.allreduce(len(f["id"]))


def ball_scene(dim, r, tol, cells=12, center=None):
    c = center or [0.5, 0.47, 0.52][:dim]
    return Scene(dim, Grid([0.0] * dim, [1.0] * dim, [cells] * dim), [Material("cu", preset="OFHC-copper")],
                 [Body("ball", sphere=Sphere(c, r), material="cu", volume_tolerance=tol)]).validate()


@pytest.mark.parametrize("dim", [2, 3])
def test_sphere_mass_within_tolerance_and_converges(dim, comm):
    errors = []
    for tol in (1e-3, 1e-6, 1e-9):
        for r in (0.3, 0.123):
            scene = ball_scene(dim, r, tol)
            m = core.initialize(scene)
            M = comm.allreduce(core.local_fields(m, ["mass"])["mass"].sum())
            exact = 8930.0 * (4.0 / 3.0 * np.pi * r**3 if dim == 3 else np.pi * r * r)
            err = abs(M - exact) / exact
            assert err <= tol, (dim, r, tol, err)
            if tol == 1e-6:      # the default: the issue asks 1e-5
                assert err <= 1e-5
            errors.append(err)
    # refinement: the finest tolerance is far better than the coarsest
    assert max(errors[-2:]) < 1e-3 * max(errors[:2]) + 1e-12


def test_cylinder_volumes(comm):
    # 3D: an oblique cylinder, curved mantle to tolerance, flat caps exact
    a = np.array([0.3, -0.5, 0.8]); a /= np.linalg.norm(a)
    base = np.array([0.5, 0.5, 0.5]) - 0.25 * a
    sc = Scene(3, Grid([0, 0, 0], [1, 1, 1], [10, 10, 10]), [Material("cu", preset="OFHC-copper")],
               [Body("rod", cylinder=Cylinder(base.tolist(), a.tolist(), 0.17, 0.5), material="cu")]).validate()
    M = comm.allreduce(core.local_fields(core.initialize(sc), ["mass"])["mass"].sum())
    exact = 8930.0 * np.pi * 0.17**2 * 0.5
    assert abs(M - exact) / exact <= 1e-5
    # 2D: the axial section, a rectangle 2R x L, exact
    sc = Scene(2, Grid([0, 0], [1, 1], [9, 11]), [Material("cu", preset="OFHC-copper")],
               [Body("rod", cylinder=Cylinder([0.3, 0.2], [0.6, 0.8], 0.1, 0.55), material="cu")]).validate()
    M = comm.allreduce(core.local_fields(core.initialize(sc), ["mass"])["mass"].sum())
    exact = 8930.0 * 0.2 * 0.55
    assert abs(M - exact) <= REL * exact


def test_slivers_merged_within_the_cell_and_mass_exact(comm):
    # an axis-aligned 2D plate whose interfaces sit 1e-9 of a cell above
    # sub-cell lines (merged into the sub-cell above) and cell lines (kept)
    h = 0.1
    y0 = 0.3 + 1e-10           # just above the cell line y = 0.3
    lam = Laminate(Frame([0.1, y0], [0.1, y0 + 1], [0.5, y0]), [0.8],
                   [__import__("plyshock").Ply("cfrp", 0.05, [[3, 0]]), __import__("plyshock").Ply("cfrp", 0.1, [[3, 90]])])
    sc = Scene(2, Grid([0, 0], [1, 1], [10, 10]), [Material("cfrp", preset="IM7/8552")],
               [Body("plate", laminate=lam, subdivision=2)]).validate()
    m = core.initialize(sc)
    f = gather(m, ["mass", "volume", "ply"])
    rho = sc.materials[0].density
    for k, t in enumerate((0.05, 0.1)):
        M = f["mass"][f["ply"][:, 0] == k, 0].sum()
        assert abs(M - rho * 0.8 * t) <= REL * rho * 0.8 * t
    # ply 0 ends at y0 + 0.05 = 0.35 + 1e-10: a sliver above the sub-cell line y = 0.35,
    # merged into ply 0's piece below it in the same cell
    assert m.stats["slivers_merged"] > 0
    vsub = (h / 2) ** 2
    small = f["volume"][:, 0] < 1e-6 * vsub
    assert small.sum() == m.stats["slivers_kept"]
    assert m.stats["pieces"] == m.stats["markers"] + m.stats["slivers_merged"]


def test_priority_takes_the_overlap_exactly(comm):
    rng = np.random.default_rng(42)
    dim = 3
    base = random_laminate_scene(dim, rng)
    body = base.bodies[0]
    o, axes = laminate_frame(body, dim)
    centre = o + axes.T @ (np.array(list(body.laminate.size) + [body._z[-1]]) / 2)
    box = Box((centre - 0.13).tolist(), (centre + 0.11).tolist())
    base.materials.append(Material("steel", preset="4340-steel"))
    body.priority = 0
    base.bodies.append(Body("insert", box=box, material="steel", priority=1))
    base.validate()
    m = core.initialize(base)
    f = gather(m, ["mass", "ply", "body"])
    A0, b0 = box_halfspaces(base.grid.lower, base.grid.upper)
    Ab, bb = box_halfspaces(box.lower, box.upper)
    rho = base.materials[0].density
    for k in range(len(body.laminate.plies)):
        lo, hi = ply_bounds(body, k, dim)
        A1, b1 = oriented_halfspaces(o, axes, lo, hi)
        V, _ = convex_moments(np.r_[A0, A1], np.r_[b0, b1])
        Vx, _ = convex_moments(np.r_[A0, A1, Ab], np.r_[b0, b1, bb])
        M = f["mass"][(f["body"][:, 0] == 0) & (f["ply"][:, 0] == k), 0].sum()
        assert abs(M - rho * (V - Vx)) <= REL * rho * V + 1e-300
    Vbox, _ = convex_moments(np.r_[A0, Ab], np.r_[b0, bb])
    Mb = f["mass"][f["body"][:, 0] == 1, 0].sum()
    assert abs(Mb - 7810.0 * Vbox) <= REL * 7810.0 * Vbox


def test_touching_bodies_do_not_overlap(comm):
    sc = Scene(2, Grid([0, 0], [1, 1], [7, 9]), [Material("steel", preset="4340-steel")],
               [Body("a", box=Box([0.1, 0.1], [0.5, 0.5]), material="steel"),
                Body("b", box=Box([0.5, 0.2], [0.9, 0.7]), material="steel")]).validate()
    m = core.initialize(sc)
    M = comm.allreduce(core.local_fields(m, ["mass"])["mass"].sum())
    assert abs(M - 7810.0 * (0.16 + 0.2)) <= REL * 7810.0 * 0.36
