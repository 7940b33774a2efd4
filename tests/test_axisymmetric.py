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


# -------------------------------------------------------------- validation --
def test_valid_decks():
    assert _load(DECK).axisymmetric
    assert not _load(_edit(lambda d: d.pop("geometry"))).axisymmetric
    assert not _load(_edit(lambda d: d.update(geometry="plane-strain"))).axisymmetric
    # an isotropic laminate, and one transversely isotropic about its stacking axis (z)
    _load(_edit(lambda d: d["bodies"].append(_lam("cu"))))
    _load(_edit(lambda d: d["bodies"].append(_lam("quasi", rotations=[[3, 30]]))))


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
]


@pytest.mark.parametrize("edit,path,allowed", BAD)
def test_bad_input_named(edit, path, allowed):
    with pytest.raises(DeckError) as e:
        _load(_edit(edit))
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
