"""The verification studies' measurements at test size (plyshock verify runs
them at full size): the smooth problem's design order, and the insertion
study's exact-against-lattice claim."""
import numpy as np
import pytest
from mpi4py import MPI

from plyshock import core
from plyshock import verify

COMM = MPI.COMM_WORLD


@pytest.mark.parametrize("shape,transfer", [("linear", "musl"), ("bspline2", "apic")])
def test_the_free_free_bar_converges_at_second_order(shape, transfer):
    """The first axial mode of a free-free elastic bar after half a period
    (smooth; markers stay in their cells): the RMS velocity error falls by 4
    when h halves (measured orders 2.11 and 2.03 from 40 to 80 cells), and is
    below 0.5% of the amplitude at 40 cells."""
    e40, *_ = verify.run_vibration(40, shape, transfer)
    e80, *_ = verify.run_vibration(80, shape, transfer)
    order = np.log2(e40 / e80)
    assert 1.8 < order < 2.4, (e40, e80, order)
    assert e40 < 5e-3


def test_exact_plies_are_exact_where_the_lattice_misses_ply_cell_pairs():
    """Plies a quarter of a cell thick in an oblique laminate: the exact
    insertion gives every ply its area and centroid to round-off with a marker
    in every (cell, ply) pair it meets; the lattice fill at 4 x 4 points per
    cell, with more markers, is off by 1e-3 or more in some ply's mass, by
    a tenth of a cell in a centroid, and leaves ply-cell pairs with no marker."""
    ex = verify.insertion_scene(2, 0.25, "exact", 1)
    m = core.initialize(ex)
    me, ce, pairs, missing = verify.insertion_errors(ex, m)
    assert me < 1e-13 and ce < 1e-12, (me, ce)
    la = verify.insertion_scene(2, 0.25, "lattice", 4)
    ml = core.initialize(la)
    lme, lce, _, lmissing = verify.insertion_errors(la, ml, pairs)
    assert ml.stats["markers"] > m.stats["markers"]
    assert lme > 1e-3 and lce > 0.1 and lmissing > 0.1, (lme, lce, lmissing)
