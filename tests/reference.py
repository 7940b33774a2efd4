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
