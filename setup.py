"""Build plyshock: the C solver in src/ and the petsc4py front end in python/plyshock.

Builds against Debian's PETSc 3.18 (PETSC_DIR, default /usr/lib/petsc) and its
petsc4py.  Install with `pip install --no-build-isolation -e .` so pip never
fetches a second PETSc from PyPI (see README).
"""
import os
import re

from setuptools import Extension, setup
from Cython.Build import cythonize
import petsc4py

PETSC_DIR = os.environ.get("PETSC_DIR", "/usr/lib/petsc")
PETSC_ARCH = os.environ.get("PETSC_ARCH", "")


def petsc_variables():
    """PETSc's include and link flags from its petscvariables."""
    path = os.path.join(PETSC_DIR, PETSC_ARCH, "lib", "petsc", "conf", "petscvariables")
    if not os.path.exists(path):
        raise SystemExit(f"PETSc not found: {path} does not exist; set PETSC_DIR (Debian: apt-get install petsc-dev)")
    out = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"^(\w+)\s*=\s*(.*)$", line.strip())
            if m:
                out[m.group(1)] = m.group(2)
    return out


def optflags():
    """The optimisation flags (src/optflags, one per line; the comment at the extension below says why each)."""
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "src", "optflags")) as f:
        return [line.strip() for line in f if line.strip()]


OPTFLAGS = optflags()
v = petsc_variables()
includes = [p[2:] for p in v.get("PETSC_CC_INCLUDES", "").split() if p.startswith("-I")]
libdirs = [p[2:] for p in v.get("PETSC_WITH_EXTERNAL_LIB", "").split() if p.startswith("-L")][:2]
sources = ["python/plyshock/_core.pyx"] + [os.path.join("src", f) for f in (
    "clip.c", "geom.c", "insert.c", "markers.c", "io.c", "solver.c", "fields.c", "step.c", "timestep.c", "grid.c",
    "transfer_musl.c", "transfer_apic.c", "contact.c", "stress.c", "migrate.c", "totals.c", "halo.c", "run.c", "checkpoint.c", "memory.c",
    "materials/registry.c", "materials/eos_mie_gruneisen.c", "materials/eos_hypoelastic.c",
    "materials/strength.c", "materials/strength_zerilli_armstrong.c", "materials/strength_mts.c",
    "materials/failure_johnson_cook.c", "materials/failure_hashin.c",
    "materials/update.c", "materials/update4.c", "materials/orthotropic.c", "materials/driver.c",
    "materials/eos_ideal_gas.c", "cells/cells.c", "cells/lagrange.c", "cells/closure.c", "cells/remap.c",
    "cells/plic.c")]

ext = Extension(
    "plyshock._core",
    sources=sources,
    include_dirs=["src", petsc4py.get_include()] + includes + ["/usr/lib/x86_64-linux-gnu/openmpi/include"],
    library_dirs=libdirs,
    runtime_library_dirs=libdirs,
    libraries=["petsc_real", "hdf5", "mpi"],
    # the optimisation flags, one per line in src/optflags (scripts/bench builds
    # its stripped floors with the same file); built on the machine that runs it
    # (scripts/setup), so -march=native is safe;
    # -fno-math-errno: sqrt becomes one instruction, not a call kept for errno
    # (nothing reads errno; every result is bitwise the same).  Python's own
    # CFLAGS bring -fwrapv (signed overflow wraps: every int index is then
    # sign-extended and re-derived in the loops) and -fstack-protector-strong
    # (a canary checked at the return of every function with a local array);
    # the C here relies on neither, and without both the cells' quadrants
    # step takes 0.93-0.96x the time (side by side, median of 16 pairs; each
    # alone about 0.99x), every result bitwise the same.  -fno-trapping-math:
    # GCC may compute a floating-point operation whose result a test then
    # discards (a division by a mass that may be zero, chosen away), so more
    # of the scalar code's tests become selects without a branch; no value
    # changes (IEEE results are the same; only the exception flags, which
    # nothing here reads, may be raised by an operation not in the source's
    # path: PETSc's -fp_trap may stop there).  The quadrants take 0.94x the
    # time at 256^2 (median of 8 pairs), the pure gas 0.96x, a cell-only
    # scene in which every cell is mixed 1.03x; every result bitwise the same
    # (twenty-ninth session, docs/speed.md)
    extra_compile_args=OPTFLAGS + ["-Wno-unused-function"],
    depends=["src/plyshock.h", "src/geom.h", "src/clip.h", "src/solver.h", "src/step.h", "src/shape.h", "src/materials.h",
             "src/cells/cells.h", "src/cells/closure.h", "src/cells/plic.h", "src/optflags"],
)

setup(
    name="plyshock",
    version="0.1.0",
    description="Exact layered-composite marker insertion and shock-physics MPM on PETSc",
    package_dir={"": "python"},
    packages=["plyshock"],
    ext_modules=cythonize([ext], language_level=3),
    entry_points={"console_scripts": ["plyshock = plyshock.cli:main"]},
    python_requires=">=3.9",
)
