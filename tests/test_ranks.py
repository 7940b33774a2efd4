"""The marker set does not depend on the rank count: `mpiexec -n k plyshock init`
for k = 1, 2, 3 writes the same markers (same ids, bitwise-equal fields)."""
import os

import h5py
import numpy as np
import pytest
import yaml
from mpi4py import MPI

from conftest import run_cli

DECKS = {
    3: {
        "dimension": 3,
        "grid": {"lower": [0, 0, -0.004], "upper": [0.012, 0.010, 0.006], "cells": [14, 11, 12],
                 "boundary": {"x-": "symmetry", "y-": "symmetry"}},
        "materials": [{"name": "cfrp", "preset": "IM7/8552"}, {"name": "cu", "preset": "OFHC-copper"},
                      {"name": "steel", "preset": "4340-steel"}],
        "bodies": [
            {"name": "plate", "subdivision": 2, "priority": 0, "clip": True,
             "laminate": {"frame": {"origin": [-0.001, -0.0012, -0.0011], "axis3": [0.0003, 0.0002, 0.01],
                                    "plane13": [0.02, 0.001, -0.0004]},
                          "size": [0.02, 0.02], "layup": "[0/±45/90]", "ply_thickness": 0.4e-3, "ply_material": "cfrp"}},
            {"name": "ball", "material": "cu", "sphere": {"center": [0.0, 0.0, 0.0015], "radius": 0.0025},
             "velocity": [0, 0, -600], "priority": 1},
            {"name": "block", "material": "steel", "box": {"lower": [0.008, 0.006, 0.003], "upper": [0.011, 0.009, 0.005]}},
        ],
    },
    2: {
        "dimension": 2,
        "grid": {"lower": [0, 0], "upper": [0.03, 0.02], "cells": [33, 25]},
        "materials": [{"name": "cfrp", "preset": "IM7/8552"}, {"name": "steel", "preset": "4340-steel"}],
        "bodies": [
            {"name": "plate", "subdivision": 3,
             "laminate": {"frame": {"origin": [0.004, 0.004], "axis3": [0.0, 0.012], "plane13": [0.03, 0.0147]},
                          "size": [0.02], "layup": "[0/90]s", "ply_thickness": 0.7e-3, "ply_material": "cfrp"}},
            {"name": "disk", "material": "steel", "sphere": {"center": [0.022, 0.004], "radius": 0.003}},
        ],
    },
}
FIELDS = ["x", "v", "mass", "volume", "body", "ply", "material", "axis1", "axis2", "axis3"]


@pytest.mark.parametrize("dim", [2, 3])
def test_same_markers_on_1_2_3_ranks(dim, tmpdir_mpi):
    deck = os.path.join(tmpdir_mpi, f"scene{dim}.yaml")
    if MPI.COMM_WORLD.rank == 0:
        with open(deck, "w") as f:
            f.write("# plyshock test deck; SI units (m, kg, s, Pa, K)\n" + yaml.safe_dump(DECKS[dim]))
    MPI.COMM_WORLD.Barrier()
    sets = []
    for k in (1, 2, 3):
        out = os.path.join(tmpdir_mpi, f"m{dim}_{k}.h5")
        rc, so, se = run_cli(["init", deck, "-o", out], ranks=k)
        assert rc == 0, se
        with h5py.File(out, "r") as f:
            g = f["markers"]
            order = np.argsort(g["id"][...])
            sets.append({"id": g["id"][...][order], **{n: g[n][...][order] for n in FIELDS}})
            assert int(f.attrs["ranks"]) == k
    ref = sets[0]
    assert len(ref["id"]) > 100 and len(np.unique(ref["id"])) == len(ref["id"])
    for s in sets[1:]:
        assert np.array_equal(s["id"], ref["id"])
        for n in FIELDS:
            assert np.array_equal(s[n], ref[n]), n


@pytest.mark.parametrize("dim", [2, 3])
def test_the_grid_partition_balances_the_markers(dim):
    """A body in the first third of the domain: PETSc's even split would give
    one rank (nearly) every marker; the partition moves the cut so both ranks
    hold a like share, and the exact masses are unchanged."""
    from plyshock import Body, Box, Grid, Material, Scene
    from plyshock import core
    comm = MPI.COMM_WORLD
    cells = [48, 6, 6][:dim]
    upper = [0.048, 0.006, 0.006][:dim]
    scene = Scene(dim, Grid([0.0] * dim, upper, cells), [Material("al", preset="6061-T6-aluminum")],
                  [Body("b", box=Box([0.001] + [0.0] * (dim - 1), [0.016] + upper[1:]), material="al", subdivision=2)]).validate()
    m = core.initialize(scene)
    n = comm.allgather(m.sw.getLocalSize())
    assert sum(n) == 15 * 6 ** (dim - 1) * 2 ** dim
    if comm.size > 1:
        assert min(n) > 0 and max(n) / min(n) < 1.5, n
    M = comm.allreduce(core.local_fields(m, ["mass"])["mass"].sum())
    exact = 2703.0 * 0.015 * 0.006 ** (dim - 1)
    assert abs(M - exact) <= 1e-12 * exact
