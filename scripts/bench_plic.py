"""Cost per call of the PLIC cell geometry (src/cells/plic.c), one core.

Each figure is the best of 5 repeats of a batch through the thin binding in
_core.pyx (one C call per item; the binding's per-item overhead, a few ns of
copying n and h, is included).  Random normals, fractions and aspect ratios up
to about 7; K materials in a cell; the slab is a quarter of the cell.

    .venv/bin/python scripts/bench_plic.py [N]
"""
import sys
import time

import numpy as np

from plyshock import _core as core


def best(f, reps=5):
    t = []
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return min(t)


def row(label, seconds):
    print(f"{label:42s}{seconds * 1e9:9.1f}")


def main():
    N = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    rng = np.random.default_rng(0)
    print(f"PLIC geometry, {N} calls per batch, best of 5, ns per call")
    for dim in (2, 3):
        h = 1e-3 * np.exp(rng.uniform(-1, 1, size=(N, dim)))
        n = rng.normal(size=(N, dim))
        a = rng.uniform(size=N)
        field = rng.uniform(size=(int(round(N ** (1 / dim))) + 2,) * dim)
        ncells = (field.shape[0] - 2) ** dim
        t = best(lambda: core.plic_youngs(field, h[0]))
        row(f"{dim}D Youngs normal (3^{dim} block)", t / ncells)
        t = best(lambda: core.plic_offset(n, a, h))
        row(f"{dim}D offset (closed form)", t / N)
        d = core.plic_offset(n, a, h)
        t = best(lambda: core.plic_volume(n, d, h))
        row(f"{dim}D volume (closed form)", t / N)
        for K, kind in ((2, ""), (3, "layers"), (3, "crossing"), (4, "layers"), (4, "crossing")):
            M = N if K == 2 else N // 10
            alpha = rng.dirichlet(np.ones(K), size=M)
            nk = rng.normal(size=(M, K - 1, dim))
            if kind == "layers":  # one normal for all the planes (layers parallel in the cell)
                nk[:] = nk[:, :1]
            t = best(lambda: core.plic_reconstruct(alpha, nk, h[:M]))
            dk = core.plic_reconstruct(alpha, nk, h[:M])
            row(f"{dim}D reconstruct, {K} materials {kind}", t / M)
            w = 0.25 * h[:M, 0]
            t = best(lambda: core.plic_slab(nk, dk, h[:M], 0, 1, w))
            row(f"{dim}D slab volumes, {K} materials {kind}", t / M)

if __name__ == "__main__":
    main()
