"""The project's own fuzz test: mutated decks (a fixed seed) through
`plyshock check` and, when it accepts them, `plyshock run` (one process
each, a few steps): every command ends with exit 0, or with exit 2 and a
`plyshock: error:` line; never a traceback, a signal or a hang.

The decks are small (a 2D metal impact, a 2D laminate struck by a flyer, a
3D ball onto a plate); a mutation sets a value to something hostile, deletes
or renames a key, swaps a subtree for a scalar, duplicates a list entry,
scales a number by up to 1e12 or by -1, 1/2, 2 or 3 (which the checks often
let through to the solver), or damages the YAML text itself.  Each test
rank takes half the decks."""
import copy
import os
import subprocess

import numpy as np
import yaml
from mpi4py import MPI

from conftest import ROOT, clean_env

COMM = MPI.COMM_WORLD
SEED = 15          # the number: the same decks on every run
NDECKS = 48
STEPS = 20         # -run_max_steps of each run
TIMEOUT = 60       # s per command: longer is a hang

METAL = {
    "dimension": 2,
    "grid": {"lower": [0, 0], "upper": [0.004, 0.002], "cells": [16, 8], "boundary": {"y-": "symmetry", "x+": "fixed"}},
    "materials": [{"name": "steel", "preset": "4340-steel"},
                  {"name": "cu", "density": 8930.0, "eos": {"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02, "spall_pressure": -1.0e9},
                   "shear_modulus": 47.7e9, "strength": {"type": "elastic-plastic", "yield_stress": 90e6}},
                  {"name": "el", "density": 2700.0, "elastic": {"type": "isotropic", "E": 70e9, "nu": 0.33}}],
    "bodies": [{"name": "flyer", "material": "steel", "box": {"lower": [0.0005, 0.0], "upper": [0.0015, 0.001]}, "velocity": [800, 0]},
               {"name": "plate", "material": "cu", "box": {"lower": [0.0015, 0.0], "upper": [0.003, 0.0015]}},
               {"name": "ball", "material": "el", "sphere": {"center": [0.0035, 0.0015], "radius": 0.0003}, "subdivision": 2}],
    "run": {"t_end": 1.0e-6, "output_interval": 0.5e-6, "history_interval": 5},
    "gauges": [{"name": "g", "point": [0.002, 0.0005]}],
}
LAMINATE = {
    "dimension": 2,
    "grid": {"lower": [0, 0], "upper": [0.004, 0.004], "cells": [10, 10]},
    "materials": [{"name": "cfrp", "preset": "IM7/8552"}, {"name": "steel", "preset": "4340-steel"}],
    "bodies": [{"name": "plate", "laminate": {"frame": {"origin": [0.0005, 0.001], "axis3": [0.0005, 0.002], "plane13": [0.002, 0.001]},
                                              "size": [0.003], "layup": "[0/90]s", "ply_thickness": 0.25e-3, "ply_material": "cfrp"}},
               {"name": "flyer", "material": "steel", "cylinder": {"base": [0.002, 0.0025], "axis": [0, 1], "radius": 0.0004, "length": 0.0008},
                "velocity": [0, -300]}],
    "run": {"t_end": 1.0e-6, "shape": "bspline2", "transfer": "apic"},
}
BALL = {
    "dimension": 3,
    "grid": {"lower": [0, 0, 0], "upper": [0.002, 0.002, 0.002], "cells": [5, 5, 5],
             "boundary": {"x-": "symmetry", "y-": "symmetry"}},
    "materials": [{"name": "cu", "preset": "OFHC-copper"}, {"name": "ta", "preset": "tantalum"}],
    "bodies": [{"name": "ball", "material": "ta", "sphere": {"center": [0, 0, 0.0015], "radius": 0.0004}, "velocity": [0, 0, -1000]},
               {"name": "plate", "material": "cu", "box": {"lower": [0, 0, 0], "upper": [0.002, 0.002, 0.0009]}}],
    "run": {"t_end": 1.0e-6, "fbar": True, "pic_fraction": 0.05},
}
HOSTILE = [None, True, False, -1, 0, 1, -1e300, 1e300, 1e-300, float("nan"), float("inf"), -float("inf"), "abc", "",
           [], {}, [1, 2, 3], {"a": 1}, 10**30, 2**31, -2**31 - 1, "1e9", [[0]], "[0/90", "free", "none"]


def leaves(d, path=()):
    """Every (path, value) of a nested deck, inner nodes included."""
    out = [(path, d)]
    if isinstance(d, dict):
        for k, v in d.items():
            out += leaves(v, path + (k,))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            out += leaves(v, path + (i,))
    return out


def set_at(d, path, value, delete=False):
    cur = d
    for k in path[:-1]:
        cur = cur[k]
    if delete:
        del cur[path[-1]]
    else:
        cur[path[-1]] = value


def too_big(d):
    """A mutation that only makes the problem large (a grid of a million cells, 64 sub-cells a side) tests the
    machine, not the code: drawn again."""
    try:
        cells = np.prod([float(c) for c in d["grid"]["cells"]])
        sub = max(float(b.get("subdivision", 1)) for b in d["bodies"])
        return cells * sub ** d["dimension"] > 2e4
    except Exception:
        return False


def mutate(rng, base):
    """(deck text, what was done) from one random mutation of a base deck."""
    while True:
        d = copy.deepcopy(base)
        nodes = [p for p, _ in leaves(d) if p]
        path = nodes[rng.integers(len(nodes))]
        # hostile value, delete, rename, duplicate, scale, truncate, damage a byte, perturb
        kind = rng.choice(8, p=[0.15, 0.1, 0.08, 0.07, 0.1, 0.07, 0.08, 0.35])
        if kind == 0:
            v = HOSTILE[rng.integers(len(HOSTILE))]
            set_at(d, path, v)
            what = f"{path} = {v!r}"
        elif kind == 1:
            set_at(d, path, None, delete=True)
            what = f"del {path}"
        elif kind == 2 and isinstance(path[-1], str):
            k = path[-1]
            j = rng.integers(len(k))
            new = k[:j] + k[j + 1:] if len(k) > 1 else k + "x"
            parent = d
            for p in path[:-1]:
                parent = parent[p]
            parent[new] = parent.pop(k)
            what = f"rename {path} -> {new!r}"
        elif kind == 3:
            lists = [p for p, v in leaves(d) if isinstance(v, list) and v and isinstance(v[0], dict)]
            p = lists[rng.integers(len(lists))]
            cur = d
            for k in p:
                cur = cur[k]
            cur.append(copy.deepcopy(cur[rng.integers(len(cur))]))
            what = f"duplicate an entry of {p}"
        elif kind == 4:
            nums = [p for p, v in leaves(d) if isinstance(v, (int, float)) and not isinstance(v, bool)]
            p = nums[rng.integers(len(nums))]
            cur = d
            for k in p:
                cur = cur[k]
            f = 10.0 ** int(rng.integers(-12, 13))
            set_at(d, p, cur * f if not isinstance(cur, int) or f < 1 else int(cur * f))
            what = f"{p} *= {f:g}"
        elif kind == 7:
            nums = [p for p, v in leaves(d) if isinstance(v, float)]
            p = nums[rng.integers(len(nums))]
            cur = d
            for k in p:
                cur = cur[k]
            f = float(rng.choice([-1.0, 0.5, 2.0, 3.0]))
            set_at(d, p, cur * f)
            what = f"{p} *= {f:g}"
        elif kind == 5:
            text = yaml.safe_dump(d)
            j = int(rng.integers(1, len(text)))
            return text[:j], f"truncated at byte {j}"
        else:
            text = yaml.safe_dump(d).encode()
            j = int(rng.integers(len(text)))
            b = bytes([int(rng.integers(32, 127) if rng.random() < 0.8 else rng.integers(128, 256))])   # mostly printable
            try:
                return (text[:j] + b + text[j + 1:]).decode("utf-8"), f"byte {j} -> {b!r}"
            except UnicodeDecodeError:
                return (text[:j] + b + text[j + 1:]), f"byte {j} -> {b!r} (not UTF-8)"
        if not too_big(d):
            return yaml.safe_dump(d), what


def decks():
    rng = np.random.default_rng(SEED)
    bases = [METAL, LAMINATE, BALL]
    return [(i, *mutate(rng, bases[i % len(bases)])) for i in range(NDECKS)]


def plyshock(args):
    """(exit status, stderr) of one `plyshock` process; a hang is status 'timeout'."""
    exe = os.path.join(ROOT, ".venv", "bin", "plyshock")
    try:
        p = subprocess.run([exe] + args, env=clean_env(), capture_output=True, text=True, timeout=TIMEOUT, cwd=ROOT, errors="replace")
    except subprocess.TimeoutExpired:
        return "timeout", ""
    return p.returncode, p.stderr


def verdict(rc, err):
    """None when the command behaved, else what is wrong."""
    if rc == "timeout":
        return f"hung (> {TIMEOUT} s)"
    if rc < 0:
        return f"killed by signal {-rc}"
    if rc not in (0, 2):
        return f"exit status {rc}"
    if "Traceback" in err or "HDF5-DIAG" in err:
        return "a traceback"
    if rc == 2 and "plyshock: error:" not in err:
        return "exit 2 without a `plyshock: error:` line"
    return None


def test_mutated_decks_end_in_success_or_a_named_error(tmpdir_mpi):
    bad, counts = [], {"check 0": 0, "check 2": 0, "run 0": 0, "run 2": 0}
    for i, text, what in decks():
        if i % COMM.size != COMM.rank:
            continue
        deck = os.path.join(tmpdir_mpi, f"fuzz{i:02d}.yaml")
        with open(deck, "wb") as f:
            f.write(text if isinstance(text, bytes) else text.encode())
        rc, err = plyshock(["check", deck])
        problem = verdict(rc, err)
        if problem:
            bad.append(f"deck {i} ({what}): check {problem}:\n{err[-1500:]}")
            continue
        counts[f"check {rc}"] += 1
        if rc != 0:
            continue
        rc, err = plyshock(["run", deck, "-o", os.path.join(tmpdir_mpi, f"out{i:02d}"), "-run_max_steps", str(STEPS)])
        problem = verdict(rc, err)
        if problem:
            bad.append(f"deck {i} ({what}): run {problem}:\n{err[-1500:]}")
        else:
            counts[f"run {rc}"] += 1
    bad = sum(COMM.allgather(bad), [])
    counts = {k: sum(COMM.allgather(v)) for k, v in counts.items()}
    if COMM.rank == 0:
        print(f"\nfuzz: {NDECKS} decks; {counts}")
    assert not bad, "\n\n".join(bad)
    # the mutations reach both the checks and the solver
    assert counts["check 2"] >= NDECKS // 4 and counts["run 0"] >= 5
