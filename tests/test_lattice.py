"""The lattice fill (insertion: lattice, points_per_cell: n), the insertion
other MPM codes use and the exact one is measured against: n^dim points per
cell, each a marker with its lattice sub-cell's volume when it lies inside the
body, in the ply containing it.  Checked against an independent numpy
enumeration of the lattice, on 2 ranks and against 1 rank."""
import os

import h5py
import numpy as np
import pytest
import yaml
from mpi4py import MPI

from plyshock import Body, Box, DeckError, Frame, Grid, Laminate, Material, Scene, Sphere
from plyshock import core
from plyshock.deck import load_text
from conftest import run_cli
from helpers import gather, laminate_frame, random_laminate_scene

COMM = MPI.COMM_WORLD


def lattice_points(scene, n):
    """Every lattice point of the grid (cell by cell, n per cell and direction)
    and its sub-cell volume, built here from the grid alone."""
    g, dim = scene.grid, scene.dimension
    axes = []
    for a in range(dim):
        h = (g.upper[a] - g.lower[a]) / g.cells[a]
        k = np.arange(g.cells[a] * n)
        axes.append(g.lower[a] + (k // n) * h + (k % n + 0.5) * (h / n))
    X = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
    return X, float(np.prod(g.h)) / n**dim


@pytest.mark.parametrize("dim,n", [(2, 1), (2, 3), (3, 2)])
def test_a_box_on_cell_faces_gets_n_to_the_dim_points_per_cell(dim, n):
    """A box whose faces lie on cell faces covers its cells fully: exactly n^dim
    markers per cell, at the lattice sub-cell centres, each with volume h^dim/n^dim
    and mass rho times it; `plyshock check` predicts the count."""
    cells = [10, 8, 6][:dim]
    upper = [1.0, 0.8, 0.6][:dim]
    lo, hi = [0.2, 0.1, 0.2][:dim], [0.7, 0.6, 0.5][:dim]
    scene = Scene(dim, Grid([0.0] * dim, upper, cells), [Material("cu", preset="OFHC-copper")],
                  [Body("b", box=Box(lo, hi), material="cu", insertion="lattice", points_per_cell=n)]).validate()
    m = core.initialize(scene)
    covered = int(np.prod([round((b - a) / 0.1) for a, b in zip(lo, hi)]))
    assert m.stats["markers"] == covered * n**dim
    counts, _ = core.count_markers(scene, m.cs)
    assert counts.sum() == m.stats["markers"]
    f = gather(m, ["x", "mass", "volume", "id"])
    vol = 0.1**dim / n**dim
    assert np.allclose(f["volume"][:, 0], vol, rtol=1e-14, atol=0)
    assert np.allclose(f["mass"][:, 0], 8930.0 * vol, rtol=1e-14, atol=0)
    # the markers are the lattice points inside the box, each once
    X, _ = lattice_points(scene, n)
    inside = X[np.all((X >= lo) & (X < hi), axis=1)]
    got = f["x"][np.lexsort(f["x"].T[::-1])]
    want = inside[np.lexsort(inside.T[::-1])]
    assert got.shape == want.shape and np.abs(got - want).max() <= 1e-14
    assert len(np.unique(f["id"][:, 0])) == len(f["id"])


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("n", [1, 3])
def test_each_point_goes_to_the_ply_containing_it(dim, n):
    """A random oblique laminate clipped by the grid: the markers are exactly the
    lattice points inside it (numpy, frame coordinates), each in the ply whose
    slab z_k <= e3.(x - o) < z_(k+1) holds it, with its sub-cell's volume and
    the ply material's density."""
    rng = np.random.default_rng(31 * dim + n)
    scene = random_laminate_scene(dim, rng, cells_range=(12, 18))
    b = scene.bodies[0]
    b.insertion, b.points_per_cell, b.subdivision, b.volume_tolerance, b.sliver_fraction = "lattice", n, None, None, None
    scene.validate()
    m = core.initialize(scene)
    f = gather(m, ["x", "mass", "volume", "ply", "id"])
    o, axes = laminate_frame(b, dim)
    X, vol = lattice_points(scene, n)
    q = (X - o) @ axes.T
    size = list(b.laminate.size) + [b._z[-1]]
    inside = np.all((q >= 0) & (q < np.array(size)), axis=1)
    # a point within round-off of a face may fall either way: leave those out of the comparison
    near = np.any(np.abs(q[:, :, None] - np.array([0.0] + list(b._z[1:]))[None, None, :]).min(axis=2) < 1e-12, axis=1) | \
        np.any(np.abs(q - np.array(size)) < 1e-12, axis=1)
    ply_np = np.searchsorted(np.array(b._z), q[:, -1], side="right") - 1
    key = lambda x: np.round(x / 1e-9).astype(np.int64)
    want = {tuple(k): p for k, p in zip(key(X[inside & ~near]), ply_np[inside & ~near])}
    got = {tuple(k): p for k, p in zip(key(f["x"]), f["ply"][:, 0])}
    assert len(want) > 10
    for k, p in want.items():
        assert got.get(k) == p, (k, got.get(k), p)
    assert len(got) - len(want) <= int(near.sum())
    assert np.allclose(f["volume"][:, 0], vol, rtol=1e-14, atol=0)
    assert np.allclose(f["mass"][:, 0], 1570.0 * vol, rtol=1e-14, atol=0)
    assert len(np.unique(f["id"][:, 0])) == len(f["id"])


def test_higher_priority_bodies_take_their_points_and_touching_bodies_share_none():
    """A disk of higher priority over a plate: the plate loses exactly the lattice
    points inside the disk; two boxes touching on a lattice line (n odd puts points
    on cell centres) claim each such point once; total mass = rho x points x volume."""
    n = 3
    scene = Scene(2, Grid([0, 0], [1, 1], [10, 10]), [Material("cu", preset="OFHC-copper")],
                  [Body("plate", box=Box([0.1, 0.1], [0.9, 0.55]), material="cu", insertion="lattice", points_per_cell=n),
                   Body("top", box=Box([0.1, 0.55], [0.9, 0.8]), material="cu", insertion="lattice", points_per_cell=n),
                   Body("disk", sphere=Sphere([0.43, 0.3], 0.1712), material="cu", priority=1, insertion="lattice",
                        points_per_cell=n)]).validate()
    m = core.initialize(scene)
    f = gather(m, ["x", "body"])
    X, vol = lattice_points(scene, n)
    in_disk = np.hypot(X[:, 0] - 0.43, X[:, 1] - 0.3) < 0.1712
    in_plate = (X[:, 0] >= 0.1) & (X[:, 0] < 0.9) & (X[:, 1] >= 0.1) & (X[:, 1] < 0.55) & ~in_disk
    in_top = (X[:, 0] >= 0.1) & (X[:, 0] < 0.9) & (X[:, 1] >= 0.55) & (X[:, 1] < 0.8)
    assert np.any(np.isclose(X[:, 1], 0.55))          # points lie on the shared face
    counts = np.bincount(f["body"][:, 0], minlength=3)
    assert list(counts) == [int(in_plate.sum()), int(in_top.sum()), int(in_disk.sum())]
    assert len(f["x"]) == len(np.unique(np.round(f["x"] / 1e-9), axis=0))


def lattice_deck(dim):
    g = {2: {"lower": [0, 0], "upper": [0.03, 0.02], "cells": [33, 25]},
         3: {"lower": [0, 0, 0], "upper": [0.012, 0.010, 0.008], "cells": [14, 11, 9]}}[dim]
    frame = {2: {"origin": [0.004, 0.004], "axis3": [0.0, 0.012], "plane13": [0.03, 0.0147]},
             3: {"origin": [0.001, 0.001, 0.002], "axis3": [0.003, 0.002, 0.01], "plane13": [0.02, 0.004, 0.001]}}[dim]
    return {"dimension": dim, "grid": g,
            "materials": [{"name": "cfrp", "preset": "IM7/8552"}, {"name": "steel", "preset": "4340-steel"}],
            "bodies": [{"name": "plate", "insertion": "lattice", "points_per_cell": 3, "clip": True,
                        "laminate": {"frame": frame, "size": [0.02] * (dim - 1), "layup": "[0/90]s",
                                     "ply_thickness": 0.3e-3, "ply_material": "cfrp"}},
                       {"name": "ball", "material": "steel", "insertion": "lattice", "points_per_cell": 2, "priority": 1,
                        "sphere": {"center": [0.008, 0.006, 0.005][:dim], "radius": 0.002}}]}


@pytest.mark.parametrize("dim", [2, 3])
def test_lattice_markers_are_the_same_on_1_and_2_ranks(dim, tmpdir_mpi):
    deck = os.path.join(tmpdir_mpi, f"lattice{dim}.yaml")
    if COMM.rank == 0:
        with open(deck, "w") as f:
            f.write("# plyshock test deck; SI units (m, kg, s, Pa, K)\n" + yaml.safe_dump(lattice_deck(dim)))
    COMM.Barrier()
    rc, so, se = run_cli(["check", deck])
    assert rc == 0, se
    predicted = int(so.split("expected markers: ")[1].split(",")[0])
    sets = []
    for k in (1, 2):
        out = os.path.join(tmpdir_mpi, f"l{dim}_{k}.h5")
        rc, so, se = run_cli(["init", deck, "-o", out], ranks=k)
        assert rc == 0, se
        with h5py.File(out, "r") as f:
            g = f["markers"]
            order = np.argsort(g["id"][...])
            sets.append({n: g[n][...][order] for n in ("id", "x", "mass", "volume", "ply", "body", "axis1")})
    assert len(sets[0]["id"]) == predicted > 100
    for n in sets[0]:
        assert np.array_equal(sets[0][n], sets[1][n]), n


BAD = [
    ({"insertion": "grid"}, "bodies[0].insertion", "must be one of exact|lattice"),
    ({"points_per_cell": 2}, "bodies[0].points_per_cell", "applies to insertion: lattice only"),
    ({"insertion": "lattice", "points_per_cell": 0}, "bodies[0].points_per_cell", "allowed [1, 16]"),
    ({"insertion": "lattice", "points_per_cell": 17}, "bodies[0].points_per_cell", "allowed [1, 16]"),
    ({"insertion": "lattice", "points_per_cell": 2.5}, "bodies[0].points_per_cell", "whole number"),
    ({"insertion": "lattice", "subdivision": 2}, "bodies[0].subdivision", "applies to insertion exact only"),
    ({"insertion": "lattice", "sliver_fraction": 0.1}, "bodies[0].sliver_fraction", "applies to insertion exact only"),
]


@pytest.mark.parametrize("keys,path,words", BAD)
def test_bad_lattice_input_names_the_key_and_range(keys, path, words):
    d = {"dimension": 2, "grid": {"lower": [0, 0], "upper": [1, 1], "cells": [4, 4]},
         "materials": [{"name": "cu", "preset": "OFHC-copper"}],
         "bodies": [{"name": "b", "material": "cu", "box": {"lower": [0.1, 0.1], "upper": [0.6, 0.6]}, **keys}]}
    with pytest.raises(DeckError) as e:
        load_text(yaml.safe_dump(d))
    assert e.value.path == path, str(e.value)
    assert words in str(e.value), str(e.value)


def test_bad_lattice_input_exits_2_before_any_work(tmpdir_mpi):
    d = lattice_deck(2)
    d["bodies"][0]["points_per_cell"] = 40
    deck = os.path.join(tmpdir_mpi, "bad.yaml")
    if COMM.rank == 0:
        with open(deck, "w") as f:
            yaml.safe_dump(d, f)
    COMM.Barrier()
    rc, so, se = run_cli(["init", deck, "-o", os.path.join(tmpdir_mpi, "bad.h5")], ranks=2)
    assert rc == 2 and "Traceback" not in se and "bodies[0].points_per_cell: 40 is out of range; allowed [1, 16]" in se, se
    assert not os.path.exists(os.path.join(tmpdir_mpi, "bad.h5"))
