/*
  sweep_floor.c - a floor for the cells' remap flux phase (scripts/bench).

  One x-sweep of a single ideal gas in uniform flow, stripped of everything
  plyshock's sweep is general in: one material (no interface reconstruction,
  no ranges of materials, no discard tests), no markers, no void, no ghosts or
  ranks, no books (lost mass, remap heat), arrays of structures replaced by one
  array per quantity.  Per face and cell it does the arithmetic of
  src/cells/remap.c's FaceFlux, CellUpdate and DualFlux: the face's volume
  delta from its corners' velocities, the donor's slab share w, van Leer
  slopes of the density and the specific energy, the cell update, and the
  momentum's dual flux (the upwind node's velocity with a van Leer slope,
  scattered to the two node columns) with its kinetic energy.  Interior faces
  are written branch-free (both donors' operands loaded, one selected) so the
  compiler may use vector lanes.

  Not plyshock's solver: a yardstick of what a kernel of this scheme costs on
  this machine once generality is gone, printed beside plyshock's own flux
  phase per cell and sweep (the pure-gas bench case) in the same bench run.
  Built with the extension's optimisation flags (setup.py; cc by itself has
  neither -fwrapv nor a stack protector, which setup.py turns off); exits 1
  if the sweeps did not conserve the mass to round-off.

    cc -O3 -march=native -fno-math-errno -std=c99 scripts/sweep_floor.c -o out/sweep_floor -lm
    out/sweep_floor [n=256] [sweeps per run=200]      (best of 5 runs)
*/
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static inline double VanLeer(double a, double b)
{
  const double p = a * b;
  return p > 0.0 ? 2.0 * p / (a + b) : 0.0;
}

/* one face's fluxes (V, M, E, face volume): donor c, its neighbours cl, cr */
static inline void Face(double delta, double A, double Vd, double Md, double r0, double r1, double r2, double e0, double e1, double e2, double *F)
{
  const double side = delta > 0.0 ? 1.0 : -1.0, w = fmin(fabs(delta) * A / Vd, 1.0), off = side * 0.5 * (1.0 - w), vol = w * Vd;
  const double dM = fmin(fmax(vol * (r1 + off * VanLeer(r1 - r0, r2 - r1)), 0.0), Md);
  const double s0 = e1 + off * VanLeer(e1 - e0, e2 - e1);
  F[0] = side * vol;
  F[1] = side * dM;
  F[2] = side * dM * s0;
  F[3] = delta * A;
}

int main(int argc, char **argv)
{
  const int n = argc > 1 ? atoi(argv[1]) : 256, sweeps = argc > 2 ? atoi(argv[2]) : 200, nn = (n + 1) * (n + 1);
  const double h = 1.0 / n, A = h, Vc = h * h, dt = 0.2 * h;
  double *V = malloc(sizeof(double) * n * n), *M = malloc(sizeof(double) * n * n), *E = malloc(sizeof(double) * n * n);
  double *vx = malloc(sizeof(double) * nn), *vy = malloc(sizeof(double) * nn), *Px = malloc(sizeof(double) * nn), *Py = malloc(sizeof(double) * nn), *K = malloc(sizeof(double) * nn);
  double *F = malloc(sizeof(double) * 4 * (n + 1)), *rho = malloc(sizeof(double) * n), *e = malloc(sizeof(double) * n), best = 1e300, m0 = 0.0, m1 = 0.0;
  int run, r, i, j, f, b;

  if (n < 4 || sweeps < 1 || !V || !M || !E || !vx || !vy || !Px || !Py || !K || !F || !rho || !e) {
    fprintf(stderr, "sweep_floor: n must be >= 4 and sweeps >= 1 (got %d, %d), or out of memory\n", n, sweeps);
    return 2;
  }
  for (run = 0; run < 5; run++) {
    struct timespec t0, t1;
    double s;
    /* a gas at rest density 1-1.5 with a small volume ripple, moving at (0.5, 0.3) with a ripple in x */
    for (j = 0; j < n; j++)
      for (i = 0; i < n; i++) {
        V[j * n + i] = Vc * (1.0 + 0.01 * sin(i));
        M[j * n + i] = V[j * n + i] * (1.0 + 0.5 * (i > n / 2));
        E[j * n + i] = 2.5 * M[j * n + i];
      }
    for (m0 = 0.0, i = 0; i < n * n; i++) m0 += M[i];
    for (i = 0; i < nn; i++) {
      vx[i] = Px[i] = 0.5 + 0.1 * sin(0.01 * i);
      vy[i] = Py[i] = 0.3;
      K[i]  = 0.0;
    }
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (r = 0; r < sweeps; r++)
      for (j = 0; j < n; j++) {
        double *Vj = V + j * n, *Mj = M + j * n, *Ej = E + j * n;
        const double *u0 = vx + j * (n + 1), *u1 = u0 + n + 1;
        for (i = 0; i < n; i++) {
          rho[i] = Mj[i] / Vj[i];
          e[i]   = Ej[i] / Mj[i];
        }
        /* walls at faces 0 and n; faces 1 and n - 1 with a clamped neighbour */
        for (b = 0; b < 4; b++) F[b] = F[4 * n + b] = 0.0;
        for (f = 1; f < n; f += n - 2) {
          const double delta = 0.5 * dt * (u0[f] + u1[f]);
          const int    c = delta > 0.0 ? f - 1 : f, cl = c > 0 ? c - 1 : c, cr = c + 1 < n ? c + 1 : c;
          Face(delta, A, Vj[c], Mj[c], rho[cl], rho[c], rho[cr], e[cl], e[c], e[cr], &F[4 * f]);
        }
        for (f = 2; f < n - 1; f++) {
          const double delta = 0.5 * dt * (u0[f] + u1[f]);
          const int    p     = delta > 0.0;
          Face(delta, A, p ? Vj[f - 1] : Vj[f], p ? Mj[f - 1] : Mj[f], p ? rho[f - 2] : rho[f - 1], p ? rho[f - 1] : rho[f], p ? rho[f] : rho[f + 1], p ? e[f - 2] : e[f - 1], p ? e[f - 1] : e[f], p ? e[f] : e[f + 1], &F[4 * f]);
        }
        for (i = 0; i < n; i++) {
          /* the cell's update, then its mid-plane's dual flux to the node columns j, j + 1 */
          const double phi = 0.25 * (F[4 * i + 1] + F[4 * i + 5]);
          double       g;
          Vj[i] += F[4 * i] - F[4 * i + 4];
          Mj[i] += F[4 * i + 1] - F[4 * i + 5];
          Ej[i] += F[4 * i + 2] - F[4 * i + 6];
          g = 0.5 * (1.0 - fmin(fabs(2.0 * phi) / Mj[i], 1.0));
          for (b = 0; b < 2; b++) {
            const int    oL = (j + b) * (n + 1) + i, oU = oL + 1, ob = phi > 0.0 ? (i > 0 ? oL - 1 : oL) : (i + 1 < n ? oU + 1 : oU);
            const double vu = phi > 0.0 ? vx[oL] : vx[oU], vd = phi > 0.0 ? vx[oU] : vx[oL], vf = vu + g * VanLeer(vu - vx[ob], vd - vu);
            const double wu = phi > 0.0 ? vy[oL] : vy[oU], wd = phi > 0.0 ? vy[oU] : vy[oL], wf = wu + g * VanLeer(wu - vy[ob], wd - wu);
            Px[oL] -= phi * vf;
            Px[oU] += phi * vf;
            Py[oL] -= phi * wf;
            Py[oU] += phi * wf;
            K[oL] -= 0.5 * phi * (vf * vf + wf * wf);
            K[oU] += 0.5 * phi * (vf * vf + wf * wf);
          }
        }
      }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    s    = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    best = fmin(best, s);
  }
  /* walls at both ends: the last run's sweeps conserve the mass to round-off
     (a floor that did not do the sweep's work would not be one) */
  for (i = 0; i < n * n; i++) m1 += M[i];
  if (!(fabs(m1 - m0) <= 1e-12 * m0)) {
    fprintf(stderr, "sweep_floor: mass %.17g after the sweeps, %.17g before: not conserved\n", m1, m0);
    return 1;
  }
  printf("sweep floor (one gas, x-sweep, %d^2 cells, %d sweeps, best of 5 runs): %.1f ns per cell and sweep (mass conserved to %.1e)\n", n, sweeps, 1e9 * best / ((double)sweeps * n * n), fabs(m1 - m0) / m0);
  printf("BENCH sweep_floor_ns_%d %.6e\n", n, 1e9 * best / ((double)sweeps * n * n));
  return 0;
}
