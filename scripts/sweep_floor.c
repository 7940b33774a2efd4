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
  scattered to the two node columns) with its kinetic energy.

  Three forms of the same arithmetic, run in turn and checked bitwise equal:
  - one pass: per row, the densities, the faces, then one loop over the cells
    that updates each cell and scatters its dual flux to its nodes (the form
    of plyshock's own loops);
  - passes: per row, each step its own loop over arrays (densities, faces,
    cells with their mid-plane mass flux, each node row's dual fluxes, then
    the nodes), every loop free of loop-carried dependences, so the compiler
    runs each in SIMD lanes; the figure the bench compares with;
  - passes, interleaved: the same over a cell's volume, mass and energy side
    by side and a node's two momenta side by side, as plyshock stores a
    material's block and the nodes.  Not what that layout costs plyshock:
    GCC 12 leaves this form's loop over the interior faces scalar (its
    -fopt-info-vec: "couldn't vectorize loop"; the nodes' momenta side by
    side cost nothing, the cells' blocks side by side all of it, even with
    the faces reading a row's V and M from planes as plyshock's faces do),
    and plyshock's own face loops run in SIMD lanes over its blocks.
  min/max are the ternaries of PetscMin/PetscMax, as in plyshock: C's
  fmin/fmax order NaNs, which keeps GCC from running them in lanes (with them
  the one pass took 1.7x as long and the passes 2x).  The flow turns each
  sweep, so the cells at the walls neither empty nor pile up: every value
  stays finite (checked).

  Not plyshock's solver: a yardstick of what a kernel of this scheme costs on
  this machine once generality is gone, printed beside plyshock's own flux
  phase per cell and sweep (the pure-gas bench case) in the same bench run.
  Built with the extension's optimisation flags (src/optflags, which setup.py
  reads; -fno-wrapv and -fno-stack-protector there undo what Python's CFLAGS
  bring, and are cc's defaults anyway); exits 1
  if the sweeps did not conserve the mass to round-off or the forms differ.

    cc $(cat src/optflags) scripts/sweep_floor.c -o out/sweep_floor -lm
    out/sweep_floor [n=256] [sweeps per run=200]      (best of 5 runs of each form)
*/
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static inline double Min(double a, double b) { return a < b ? a : b; }
static inline double Max(double a, double b) { return a < b ? b : a; }

static inline double VanLeer(double a, double b)
{
  const double p = a * b;
  return p > 0.0 ? 2.0 * p / (a + b) : 0.0;
}

/* one face's fluxes of volume, mass and energy: donor volume Vd and mass Md,
   the densities r0 r1 r2 and specific energies e0 e1 e2 of the donor's
   upwind neighbour, the donor and its downwind neighbour */
static inline void Face(double delta, double A, double Vd, double Md, double r0, double r1, double r2, double e0, double e1, double e2, double *Fv, double *Fm, double *Fe)
{
  const double side = delta > 0.0 ? 1.0 : -1.0, w = Min(fabs(delta) * A / Vd, 1.0), off = side * 0.5 * (1.0 - w), vol = w * Vd;
  const double dM = Min(Max(vol * (r1 + off * VanLeer(r1 - r0, r2 - r1)), 0.0), Md);
  const double s0 = e1 + off * VanLeer(e1 - e0, e2 - e1);
  *Fv = side * vol;
  *Fm = side * dM;
  *Fe = side * dM * s0;
}

/* a cell's dual flux through its mid-plane, mass flux phi, slope factor g:
   the velocity of the upwind node (u: upwind, d: downwind, b: behind it) */
static inline void Dual(double phi, double g, double vu, double vd, double vb, double wu, double wd, double wb, double *gx, double *gy, double *gk)
{
  const double vf = vu + g * VanLeer(vu - vb, vd - vu), wf = wu + g * VanLeer(wu - wb, wd - wu);
  *gx = phi * vf;
  *gy = phi * wf;
  *gk = 0.5 * phi * (vf * vf + wf * wf);
}

/* sweeps of the n x n cells along x (walls at faces 0 and n), the cells'
   volume, mass and energy at V, M, E with stride cs (1: an array each; 3:
   interleaved, a cell's three side by side), the nodes' momenta at Px, Py
   with stride ns (1 or 2); onepass: the one pass (cs = ns = 1 only), else
   the passes; w scratch of 12 (n + 2) reals.  Always inline with constant
   strides, so each form compiles with its own */
static inline __attribute__((always_inline)) void Sweeps(int onepass, const int cs, const int ns, int n, int sweeps, double dt, double A, double *restrict V, double *restrict M, double *restrict E, const double *restrict vx, const double *restrict vy, double *restrict Px, double *restrict Py, double *restrict K, double *restrict w)
{
  double *restrict rho = w, *restrict e = rho + n, *restrict Fv = e + n, *restrict Fm = Fv + n + 1, *restrict Fe = Fm + n + 1, *restrict phi = Fe + n + 1, *restrict g = phi + n;
  double *restrict Gx = g + n, *restrict Gy = Gx + n + 2, *restrict Gk = Gy + n + 2; /* G[i + 1]: cell i's; G[0] = G[n + 1] = 0 */
  int r, i, j, f, b;

  for (r = 0; r < sweeps; r++)
    for (j = 0; j < n; j++) {
      const double           sg = r % 2 ? -1.0 : 1.0; /* the flow turns each sweep: the cells at the walls neither empty nor pile up */
      double *restrict       Vj = V + cs * j * n, *restrict Mj = M + cs * j * n, *restrict Ej = E + cs * j * n;
      const double *restrict u0 = vx + j * (n + 1), *restrict u1 = u0 + n + 1;
      for (i = 0; i < n; i++) {
        rho[i] = Mj[cs * i] / Vj[cs * i];
        e[i]   = Ej[cs * i] / Mj[cs * i];
      }
      /* faces 1 and n - 1 with a clamped neighbour; interior faces branch-free
         (both donors' operands loaded, one selected) */
      Fv[0] = Fm[0] = Fe[0] = Fv[n] = Fm[n] = Fe[n] = 0.0;
      for (f = 1; f < n; f += n - 2) {
        const double delta = sg * 0.5 * dt * (u0[f] + u1[f]);
        const int    c = delta > 0.0 ? f - 1 : f, cl = c > 0 ? c - 1 : c, cr = c + 1 < n ? c + 1 : c;
        Face(delta, A, Vj[cs * c], Mj[cs * c], rho[cl], rho[c], rho[cr], e[cl], e[c], e[cr], &Fv[f], &Fm[f], &Fe[f]);
      }
      for (f = 2; f < n - 1; f++) {
        const double delta = sg * 0.5 * dt * (u0[f] + u1[f]);
        const int    p     = delta > 0.0;
        Face(delta, A, p ? Vj[cs * (f - 1)] : Vj[cs * f], p ? Mj[cs * (f - 1)] : Mj[cs * f], p ? rho[f - 2] : rho[f - 1], p ? rho[f - 1] : rho[f], p ? rho[f] : rho[f + 1], p ? e[f - 2] : e[f - 1], p ? e[f - 1] : e[f], p ? e[f] : e[f + 1], &Fv[f], &Fm[f], &Fe[f]);
      }
      if (onepass) {
        /* one pass: the cell's update, then its dual flux to the node columns j, j + 1 */
        for (i = 0; i < n; i++) {
          const double ph = 0.25 * (Fm[i] + Fm[i + 1]);
          double       gg;
          Vj[i] += Fv[i] - Fv[i + 1];
          Mj[i] += Fm[i] - Fm[i + 1];
          Ej[i] += Fe[i] - Fe[i + 1];
          gg = 0.5 * (1.0 - Min(fabs(2.0 * ph) / Mj[i], 1.0));
          for (b = 0; b < 2; b++) {
            const int oL = (j + b) * (n + 1) + i, oU = oL + 1, ob = ph > 0.0 ? (i > 0 ? oL - 1 : oL) : (i + 1 < n ? oU + 1 : oU);
            double    gx, gy, gk;
            Dual(ph, gg, ph > 0.0 ? vx[oL] : vx[oU], ph > 0.0 ? vx[oU] : vx[oL], vx[ob], ph > 0.0 ? vy[oL] : vy[oU], ph > 0.0 ? vy[oU] : vy[oL], vy[ob], &gx, &gy, &gk);
            Px[oL] -= gx;
            Px[oU] += gx;
            Py[oL] -= gy;
            Py[oU] += gy;
            K[oL] -= gk;
            K[oU] += gk;
          }
        }
      } else {
        /* passes: the cells and their mid-plane mass flux; each node row's
           dual fluxes (the end cells with a clamped node behind), then its
           nodes, each taking its left cell's flux, then its right cell's
           (the one pass's order) */
        for (i = 0; i < n; i++) {
          Vj[cs * i] += Fv[i] - Fv[i + 1];
          Mj[cs * i] += Fm[i] - Fm[i + 1];
          Ej[cs * i] += Fe[i] - Fe[i + 1];
          phi[i] = 0.25 * (Fm[i] + Fm[i + 1]);
          g[i]   = 0.5 * (1.0 - Min(fabs(2.0 * phi[i]) / Mj[cs * i], 1.0));
        }
        for (b = 0; b < 2; b++) {
          const double *restrict ux = vx + (j + b) * (n + 1), *restrict uy = vy + (j + b) * (n + 1);
          double *restrict       px = Px + ns * (j + b) * (n + 1), *restrict py = Py + ns * (j + b) * (n + 1), *restrict k = K + (j + b) * (n + 1);
          Gx[0] = Gy[0] = Gk[0] = Gx[n + 1] = Gy[n + 1] = Gk[n + 1] = 0.0;
          for (i = 0; i < n; i += n - 1) {
            const int p = phi[i] > 0.0, ib = p ? (i > 0 ? i - 1 : i) : (i + 1 < n ? i + 2 : i + 1);
            Dual(phi[i], g[i], p ? ux[i] : ux[i + 1], p ? ux[i + 1] : ux[i], ux[ib], p ? uy[i] : uy[i + 1], p ? uy[i + 1] : uy[i], uy[ib], &Gx[i + 1], &Gy[i + 1], &Gk[i + 1]);
          }
          for (i = 1; i < n - 1; i++) {
            const int p = phi[i] > 0.0;
            Dual(phi[i], g[i], p ? ux[i] : ux[i + 1], p ? ux[i + 1] : ux[i], p ? ux[i - 1] : ux[i + 2], p ? uy[i] : uy[i + 1], p ? uy[i + 1] : uy[i], p ? uy[i - 1] : uy[i + 2], &Gx[i + 1], &Gy[i + 1], &Gk[i + 1]);
          }
          for (i = 0; i <= n; i++) {
            px[ns * i] = (px[ns * i] + Gx[i]) - Gx[i + 1];
            py[ns * i] = (py[ns * i] + Gy[i]) - Gy[i + 1];
            k[i]       = (k[i] + Gk[i]) - Gk[i + 1];
          }
        }
      }
    }
}

/* the three forms, each compiled with its constant strides */
static void Form(int form, int n, int sweeps, double dt, double A, double *const st[8], double *w)
{
  if (form == 0) Sweeps(1, 1, 1, n, sweeps, dt, A, st[0], st[1], st[2], st[3], st[4], st[5], st[6], st[7], w);
  else if (form == 1) Sweeps(0, 1, 1, n, sweeps, dt, A, st[0], st[1], st[2], st[3], st[4], st[5], st[6], st[7], w);
  else Sweeps(0, 3, 2, n, sweeps, dt, A, st[0], st[0] + 1, st[0] + 2, st[3], st[4], st[5], st[5] + 1, st[7], w);
}

/* form f's value of a cell's quantity q (0 V, 1 M, 2 E), a node's momentum
   component q (3 Px, 4 Py) or kinetic energy (5 K) */
static double Value(int form, double *const st[8], int q, int c)
{
  if (q < 3) return form < 2 ? st[q][c] : st[0][3 * c + q];
  if (q < 5) return form < 2 ? st[2 + q][c] : st[5][2 * c + q - 3];
  return st[7][c];
}

int main(int argc, char **argv)
{
  const int    n = argc > 1 ? atoi(argv[1]) : 256, sweeps = argc > 2 ? atoi(argv[2]) : 200, nn = (n + 1) * (n + 1);
  const double h = 1.0 / n, A = h, Vc = h * h, dt = 0.2 * h;
  const char  *name[3] = {"one pass", "passes", "passes, interleaved"};
  double      *st[3][8], best[3] = {1e300, 1e300, 1e300}, m0 = 0.0, m1 = 0.0, *w = malloc(sizeof(double) * 12 * (n + 2));
  int          form, run, i, j, q, ok = w != NULL, same = 1;

  /* forms 0, 1: an array per quantity; form 2: V, M, E interleaved in st[2][0], Px, Py in st[2][5] */
  for (form = 0; form < 3; form++) {
    for (i = 0; i < 3; i++) ok = ok && (st[form][i] = malloc(sizeof(double) * 3 * n * n));
    for (i = 3; i < 8; i++) ok = ok && (st[form][i] = malloc(sizeof(double) * 2 * nn));
  }
  if (n < 4 || sweeps < 1 || !ok) {
    fprintf(stderr, "sweep_floor: n must be >= 4 and sweeps >= 1 (got %d, %d), or out of memory\n", n, sweeps);
    return 2;
  }
  for (run = 0; run < 5; run++)
    for (form = 0; form < 3; form++) {
      double *const  *S = st[form];
      const int       cs = form < 2 ? 1 : 3, ns = form < 2 ? 1 : 2;
      double         *V = S[0], *M = form < 2 ? S[1] : S[0] + 1, *E = form < 2 ? S[2] : S[0] + 2, *Px = S[5], *Py = form < 2 ? S[6] : S[5] + 1;
      struct timespec t0, t1;
      double          s;
      /* a gas of density 1-1.5 with a small volume ripple, moving at (0.5, 0.3) with a ripple in x */
      for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
          const int c = j * n + i;
          V[cs * c]   = Vc * (1.0 + 0.01 * sin(i));
          M[cs * c]   = V[cs * c] * (1.0 + 0.5 * (i > n / 2));
          E[cs * c]   = 2.5 * M[cs * c];
        }
      for (i = 0; i < nn; i++) {
        S[3][i] = Px[ns * i] = 0.5 + 0.1 * sin(0.01 * i);
        S[4][i] = Py[ns * i] = 0.3;
        S[7][i] = 0.0;
      }
      clock_gettime(CLOCK_MONOTONIC, &t0);
      Form(form, n, sweeps, dt, A, S, w);
      clock_gettime(CLOCK_MONOTONIC, &t1);
      s          = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
      best[form] = fmin(best[form], s);
    }
  /* walls at both ends: the last run's sweeps conserve the mass to round-off
     (a floor that did not do the sweep's work would not be one), and the
     three forms did the same arithmetic */
  for (j = 0; j < n; j++)
    for (i = 0; i < n; i++) {
      m0 += Vc * (1.0 + 0.01 * sin(i)) * (1.0 + 0.5 * (i > n / 2));
      m1 += st[1][1][j * n + i];
    }
  for (form = 0; form < 3; form += 2)
    for (q = 0; q < 6; q++)
      for (i = 0; i < (q < 3 ? n * n : nn); i++) same = same && isfinite(Value(1, st[1], q, i)) && Value(form, st[form], q, i) == Value(1, st[1], q, i);
  if (!(fabs(m1 - m0) <= 1e-12 * m0) || !same) {
    fprintf(stderr, "sweep_floor: mass %.17g after the sweeps, %.17g before; the three forms %s\n", m1, m0, same ? "agree, finite" : "differ, or a value is not finite");
    return 1;
  }
  printf("sweep floor (one gas, x-sweep, %d^2 cells, %d sweeps, best of 5 runs of each form), ns per cell and sweep:", n, sweeps);
  for (form = 0; form < 3; form++) printf(" %s %.1f%s", name[form], 1e9 * best[form] / ((double)sweeps * n * n), form < 2 ? "," : "");
  printf(" (the forms bitwise the same, mass conserved to %.1e)\n", fabs(m1 - m0) / m0);
  printf("BENCH sweep_floor_ns_%d %.6e\n", n, 1e9 * best[1] / ((double)sweeps * n * n));
  printf("BENCH sweep_floor_onepass_ns_%d %.6e\n", n, 1e9 * best[0] / ((double)sweeps * n * n));
  printf("BENCH sweep_floor_interleaved_ns_%d %.6e\n", n, 1e9 * best[2] / ((double)sweeps * n * n));
  return 0;
}
