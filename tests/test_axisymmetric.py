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
