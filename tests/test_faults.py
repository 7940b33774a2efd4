"""Runs that survive hostile input (under mpiexec -n 2): guards with named
errors against absurd velocities, grids beyond the index size or memory,
decks that are not text or not a mapping, a collapsing time step and runs
the step counter cannot hold; runs whose markers all leave the grid finish
cleanly."""
import glob
import os
import time

import h5py
import numpy as np
import pytest
import yaml
from mpi4py import MPI

from plyshock import DeckError
from plyshock import core
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


def markers_file(outdir, last=True):
    files = sorted(glob.glob(os.path.join(outdir, "markers_*.h5")))
    return files[-1] if last else files


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


def test_a_collapsing_time_step_stops_the_run_naming_the_marker(tmpdir_mpi):
    """run.dt_floor: the step that falls below the floor (here set to 0.9 of
    the first step, which a 4 km/s steel impact's shock crosses at once) stops
    the run, on both ranks, with exit 2 and one line naming the marker, its
    body and material, where it is and what about it limits the step.  Flyer
    and plate bonded: in one velocity field the shock compresses the first
    cells at once (J = 0.9); in contact (the default) the time step falls more
    slowly (measured 0.955 of the first after 6 steps), not below this floor."""
    d = {"dimension": 2, "grid": {"lower": [0, 0], "upper": [0.004, 0.0002], "cells": [80, 4],
                                  "boundary": {"y-": "symmetry", "y+": "symmetry"}},
         "materials": [{"name": "steel", "preset": "4340-steel"}],
         "bodies": [{"name": "flyer", "material": "steel", "box": {"lower": [0.0005, 0], "upper": [0.0015, 0.0002]}, "velocity": [4000, 0]},
                    {"name": "plate", "material": "steel", "box": {"lower": [0.0015, 0], "upper": [0.0035, 0.0002]}}],
         "run": {"t_end": 0.5e-6, "dt_floor": 0.9}, "contact": {"type": "bonded"}}
    deck = write_deck(os.path.join(tmpdir_mpi, "floor.yaml"), d)
    rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "o")], ranks=2)
    assert rc == 2 and clean(se) and se.count("plyshock: error: run.dt_floor: the time step fell to") == 1, se
    for words in ("below 0.9 of the run's first step", "(body flyer, material steel) at (0.00", "wave speed",
                  "viscous term", "J = V/V0 = 0.9", "times the fastest marker's at the first step"):
        assert words in se, (words, se)
    # the default floor (1e-3) lets the same impact run
    rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "o2"), "-run_dt_floor", "1e-3", "-run_t_end", "0.1e-6"], ranks=2)
    assert rc == 0, se
    # the floor's range is checked with the other run options
    rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "o3"), "-run_dt_floor", "1"])
    assert rc == 2 and "run.dt_floor: 1 is out of range; allowed [0, 1)" in se, se
    # and an option PETSc cannot read is a named error of every rank, not an abort
    rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "o3"), "-run_dt_floor", "abc"], ranks=2)
    assert rc == 2 and clean(se) and se.count("plyshock: error: -run_<key>: Input string abc has no numeric value") == 1, se


def test_a_run_the_step_counter_cannot_hold_is_refused_before_its_first_step(tmpdir_mpi):
    """t_end of 100 s on 100 um cells of steel: about 2e10 steps."""
    d = dict(LOST, run={"t_end": 100.0})
    deck = write_deck(os.path.join(tmpdir_mpi, "long.yaml"), d)
    rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "o")], ranks=2)
    assert rc == 2 and clean(se) and "plyshock: error: run.t_end: 100 s needs about" in se and "step counter" in se, se
    assert "step " not in so                       # no step was taken


def test_run_keys_of_checkpoints_are_range_checked_in_one_place():
    """The new run keys: structure in scene.Run, ranges in C's PSRunParamsCheck."""
    scene = load_text(yaml.safe_dump(LOST))
    from plyshock import Run
    for kw, key, words in ((dict(checkpoint_interval=-1.0), "run.checkpoint_interval", "allowed [0, inf) s"),
                           (dict(checkpoint_wall_interval=-5.0), "run.checkpoint_wall_interval", "allowed [0, inf) s of wall time"),
                           (dict(dt_floor=1.5), "run.dt_floor", "allowed [0, 1)")):
        scene.run = Run(**{"t_end": 1e-6, **kw}).validate()
        with pytest.raises(DeckError) as e:
            core.run_options(scene)
        assert e.value.path == key and words in str(e.value), str(e.value)
    with pytest.raises(DeckError) as e:
        Run(t_end=1e-6, checkpoint_wall_interval="hourly").validate()
    assert e.value.path == "run.checkpoint_wall_interval"


def test_a_run_whose_markers_all_leave_finishes_cleanly(tmpdir_mpi):
    """Issue 15's reproducer: exit 0, a warning line, the losses booked, no
    sentinel values (max_pressure read -1.797693e+308 once the grid was
    empty), and the empty end state's checkpoint (it crashed writing zero
    rows) restarts."""
    deck = write_deck(os.path.join(tmpdir_mpi, "lost.yaml"), LOST)
    out = os.path.join(tmpdir_mpi, "out")
    rc, so, se = run_cli(["run", deck, "-o", out], ranks=2)
    assert rc == 0 and clean(se), se
    assert so.count("warning: no marker is left in the grid") == 1, so
    H = np.genfromtxt(os.path.join(out, "history.csv"), delimiter=",", names=True)
    assert H["markers"][-1] == 0 and H["time"][-1] == 2e-6
    m0 = 7810.0 * 0.0004 * 0.0004
    assert abs(H["mass"][0] - m0) <= 1e-12 * m0 and abs(H["lost_mass"][-1] - m0) <= 1e-12 * m0
    assert abs(H["total"][-1] - H["total"][0]) <= 1e-12 * H["total"][0]       # the energy went out, booked
    for k in H.dtype.names:
        assert np.all(np.abs(H[k]) < 1e300), k
    assert np.all(H["max_pressure"][H["markers"] == 0] == 0.0)
    with h5py.File(markers_file(out), "r") as f:
        assert f["markers/x"].shape == (0, 2)
    with h5py.File(os.path.join(out, "checkpoint.h5"), "r") as f:
        assert f["checkpoint/x"].shape == (0, 2) and f.attrs["complete"][0] == 1
    rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "more"), "-run_t_end", "3e-6",
                          "--restart", os.path.join(out, "checkpoint.h5")], ranks=2)
    assert rc == 0 and clean(se), se
    H2 = np.genfromtxt(os.path.join(tmpdir_mpi, "more", "history.csv"), delimiter=",", names=True)
    assert H2["time"][-1] == 3e-6 and H2["lost_mass"][-1] == H["lost_mass"][-1]
