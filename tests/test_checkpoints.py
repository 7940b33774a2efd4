"""Periodic, crash-safe checkpoints (under mpiexec -n 2): their cadence, a
SIGKILLed run resumed from its last checkpoint ending bitwise as an
uninterrupted one, and damaged checkpoints refused by name."""
import glob
import os
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np
from mpi4py import MPI

from conftest import ROOT, clean, clean_env, run_cli, write_deck

COMM = MPI.COMM_WORLD

# a hydrodynamic steel flyer onto copper in uniaxial strain, with a gauge: about 2 s on 2 ranks
PLATE = {
    "dimension": 2,
    "grid": {"lower": [0, 0], "upper": [0.01, 0.0003], "cells": [200, 4], "boundary": {"y-": "symmetry", "y+": "symmetry"}},
    "materials": [{"name": "steel", "density": 7850.0, "eos": {"type": "mie-gruneisen", "c0": 4570.0, "s": 1.49, "gamma0": 1.93}},
                  {"name": "cu", "density": 8930.0, "eos": {"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02}}],
    "bodies": [{"name": "flyer", "material": "steel", "box": {"lower": [0.001, 0], "upper": [0.003, 0.0003]}, "velocity": [800, 0]},
               {"name": "target", "material": "cu", "box": {"lower": [0.003, 0], "upper": [0.008, 0.0003]}}],
    "run": {"t_end": 3.0e-6, "output_interval": 1.0e-6, "history_interval": 5},
    "gauges": [{"name": "target", "point": [0.0035, 0.00015]}],
}

def markers_file(outdir, last=True):
    files = sorted(glob.glob(os.path.join(outdir, "markers_*.h5")))
    return files[-1] if last else files


def test_checkpoints_at_every_output_time_or_at_the_set_cadence(tmpdir_mpi):
    """By default checkpoint.h5 is refreshed at every output time and at the
    end; run.checkpoint_interval (simulated s) sets its own cadence; each is
    renamed into place (no .tmp left) and carries the completeness flag and a
    checksum per dataset.  Checkpoints never change the steps taken."""
    deck = write_deck(os.path.join(tmpdir_mpi, "d.yaml"), dict(PLATE, run=dict(PLATE["run"], t_end=1.5e-6, output_interval=0.5e-6)))
    H = {}
    for name, opts, times in (("outputs", [], [0.5e-6, 1.0e-6, 1.5e-6]),
                              ("interval", ["-run_checkpoint_interval", "0.7e-6"], [0.7e-6, 1.4e-6, 1.5e-6]),
                              ("max_steps", ["-run_max_steps", "150"], [0.5e-6, None])):
        out = os.path.join(tmpdir_mpi, name)
        rc, so, se = run_cli(["run", deck, "-o", out] + opts, ranks=2)
        assert rc == 0, se
        lines = [ln for ln in so.splitlines() if ln.startswith("checkpoint: ")]
        t = [float(ln.split("t = ")[1].split()[0]) for ln in lines]
        assert len(t) == len(times), (name, lines)
        for a, b in zip(t, times):
            # a simulated-time cadence checkpoints after the step that reaches it (within one step)
            assert b is None or b <= a < b + 1e-8, (name, t)
        assert not os.path.exists(os.path.join(out, "checkpoint.h5.tmp"))
        with h5py.File(os.path.join(out, "checkpoint.h5"), "r") as f:
            assert f.attrs["complete"][0] == 1 and f.attrs["format"][0] == 2
            assert list(f["run/gauges"][...]) and f["checkpoint/state"].shape == (5,)
            assert all("checksum" in f[k].attrs for k in ("checkpoint/x", "checkpoint/ranks", "run/schedule"))
        H[name] = np.genfromtxt(os.path.join(out, "history.csv"), delimiter=",", names=True)
    # the same steps whatever the cadence
    assert np.array_equal(H["outputs"]["dt"], H["interval"]["dt"])


def kill_when_checkpointed(args, ckpt, after):
    """Start `mpiexec -n 2 plyshock ARGS` (rank 0 of the tests only), SIGKILL
    every process of it once ckpt exists and `after` more seconds have passed;
    the run's processes are ours, killed by their ids."""
    exe = os.path.join(ROOT, ".venv", "bin", "plyshock")
    p = subprocess.Popen([shutil.which("mpiexec"), "-n", "2", exe] + args, env=clean_env(), cwd=ROOT,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
    t0 = time.time()
    while not os.path.exists(ckpt) and p.poll() is None and time.time() - t0 < 120:
        time.sleep(0.02)
    time.sleep(after)
    alive = p.poll() is None
    # mpiexec and its ranks share the session mpiexec leads (each rank has a process group of its own)
    pids = [int(x) for x in subprocess.run(["ps", "-o", "pid=", "-s", str(p.pid)], capture_output=True, text=True).stdout.split()]
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    out = p.communicate()[0].decode(errors="replace")
    return alive, out


def test_a_killed_run_resumes_from_its_last_checkpoint_bitwise(tmpdir_mpi):
    """`plyshock run` under mpiexec -n 2 with a checkpoint every 0.2 s of wall
    time (at arbitrary steps, between output times), SIGKILLed once a
    checkpoint exists; `--restart OUTDIR/checkpoint.h5` into the same OUTDIR
    ends with the same marker files, bitwise, as an uninterrupted run, and the
    same history rows."""
    # ten times the plate's markers (a 40-cell-tall strip between symmetry faces: the same 1D answer), so
    # that the run outlives its first checkpoint by seconds on a fast machine too (CI once finished first)
    grid = dict(PLATE["grid"], upper=[0.01, 0.003], cells=[200, 40])
    bodies = [dict(b, box={"lower": b["box"]["lower"], "upper": [b["box"]["upper"][0], 0.003]}) for b in PLATE["bodies"]]
    d = dict(PLATE, grid=grid, bodies=bodies, run=dict(PLATE["run"], checkpoint_wall_interval=0.2))
    deck = write_deck(os.path.join(tmpdir_mpi, "plate.yaml"), d)
    full, killed = os.path.join(tmpdir_mpi, "full"), os.path.join(tmpdir_mpi, "killed")
    rc, so, se = run_cli(["run", deck, "-o", full], ranks=2)
    assert rc == 0, se
    res = None
    if COMM.rank == 0:
        ckpt = os.path.join(killed, "checkpoint.h5")
        alive, out = kill_when_checkpointed(["run", deck, "-o", killed], ckpt, after=0.1)
        with h5py.File(ckpt, "r") as f:
            t_ckpt = float(f["checkpoint/state"][0])
        res = (alive, out, t_ckpt, len(glob.glob(os.path.join(killed, "markers_*.h5"))))
    alive, out, t_ckpt, nfiles = COMM.bcast(res, root=0)
    assert alive, "the run ended before it could be killed:\n" + out
    assert "done:" not in out and 0 < t_ckpt < 3.0e-6, out
    rc, so, se = run_cli(["run", deck, "-o", killed, "--restart", os.path.join(killed, "checkpoint.h5")], ranks=2)
    assert rc == 0 and clean(se), se
    names = [os.path.basename(f) for f in markers_file(full, last=False)]
    assert names == [os.path.basename(f) for f in markers_file(killed, last=False)]    # the same numbers
    for name in names[-2:]:
        with h5py.File(os.path.join(full, name), "r") as a, h5py.File(os.path.join(killed, name), "r") as b:
            assert a.attrs["time"] == b.attrs["time"]
            assert set(a["markers"]) == set(b["markers"])
            for k in a["markers"]:
                assert np.array_equal(a["markers"][k][...], b["markers"][k][...]), (name, k)
    if COMM.rank == 0:
        print(f"\nkilled after the checkpoint at t = {t_ckpt:.4g} s ({nfiles} marker files), resumed: bitwise")
    # history.csv cut back to the checkpoint and continued: every row of the full run's there, once
    a = np.genfromtxt(os.path.join(full, "history.csv"), delimiter=",", names=True)
    b = np.genfromtxt(os.path.join(killed, "history.csv"), delimiter=",", names=True)
    assert np.all(np.diff(b["step"]) > 0)
    common = np.isin(b["step"], a["step"])
    assert np.isin(a["step"], b["step"]).all()
    for k in ("time", "dt", "mass", "px", "kinetic", "internal"):
        assert np.array_equal(a[k], b[k][common]), k
    g = np.genfromtxt(os.path.join(killed, "gauges.csv"), delimiter=",", names=True)
    assert g["time"][-1] == 3.0e-6 and np.all(np.diff(g["time"]) > 0)           # the gauge followed on


def test_restart_of_a_bad_checkpoint_is_a_named_error(tmpdir_mpi):
    """--restart of a truncated, damaged, incomplete, foreign or missing
    checkpoint: exit 2, one `plyshock: error: --restart:` line naming what is
    wrong, no traceback and no HDF5 dump from any rank, nothing run."""
    deck = write_deck(os.path.join(tmpdir_mpi, "plate.yaml"), dict(PLATE, run=dict(PLATE["run"], t_end=0.2e-6)))
    src = os.path.join(tmpdir_mpi, "src")
    rc, so, se = run_cli(["run", deck, "-o", src], ranks=2)
    assert rc == 0, se
    good = os.path.join(src, "checkpoint.h5")
    other = write_deck(os.path.join(tmpdir_mpi, "other.yaml"), dict(PLATE, grid=dict(PLATE["grid"], cells=[100, 4])))
    cases = {}
    if COMM.rank == 0:
        size = os.path.getsize(good)
        with h5py.File(good, "r") as f:
            x_at = f["checkpoint/x"].id.get_offset()
        for name in ("truncated", "flipped", "incomplete", "text"):
            fn = os.path.join(tmpdir_mpi, name + ".h5")
            shutil.copy(good, fn)
            cases[name] = fn
        with open(cases["truncated"], "r+b") as f:
            f.truncate(size // 2)
        with open(cases["flipped"], "r+b") as f:          # one bit of one marker's position
            f.seek(x_at + 8 * 17 + 3)
            b = f.read(1)
            f.seek(x_at + 8 * 17 + 3)
            f.write(bytes([b[0] ^ 0x10]))
        with h5py.File(cases["incomplete"], "r+") as f:   # as if the writer had been killed before its last word
            del f.attrs["complete"]
        with open(cases["text"], "w") as f:
            f.write("not a checkpoint\n")
    cases = COMM.bcast(cases, root=0)
    expect = [("truncated", deck, "is not a readable HDF5 file", 2),
              ("flipped", deck, "is damaged: dataset /checkpoint/x fails its checksum", 2),
              ("incomplete", deck, "is incomplete", 2),
              ("text", deck, "is not a readable HDF5 file", None),
              ("missing", deck, "does not exist", None),
              ("good", other, "was written for another grid", None)]
    for name, d, words, ranks in expect:
        path = {"missing": os.path.join(tmpdir_mpi, "nope.h5"), "good": good}.get(name, cases.get(name))
        out = os.path.join(tmpdir_mpi, "o_" + name)
        rc, so, se = run_cli(["run", d, "-o", out, "--restart", path], ranks=ranks)
        assert rc == 2 and clean(se), (name, se)
        assert f"plyshock: error: --restart: checkpoint {path} {words}" in se and se.count("plyshock: error:") == 1, (name, se)
        assert not os.path.exists(os.path.join(out, "history.csv")), name
    rc, so, se = run_cli(["run", deck, "-o", os.path.join(tmpdir_mpi, "again"), "--restart", good], ranks=2)
    assert rc == 0, se
