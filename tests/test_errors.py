"""Bad input: a clear error naming the deck key path and the allowed range,
exit status 2, no traceback, nothing written, before any PETSc object."""
import copy
import os

import pytest
import yaml

from plyshock import DeckError
from plyshock import core
from plyshock.deck import load_text
from conftest import run_cli

BASE = {
    "dimension": 2,
    "grid": {"lower": [0, 0], "upper": [0.06, 0.04], "cells": [60, 40],
             "boundary": {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "free"}},
    "materials": [
        {"name": "cfrp", "preset": "IM7/8552"},
        {"name": "glass", "density": 1980,
         "elastic": {"type": "orthotropic", "E1": 43e9, "E2": 9e9, "E3": 9e9, "G12": 4.5e9, "G13": 4.5e9,
                     "G23": 3.5e9, "nu12": 0.27, "nu13": 0.27, "nu23": 0.4}},
        {"name": "steel", "density": 7810, "eos": {"type": "mie-gruneisen", "c0": 4578, "s": 1.33, "gamma0": 1.67},
         "shear_modulus": 77.5e9,
         "strength": {"type": "johnson-cook", "A": 792e6, "B": 510e6, "n": 0.26, "C": 0.014, "m": 1.03, "T_melt": 1793}},
    ],
    "bodies": [
        {"name": "plate", "laminate": {"frame": {"origin": [0.02, 0.005], "axis3": [0.0, 0.025], "plane13": [0.04, 0.025]},
                                       "size": [0.03],
                                       "plies": [{"material": "cfrp", "thickness": 1.0e-3, "rotations": [[3, 0]]},
                                                 {"material": "glass", "thickness": 1.0e-3, "rotations": [[3, 90]]}]},
         "subdivision": 1, "velocity": [0, 0]},
        {"name": "flyer", "material": "steel", "box": {"lower": [0.005, 0.03], "upper": [0.015, 0.035]}, "velocity": [0, -500]},
        {"name": "ball", "material": "steel", "sphere": {"center": [0.045, 0.03], "radius": 2.0e-3}, "velocity": [0, 0]},
    ],
}


def check(d):
    """What `plyshock check` does before any PETSc object: validate, then geometry."""
    scene = load_text(yaml.safe_dump(d))
    core.check_geometry(scene, core.c_scene(scene))
    return scene


def test_base_deck_is_valid():
    s = check(BASE)
    assert [b.kind for b in s.bodies] == ["laminate", "box", "sphere"]


def edit(path, value, delete=False):
    d = copy.deepcopy(BASE)
    keys = path.split(".")
    cur = d
    for k in keys[:-1]:
        cur = cur[int(k)] if k.isdigit() else cur[k]
    last = int(keys[-1]) if keys[-1].isdigit() else keys[-1]
    if delete:
        del cur[last]
    else:
        cur[last] = value
    return d


CASES = [
    # (edit path, value, expected key path in the message, words in the message)
    ("bodies.0.laminate.plies.0.thickness", 0.0, "bodies[0].laminate.plies[0].thickness", "allowed (0"),
    ("bodies.0.laminate.plies.1.thickness", -1e-3, "bodies[0].laminate.plies[1].thickness", "out of range"),
    ("bodies.0.laminate.frame.axis3", [0.02, 0.005], "bodies[0].laminate.frame.axis3", "coincides"),
    ("bodies.0.laminate.frame.plane13", [-0.02, 0.045], "bodies[0].laminate.frame.plane13", "collinear"),
    ("bodies.0.laminate.plies.0.rotations", [[4, 0]], "bodies[0].laminate.plies[0].rotations[0][0]", "1, 2 or 3"),
    ("bodies.0.laminate.plies.0.rotations", [[3, 0], [1, 0], [2, 0]], "bodies[0].laminate.plies[0].rotations", "at most 2"),
    ("bodies.0.laminate.plies.0.material", "cfrq", "bodies[0].laminate.plies[0].material", "did you mean 'cfrp'"),
    ("materials.0.preset", "IM7-8552", "materials[0].preset", "did you mean 'IM7/8552'"),
    ("bodies.1.velocty", [0, 1], "bodies[1].velocty", "did you mean 'velocity'"),
    ("grid.cellz", [1, 1], "grid.cellz", "did you mean 'cells'"),
    ("bodies.1.box", {"lower": [0.1, 0.1], "upper": [0.12, 0.12]}, "bodies[1]", "wholly outside"),
    ("bodies.1.box", {"lower": [0.055, 0.02], "upper": [0.065, 0.025]}, "bodies[1].clip", "face x+"),
    ("bodies.2.sphere", {"center": [0.01, 0.033], "radius": 3e-3}, "bodies[2]", "overlap"),
    ("bodies.0.subdivision", 0, "bodies[0].subdivision", "allowed [1, 64]"),
    ("grid.cells", [0, 40], "grid.cells[0]", "allowed [1"),
    ("grid.upper", [0.0, 0.04], "grid.upper[0]", "must be > lower[0]"),
    ("materials.1.elastic.nu12", 2.5, "materials[1].elastic", "not positive definite"),
    ("materials.2.elastic", {"type": "isotropic", "E": 200e9, "nu": 0.3}, "materials[2].shear_modulus", "keep one"),
    ("bodies.0.laminate.plies", None, "bodies[0].laminate.plies", "required"),
    ("dimension", 4, "dimension", "2 (plane strain) or 3"),
]


@pytest.mark.parametrize("path,value,key,words", CASES)
def test_bad_input_names_key_and_range(path, value, key, words):
    with pytest.raises(DeckError) as e:
        check(edit(path, value))
    assert e.value.path == key, str(e.value)
    assert words in str(e.value), str(e.value)


def test_bad_layup_string():
    d = copy.deepcopy(BASE)
    d["bodies"][0]["laminate"] = {"frame": BASE["bodies"][0]["laminate"]["frame"], "size": [0.03],
                                  "layup": "[0/90", "ply_thickness": 1e-3, "ply_material": "cfrp"}
    with pytest.raises(DeckError) as e:
        check(d)
    assert e.value.path == "bodies[0].laminate.layup"


def test_priority_resolves_an_overlap():
    d = edit("bodies.2.sphere", {"center": [0.01, 0.033], "radius": 3e-3})
    d["bodies"][2]["priority"] = 1
    check(d)   # no error: the ball wins the overlap


def test_clip_true_allows_crossing_and_reports_the_volume():
    d = edit("bodies.1.box", {"lower": [0.055, 0.02], "upper": [0.065, 0.025]})
    d["bodies"][1]["clip"] = True
    s = load_text(yaml.safe_dump(d))
    clipped = core.check_geometry(s, core.c_scene(s))
    assert abs(clipped["flyer"] - 0.005 * 0.005) <= 1e-12 * 0.005 * 0.005 * 2


def test_cli_exit_status_2_no_traceback_nothing_written(tmpdir_mpi):
    deck = os.path.join(tmpdir_mpi, "bad.yaml")
    out = os.path.join(tmpdir_mpi, "bad.h5")
    from mpi4py import MPI
    if MPI.COMM_WORLD.rank == 0:
        with open(deck, "w") as f:
            yaml.safe_dump(edit("bodies.0.laminate.plies.0.thickness", -1.0), f)
    MPI.COMM_WORLD.Barrier()
    for args, ranks in ((["check", deck], None), (["init", deck, "-o", out], 2)):
        rc, so, se = run_cli(args, ranks)
        assert rc == 2, (rc, so, se)
        assert "Traceback" not in se and "bodies[0].laminate.plies[0].thickness" in se
    assert not os.path.exists(out)
