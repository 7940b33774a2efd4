"""Test harness: runs under `mpiexec -n 2` (scripts/test).

Collective tests use PETSc.COMM_WORLD in process; tests that compare rank
counts launch `mpiexec -n k plyshock ...` from rank 0 with the parent's
OMPI_*/PMIX_* variables removed, and broadcast the result.
"""
import os
import shutil
import subprocess
import sys
import tempfile

import pytest

import petsc4py

petsc4py.init(sys.argv[:1])
from petsc4py import PETSc  # noqa: E402
from mpi4py import MPI  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "examples"))
sys.path.insert(0, os.path.dirname(__file__))
COMM = MPI.COMM_WORLD


@pytest.fixture
def comm():
    return COMM


@pytest.fixture
def tmpdir_mpi():
    """One temporary directory shared by all ranks, removed afterwards."""
    d = tempfile.mkdtemp(prefix="plyshock-") if COMM.rank == 0 else None
    d = COMM.bcast(d, root=0)
    yield d
    COMM.Barrier()
    if COMM.rank == 0:
        shutil.rmtree(d, ignore_errors=True)


def clean_env():
    """The environment without the parent mpiexec's variables (a nested
    mpiexec refuses to start otherwise)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_", "OPAL_", "HYDRA_"))}
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_MCA_btl_vader_single_copy_mechanism="none")
    return env


def run_cli(args, ranks=None, timeout=300):
    """Run `plyshock ARGS` (under `mpiexec -n ranks` when given) on rank 0;
    every rank gets (returncode, stdout, stderr)."""
    out = None
    if COMM.rank == 0:
        exe = os.path.join(ROOT, ".venv", "bin", "plyshock")
        cmd = ([shutil.which("mpiexec"), "-n", str(ranks)] if ranks else []) + [exe] + list(args)
        p = subprocess.run(cmd, env=clean_env(), capture_output=True, text=True, timeout=timeout, cwd=ROOT)
        out = (p.returncode, p.stdout, p.stderr)
    return COMM.bcast(out, root=0)


def write_deck(path, d):
    """A deck file from a dict, written by rank 0 (all ranks return its path)."""
    if COMM.rank == 0:
        import yaml
        with open(path, "w") as f:
            f.write("# plyshock test deck; SI units\n" + yaml.safe_dump(d))
    COMM.Barrier()
    return path


def clean(err):
    """A command's stderr holds no traceback and no HDF5 or PETSc error dump from any rank."""
    return "Traceback" not in err and "HDF5-DIAG" not in err and "PETSC ERROR" not in err


def histories_on_ranks(deck, tmpdir, ranks=(1, 2)):
    """`plyshock run DECK -o TMPDIR/o<k>` on each rank count k (each must pass
    cleanly): their history.csv tables, in the order of ranks."""
    import numpy as np
    hs = []
    for k in ranks:
        out = os.path.join(tmpdir, f"o{k}")
        rc, so, se = run_cli(["run", deck, "-o", out], ranks=k)
        assert rc == 0 and clean(se), se
        hs.append(np.genfromtxt(os.path.join(out, "history.csv"), delimiter=",", names=True))
    return hs


@pytest.fixture(autouse=True)
def _sync():
    """Ranks leave each test together; PETSc garbage is collected."""
    yield
    import gc
    gc.collect()
    COMM.Barrier()


def energy_and_work_per_step(r, L, dt, rho0):
    """From a material-driver history r (core.drive_material) under velocity
    gradients L: each step's change of specific internal energy, and the work
    of the Cauchy stress carried over it, (sigma_prev + sigma) : L dt / (2 rho)
    (J/kg), the marker starting unstressed at e = 0."""
    import numpy as np
    s = r["stress"]
    s_prev = np.concatenate([np.zeros((1, 3, 3)), s[:-1]])
    dw = 0.5 * np.einsum("nij,nij->n", s_prev + s, L) * dt * r["J"] / rho0
    return np.diff(np.concatenate([[0.0], r["energy"]])), dw
