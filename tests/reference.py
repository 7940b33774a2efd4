"""Independent reference geometry for the tests: exact convex clipping by Qhull.

The area/volume and centroid of {x : A x <= b} come from scipy's
HalfspaceIntersection and ConvexHull (Qhull), split into simplices from an
interior point; nothing here shares code with src/.
"""
import numpy as np
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection


def convex_moments(A, b):
    """(volume, centroid) of the polytope A x <= b; (0, None) when empty or flat."""
    A = np.asarray(A, float)
    b = np.asarray(b, float)
    dim = A.shape[1]
    # Chebyshev centre: an interior point, and how deep it is
    norm = np.linalg.norm(A, axis=1)
    res = linprog(np.r_[np.zeros(dim), -1.0], A_ub=np.c_[A, norm], b_ub=b,
                  bounds=[(None, None)] * dim + [(0, None)], method="highs")
    if not res.success or res.x[-1] <= 1e-13 * max(1.0, np.abs(b).max()):
        return 0.0, None
    x0 = res.x[:dim]
    hs = HalfspaceIntersection(np.c_[A, -b], x0)
    V = hs.intersections
    hull = ConvexHull(V)
    c0 = V.mean(axis=0)
    vol, mom = 0.0, np.zeros(dim)
    for s in hull.simplices:
        P = V[s] - c0
        v = abs(np.linalg.det(P)) / (2.0 if dim == 2 else 6.0)
        vol += v
        mom += v * (V[s].sum(axis=0) + c0) / (dim + 1)
    return vol, mom / vol


def box_halfspaces(lo, hi):
    dim = len(lo)
    A, b = [], []
    for i in range(dim):
        e = np.zeros(dim); e[i] = 1
        A += [e, -e]; b += [hi[i], -lo[i]]
    return np.array(A), np.array(b)


def oriented_halfspaces(origin, axes, lo, hi):
    """{x : lo_k <= axes[k] . (x - origin) <= hi_k} for each row of axes."""
    A, b = [], []
    for e, l, h in zip(axes, lo, hi):
        e = np.asarray(e, float)
        A += [e, -e]; b += [h + e @ origin, -(l + e @ origin)]
    return np.array(A), np.array(b)


def box_plane_fraction(n, d, h):
    """Exact volume fraction of {x : n.x <= d} in the box [-h/2, h/2] (any dim),
    in rational arithmetic (fractions.Fraction of the given floats, so no
    round-off at all), returned as a float.  In unit-cell coordinates
    s_i = x_i/h_i + 1/2 (reflected where n_i < 0) the set is {m.s <= a} with
    m_i = |n_i| h_i > 0 and a = d + sum(m)/2; its volume is the inclusion-exclusion
    sum over the cell's vertices v of (-1)^|v| (a - m.v)_+^k / (k! prod m)
    (k = number of non-zero n_i; components that are zero drop out)."""
    import itertools
    import math
    from fractions import Fraction
    n = [Fraction(float(x)) for x in n]
    h = [Fraction(float(x)) for x in h]
    m = [abs(ni) * hi for ni, hi in zip(n, h) if ni != 0]
    a = Fraction(float(d)) + sum(m) / 2
    k = len(m)
    if k == 0:
        return 1.0 if d >= 0 else 0.0
    total = Fraction(0)
    for v in itertools.product((0, 1), repeat=k):
        t = a - sum(mi for mi, vi in zip(m, v) if vi)
        if t > 0:
            total += (-1) ** sum(v) * t ** k
    return float(total / (math.factorial(k) * math.prod(m)))
