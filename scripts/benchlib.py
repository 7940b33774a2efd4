"""What the solver benchmarks share: the wall time of a number of steps,
between barriers so that every rank's share is in it; the process's
resident size; the quadrants scene (bench_cells.py, bench_cfl.py)."""
import os
import time


def resident_bytes():
    """This process's resident size now (bytes; /proc/self/statm's second field, in pages)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def timed_steps(S, steps, mpi):
    """Seconds of wall time for `steps` steps of solver S on all ranks of mpi."""
    mpi.Barrier()
    t = time.perf_counter()
    for _ in range(steps):
        S.step()
    mpi.Barrier()
    return time.perf_counter() - t


# the Liska-Wendroff quadrants (clawpack.pyclaw.examples.euler_2d.quadrants'
# initial data: the unit square cut at x = y = 0.8, gamma 1.4): (name, x range,
# y range, rho, u, v, p), each quadrant a gas material of its own (the
# contract's material density is the initial density), walls all round
QUADRANTS = [("ur", (0.8, 1.0), (0.8, 1.0), 1.5, 0.0, 0.0, 1.5),
             ("ul", (0.0, 0.8), (0.8, 1.0), 0.532258064516129, 1.206045378311055, 0.0, 0.3),
             ("ll", (0.0, 0.8), (0.0, 0.8), 0.137992831541219, 1.206045378311055, 1.206045378311055, 0.029032258064516),
             ("lr", (0.8, 1.0), (0.0, 0.8), 0.532258064516129, 0.0, 1.206045378311055, 0.3)]
WALLS = {"x-": "symmetry", "x+": "symmetry", "y-": "symmetry", "y+": "symmetry"}
GAS = {"type": "ideal-gas", "gamma": 1.4}


def quadrants_scene(n, cfl=0.4, t_end=10.0, one_gas=False):
    """The quadrants on n x n cells (SI units of a unit square: m, kg/m^3, m/s, Pa).
    one_gas: one material, each quadrant a body at its own density (the body
    key `density`), as PyClaw's one fluid; else a gas material per quadrant,
    each quadrant's edges material interfaces (Youngs' PLIC, mixed cells)."""
    from plyshock import Body, Box, Grid, Material, Run, Scene
    if one_gas:
        mats = [Material("gas", density=QUADRANTS[0][3], eos=GAS)]
        bodies = [Body(name, box=Box([xr[0], yr[0]], [xr[1], yr[1]]), material="gas", representation="cells", pressure=p,
                       density=rho, velocity=[u, v]) for name, xr, yr, rho, u, v, p in QUADRANTS]
    else:
        mats = [Material(name, density=rho, eos=GAS) for name, xr, yr, rho, u, v, p in QUADRANTS]
        bodies = [Body(name, box=Box([xr[0], yr[0]], [xr[1], yr[1]]), material=name, representation="cells", pressure=p, velocity=[u, v])
                  for name, xr, yr, rho, u, v, p in QUADRANTS]
    return Scene(2, Grid([0, 0], [1, 1], [n, n], WALLS), mats, bodies, Run(t_end=t_end, cfl=cfl)).validate()
