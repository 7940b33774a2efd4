"""Hostile input (under mpiexec -n 2): guards with named errors against
absurd velocities, grids beyond the index size or memory, decks that are not
text or not a mapping."""
import os
import time

import numpy as np
import pytest
import yaml
from mpi4py import MPI

from plyshock import DeckError
from plyshock.deck import load_text
from conftest import clean, run_cli, write_deck

COMM = MPI.COMM_WORLD

# issue 15's reproducer: one steel box leaving a small grid with free faces at 2 km/s
LOST = {
    "dimension": 2,
    "grid": {"lower": [0, 0], "upper": [0.002, 0.002], "cells": [20, 20]},
    "materials": [{"name": "steel", "preset": "4340-steel"}],
    "bodies": [{"name": "box", "material": "steel", "box": {"lower": [0.0008, 0.0002], "upper": [0.0012, 0.0006]},
                "velocity": [0, -2000]}],
    "run": {"t_end": 2.0e-6, "output_interval": 0.5e-6},
}


def test_velocity_beyond_a_physical_bound_is_refused_at_validation():
    """1e20 m/s was accepted (the run never ended), 1e300 m/s crashed."""
    for v in (1e20, 1e300, -2e5):
        d = dict(LOST, bodies=[dict(LOST["bodies"][0], velocity=[v, 0.0])])
        with pytest.raises(DeckError) as e:
            load_text(yaml.safe_dump(d))
        assert e.value.path == "bodies[0].velocity" and "allowed |v| <= 100000 m/s" in str(e.value), str(e.value)
    load_text(yaml.safe_dump(dict(LOST, bodies=[dict(LOST["bodies"][0], velocity=[7e4, 7e4])])))   # 99 km/s


def test_a_grid_beyond_the_index_size_or_memory_is_refused_with_its_estimate(tmpdir_mpi):
    """`grid.cells: [100000, 100000]` passed validation and check ran for
    minutes; now check prints the estimate and refuses at once, naming
    grid.cells, and so do init and run; a grid that fits the index but not the
    memory likewise."""
    for cells, words in (([100000, 100000], "beyond PETSc's 32-bit index limit 2147483647"),
                         ([20000, 20000], "need more memory than there is")):
        deck = write_deck(os.path.join(tmpdir_mpi, "big.yaml"), dict(LOST, grid=dict(LOST["grid"], cells=cells)))
        t0 = time.time()
        rc, so, se = run_cli(["check", deck])
        assert rc == 2 and clean(se) and f"plyshock: error: grid.cells: {cells[0]} x {cells[1]}" in se and words in se, se
        assert "memory: about" in so and "MiB" in so, so
        assert time.time() - t0 < 30
        rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "o")], ranks=2)
        assert rc == 2 and clean(se) and "grid.cells" in se, se
    rc, so, se = run_cli(["check", write_deck(os.path.join(tmpdir_mpi, "ok.yaml"), LOST)])
    assert rc == 0 and "memory: about" in so and "deck OK" in so, so


def test_decks_that_are_not_text_or_not_a_mapping(tmpdir_mpi):
    """A binary deck gave a UnicodeDecodeError traceback."""
    files = {"binary.yaml": bytes(np.random.default_rng(15).integers(0, 256, 4000, dtype=np.uint8)),
             "latin1.yaml": "dimension: 2\n# r\xe9sum\xe9\n".encode("latin-1"),
             "list.yaml": b"- dimension\n- grid\n", "empty.yaml": b"", "scalar.yaml": b"42\n",
             "date.yaml": b"dimension: 2024-13-45\n", "tabs.yaml": b"a:\n\t- b\n"}
    words = {"binary.yaml": "is not a text file", "latin1.yaml": "is not a text file (byte 0xe9",
             "list.yaml": "must be a mapping", "empty.yaml": "it is empty", "scalar.yaml": "it is a int",
             "date.yaml": "is not a valid deck", "tabs.yaml": "is not valid YAML"}
    if COMM.rank == 0:
        for name, data in files.items():
            with open(os.path.join(tmpdir_mpi, name), "wb") as f:
                f.write(data)
    COMM.Barrier()
    for name in files:
        rc, so, se = run_cli(["check", os.path.join(tmpdir_mpi, name)])
        assert rc == 2 and clean(se) and words[name] in se and se.startswith("plyshock: error:"), (name, se)
    rc, so, se = run_cli(["check", tmpdir_mpi])                    # a directory
    assert rc == 2 and clean(se) and "cannot read deck" in se, se
