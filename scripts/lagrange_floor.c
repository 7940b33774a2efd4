/*
  lagrange_floor.c - a floor for the cells' Lagrangian phases (scripts/bench).

  The cells' P2G, the grid update, the predictor-corrector and the
  Lagrangian phase of a single ideal gas in 2D, stripped of everything
  plyshock's phases are general in: one material (no closure, no compliance,
  no share of the volume change among materials, markers and void), no
  strength, no markers, no ghosts or ranks, no books, no time step control
  (a fixed dt), one array per quantity.  Per cell and node it does the
  arithmetic of src/cells/lagrange.c for such a cell (its lanes' kernels
  ToGridGasLanes, PredictGasLanes, LagrangeGasLanes, and the nodes' loops):
  - P2G: the ideal gas's p = (gamma - 1) E / V and c = sqrt(gamma p V / M)
    (the EOS cache), the nodal velocity v^n = P / m, the hourglass rate
    g = sum_a G(a) v_a, and each corner's mass M / 4 and force
    -(-V_c (p + q)) grad N_a - kappa M c G(a) g (one-point quadrature,
    Flanagan & Belytschko's viscous hourglass force), summed to the nodes;
  - grid: v* = v^n + dt f / m, walls all round (a wall node held at rest);
  - predictor: v^{n+1/2*} = (v^n + v*)/2, each cell's half-step volume
    change, the ideal gas's p^h (the predictor's two divisions), q^h
    (linear and quadratic viscosity, compression only), the hourglass rates
    at v^{n+1/2*}, and each corner's force change, summed to the nodes; the
    corrector v^{n+1} = v* + dt df / m;
  - Lagrange: v^{n+1/2} = (v^n + v^{n+1})/2, P = m v^{n+1}, each cell's
    velocity divergence and largest corner speed, dV = V_c dt tr D, q, the
    hourglass heat, E += heat - (p^h + q^h) dV, V += dV, and the time step's
    signal speed c + |v| + q/(rho c) (its largest value over the cells).
  The force's volume is V_c, the volume of a pure cell after the remap
  (plyshock's V_m): with it the predictor-corrector conserves the total
  energy to round-off without a remap (Caramana et al., JCP 146, 1998), which
  the floor checks.  A gas at rest with a pressure bump, walls all round.

  Three forms of the same arithmetic, run in turn and checked bitwise equal:
  - one pass: per row of cells, one loop that computes each cell's corner
    values and adds them to its four nodes (the form of plyshock's scalar
    loops);
  - passes: per row, the cells' corner values into planes (a loop free of
    loop-carried dependences, so the compiler runs it in SIMD lanes), then
    each node row gathers its corners in the one pass's order (the form of
    plyshock's lanes), an array per quantity;
  - passes, interleaved: the same over plyshock's layout, a cell's mass,
    volume and energy side by side (its material's block), its p and c side
    by side (the EOS cache), its q^h and hourglass rates side by side (the
    half-step slot), and a node's components side by side (plyshock's grid
    array holds the node's mass beside them too; here it has an array of its
    own): what the layout costs.
  Each phase is timed alone (clock_gettime around it, summed over the
  steps); the figure is ns per cell and step.  Built and run like
  sweep_floor.c, with the extension's optimisation flags:

    cc $(cat src/optflags) scripts/lagrange_floor.c -o out/lagrange_floor -lm
    out/lagrange_floor [n=256] [steps=100]      (best of 5 runs of each form)

  Not plyshock's solver: a yardstick of what these phases of this scheme
  cost on this machine once generality is gone, printed beside plyshock's own
  phases of the pure case in the same bench run.  Exits 1 if the energy was
  not conserved to round-off, a value is not finite, or the forms differ.
*/
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define ALWAYS static inline __attribute__((always_inline))

static inline double Max(double a, double b) { return a < b ? b : a; }

typedef struct {
  int    n;                               /* n x n cells, (n + 1)^2 nodes */
  double h, Vc, dt, gam, g1, cl, cq, khg; /* m, m^2 (2D), s, gamma, gamma - 1, viscosity, kappa / h / 4 */
  /* cells: mass, volume, energy (stride CS), q and p^h (1), p and c (ES), q^h and the hourglass rates (HS) */
  double *M, *V, *E, *Q, *ph, *p, *c, *qh, *gx, *gy;
  /* nodes: mass (1); momentum, v^n, f, v* (then v^{n+1}), v^{n+1/2}, df (the components VS apart) */
  double *m, *Px, *Py, *vx, *vy, *fx, *fy, *sx, *sy, *hx, *hy, *dx, *dy;
  double *R;     /* a row's planes: the corners' mass and forces (plane 2 a + d + 1) */
  double *S;     /* the signal speed of each cell of a row */
  double  smax;  /* the largest signal speed (m/s) */
  double  t[4];  /* each phase's time (s) */
  double *mem[8]; /* (the allocations) */
} Fl;

static double Now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* the strides of form il (0: an array per quantity; 1: interleaved) */
#define CS (il ? 3 : 1)
#define ES (il ? 2 : 1)
#define HS (il ? 3 : 1)
#define VS (il ? 2 : 1)

/* a row's corner values to the nodes (stride vs): node row j takes corners
   1 (cell i - 1) and 0 (cell i) after what row j - 1 left; node row j + 1
   starts with corners 3 and 2, in the one pass's order of the sums */
ALWAYS void Gather(int n, const int vs, const double *restrict c0, const double *restrict c1, const double *restrict c2, const double *restrict c3, double *restrict lo, double *restrict up)
{
  int i;
  lo[0] = lo[0] + c0[0];
  up[0] = 0.0 + c2[0];
  for (i = 1; i < n; i++) {
    lo[vs * i] = (lo[vs * i] + c1[i - 1]) + c0[i];
    up[vs * i] = (0.0 + c3[i - 1]) + c2[i];
  }
  lo[vs * n] = lo[vs * n] + c1[n - 1];
  up[vs * n] = 0.0 + c3[n - 1];
}

/* a corner's value to its node in the one pass */
#define ADD(arr, o, x) ((arr)[o] = (arr)[o] + (x))

ALWAYS double Viscosity(double rho, double h, double trD, double c, double cl, double cq)
{
  const double qv = rho * h * (cq * h * trD * trD + cl * c * fabs(trD));
  return trD < 0.0 ? qv : 0.0;
}

/* grad N_a at the centre (1/m) and G(a), the hourglass mode's signs, of the
   corners a = (0,0), (1,0), (0,1), (1,1) */
#define CORNERS \
  const double g = 0.5 / F->h, gN[4][2] = {{-g, -g}, {g, -g}, {-g, g}, {g, g}}, sg[4] = {1.0, -1.0, -1.0, 1.0}

/* P2G: EOS, v^n, corner masses and forces to the nodes */
ALWAYS void P2G(Fl *F, const int onepass, const int il)
{
  const int n = F->n, nn = n + 1;
  double *restrict M = F->M, *restrict V = F->V, *restrict E = F->E, *restrict Q = F->Q, *restrict p = F->p, *restrict c = F->c, *restrict gx = F->gx, *restrict gy = F->gy;
  double *restrict m = F->m, *restrict vx = F->vx, *restrict vy = F->vy, *restrict fx = F->fx, *restrict fy = F->fy;
  const double *restrict Px = F->Px, *restrict Py = F->Py;
  const double g1 = F->g1, gam = F->gam, Vc = F->Vc, khg = F->khg;
  int          x, j, a;
  CORNERS;

  for (x = 0; x < n * n; x++) {
    p[ES * x] = g1 * E[CS * x] / V[CS * x];
    c[ES * x] = sqrt(gam * p[ES * x] * V[CS * x] / M[CS * x]);
  }
  for (x = 0; x < nn * nn; x++) {
    vx[VS * x] = Px[VS * x] / m[x];
    vy[VS * x] = Py[VS * x] / m[x];
  }
  if (onepass) {
    for (x = 0; x < nn * nn; x++) m[x] = fx[VS * x] = fy[VS * x] = 0.0;
  } else {
    for (x = 0; x < nn; x++) m[x] = fx[VS * x] = fy[VS * x] = 0.0;
  }
  for (j = 0; j < n; j++) {
    double *restrict R = F->R;
    int              i;
#pragma GCC ivdep
    for (i = 0; i < n; i++) {
      const int    ci = j * n + i, o0 = j * nn + i, o[4] = {o0, o0 + 1, o0 + nn, o0 + nn + 1};
      const double sgm = 0.0 - Vc * p[ES * ci] - Vc * Q[ci], kap = khg * M[CS * ci] * c[ES * ci];
      double       hgx = 0.0, hgy = 0.0;
#pragma GCC unroll 4
      for (a = 0; a < 4; a++) {
        hgx += sg[a] * vx[VS * o[a]];
        hgy += sg[a] * vy[VS * o[a]];
      }
      gx[HS * ci] = hgx;
      gy[HS * ci] = hgy;
#pragma GCC unroll 4
      for (a = 0; a < 4; a++) {
        const double fa = (0.0 - sgm * gN[a][0]) - kap * sg[a] * hgx, fb = (0.0 - sgm * gN[a][1]) - kap * sg[a] * hgy;
        if (onepass) {
          ADD(m, o[a], M[CS * ci] / 4);
          ADD(fx, VS * o[a], fa);
          ADD(fy, VS * o[a], fb);
        } else {
          R[(2 * a + 1) * n + i] = fa;
          R[(2 * a + 2) * n + i] = fb;
        }
      }
      if (!onepass) R[i] = M[CS * ci] / 4;
    }
    if (!onepass) {
      Gather(n, 1, R, R, R, R, &m[j * nn], &m[(j + 1) * nn]);
      Gather(n, VS, &R[1 * n], &R[3 * n], &R[5 * n], &R[7 * n], &fx[VS * j * nn], &fx[VS * (j + 1) * nn]);
      Gather(n, VS, &R[2 * n], &R[4 * n], &R[6 * n], &R[8 * n], &fy[VS * j * nn], &fy[VS * (j + 1) * nn]);
    }
  }
}

/* the grid update v* = v^n + dt f / m, walls all round (a wall node held at rest) */
ALWAYS void Grid(Fl *F, const int il)
{
  const int              n = F->n, nn = n + 1;
  const double *restrict vx = F->vx, *restrict vy = F->vy, *restrict fx = F->fx, *restrict fy = F->fy, *restrict m = F->m, dt = F->dt;
  double *restrict       sx = F->sx, *restrict sy = F->sy;
  int                    j, i;
  for (j = 0; j < nn; j++) {
    const int w = j == 0 || j == n;
    for (i = 0; i < nn; i++) {
      const int x = j * nn + i, in = !w && i > 0 && i < n;
      sx[VS * x] = in ? vx[VS * x] + dt * fx[VS * x] / m[x] : 0.0;
      sy[VS * x] = in ? vy[VS * x] + dt * fy[VS * x] / m[x] : 0.0;
    }
  }
}

/* the predictor (the force's change at v^{n+1/2*}) and the corrector */
ALWAYS void Predict(Fl *F, const int onepass, const int il)
{
  const int n = F->n, nn = n + 1;
  double *restrict M = F->M, *restrict V = F->V, *restrict E = F->E, *restrict Q = F->Q, *restrict p = F->p, *restrict c = F->c, *restrict gx = F->gx, *restrict gy = F->gy, *restrict qh = F->qh, *restrict ph = F->ph;
  double *restrict m = F->m, *restrict vx = F->vx, *restrict vy = F->vy, *restrict sx = F->sx, *restrict sy = F->sy, *restrict hx = F->hx, *restrict hy = F->hy, *restrict dx = F->dx, *restrict dy = F->dy;
  const double g1 = F->g1, Vc = F->Vc, khg = F->khg, dt = F->dt, h = F->h, cl = F->cl, cq = F->cq;
  int          x, j, a;
  CORNERS;

  for (x = 0; x < nn * nn; x++) {
    hx[VS * x] = 0.5 * (vx[VS * x] + sx[VS * x]);
    hy[VS * x] = 0.5 * (vy[VS * x] + sy[VS * x]);
  }
  if (onepass) {
    for (x = 0; x < nn * nn; x++) dx[VS * x] = dy[VS * x] = 0.0;
  } else {
    for (x = 0; x < nn; x++) dx[VS * x] = dy[VS * x] = 0.0;
  }
  for (j = 0; j < n; j++) {
    double *restrict R = F->R;
    int              i;
#pragma GCC ivdep
    for (i = 0; i < n; i++) {
      const int ci = j * n + i, o0 = j * nn + i, o[4] = {o0, o0 + 1, o0 + nn, o0 + nn + 1};
      double    L0 = 0.0, L1 = 0.0, hgx = 0.0, hgy = 0.0;
#pragma GCC unroll 4
      for (a = 0; a < 4; a++) {
        L0 += hx[VS * o[a]] * gN[a][0];
        L1 += hy[VS * o[a]] * gN[a][1];
      }
      const double Mc = M[CS * ci], Vo = V[CS * ci], pn = p[ES * ci], cn = c[ES * ci];
      const double trD = L0 + L1, dVh = 0.5 * Vc * dt * trD;
      const double V1 = Max(Vo + dVh, 0.5 * Vo), dV = V1 - Vo, iV1 = 1.0 / V1;
      const double den = 1.0 + 0.5 * g1 * dV * iV1, pk = Max(g1 * iV1 * (E[CS * ci] - dV * (0.5 * pn + Q[ci])) / den, 0.0);
      const double q = Viscosity(Mc / V1, h, trD, cn, cl, cq), ds = 0.0 - Vc * (pk + q - pn - Q[ci]), kap = khg * Mc * cn;
#pragma GCC unroll 4
      for (a = 0; a < 4; a++) {
        hgx += sg[a] * hx[VS * o[a]];
        hgy += sg[a] * hy[VS * o[a]];
      }
#pragma GCC unroll 4
      for (a = 0; a < 4; a++) {
        const double fa = (0.0 - ds * gN[a][0]) - kap * sg[a] * (hgx - gx[HS * ci]), fb = (0.0 - ds * gN[a][1]) - kap * sg[a] * (hgy - gy[HS * ci]);
        if (onepass) {
          ADD(dx, VS * o[a], fa);
          ADD(dy, VS * o[a], fb);
        } else {
          R[(2 * a + 1) * n + i] = fa;
          R[(2 * a + 2) * n + i] = fb;
        }
      }
      gx[HS * ci] = hgx;
      gy[HS * ci] = hgy;
      qh[HS * ci] = q;
      ph[ci]      = pk;
    }
    if (!onepass) {
      Gather(n, VS, &R[1 * n], &R[3 * n], &R[5 * n], &R[7 * n], &dx[VS * j * nn], &dx[VS * (j + 1) * nn]);
      Gather(n, VS, &R[2 * n], &R[4 * n], &R[6 * n], &R[8 * n], &dy[VS * j * nn], &dy[VS * (j + 1) * nn]);
    }
  }
  /* the corrector: v^{n+1} = v* + dt df / m (into sx, sy) */
  for (j = 0; j < nn; j++) {
    const int w = j == 0 || j == n;
    int       i;
    for (i = 0; i < nn; i++) {
      const int o = j * nn + i, in = !w && i > 0 && i < n;
      sx[VS * o] = in ? sx[VS * o] + dt * dx[VS * o] / m[o] : 0.0;
      sy[VS * o] = in ? sy[VS * o] + dt * dy[VS * o] / m[o] : 0.0;
    }
  }
}

/* the Lagrangian phase: P = m v^{n+1}, the cells' volume and energy */
ALWAYS void Lagrange(Fl *F, const int il)
{
  const int n = F->n, nn = n + 1;
  double *restrict M = F->M, *restrict V = F->V, *restrict E = F->E, *restrict Q = F->Q, *restrict c = F->c, *restrict gx = F->gx, *restrict gy = F->gy, *restrict qh = F->qh, *restrict ph = F->ph;
  double *restrict m = F->m, *restrict vx = F->vx, *restrict vy = F->vy, *restrict sx = F->sx, *restrict sy = F->sy, *restrict hx = F->hx, *restrict hy = F->hy, *restrict Px = F->Px, *restrict Py = F->Py, *restrict S = F->S;
  const double Vc = F->Vc, khg = F->khg, dt = F->dt, h = F->h, cl = F->cl, cq = F->cq;
  double       smax = F->smax;
  int          x, j, a;
  CORNERS;

  for (x = 0; x < nn * nn; x++) {
    hx[VS * x] = 0.5 * (vx[VS * x] + sx[VS * x]);
    hy[VS * x] = 0.5 * (vy[VS * x] + sy[VS * x]);
    Px[VS * x] = m[x] * sx[VS * x];
    Py[VS * x] = m[x] * sy[VS * x];
  }
  for (j = 0; j < n; j++) {
    int i;
#pragma GCC ivdep
    for (i = 0; i < n; i++) {
      const int ci = j * n + i, o0 = j * nn + i, o[4] = {o0, o0 + 1, o0 + nn, o0 + nn + 1};
      double    L0 = 0.0, L1 = 0.0, v2max = 0.0, hgx = 0.0, hgy = 0.0, hgw = 0.0;
#pragma GCC unroll 4
      for (a = 0; a < 4; a++) {
        const double ux = hx[VS * o[a]], uy = hy[VS * o[a]], v2 = ux * ux + uy * uy;
        L0 += ux * gN[a][0];
        L1 += uy * gN[a][1];
        v2max = Max(v2max, v2);
        hgx += sg[a] * ux;
        hgy += sg[a] * uy;
      }
      const double Mc = M[CS * ci], cn = c[ES * ci];
      const double trD = L0 + L1, dV = Vc * dt * trD, rho = Mc / V[CS * ci], q = Viscosity(rho, h, trD, cn, cl, cq), kap = khg * Mc * cn;
      hgw += kap * gx[HS * ci] * hgx * dt;
      hgw += kap * gy[HS * ci] * hgy * dt;
      E[CS * ci] = E[CS * ci] + hgw - (ph[ci] + qh[HS * ci]) * dV;
      V[CS * ci] = V[CS * ci] + dV;
      Q[ci]      = q;
      /* the time step's signal speed (c kept at least sqrt(q/rho)/2) */
      const double cq2 = Max(cn, 0.5 * sqrt(q / rho)), sq = q > 0.0 ? q / (rho * cq2) : 0.0;
      S[i] = cn + sqrt(v2max) + sq;
    }
    for (i = 0; i < n; i++) smax = Max(smax, S[i]);
  }
  F->smax = smax;
}

/* one step, each phase timed */
ALWAYS void Step(Fl *F, const int onepass, const int il)
{
  double t0 = Now(), t1, t2, t3, t4;
  P2G(F, onepass, il);
  t1 = Now();
  Grid(F, il);
  t2 = Now();
  Predict(F, onepass, il);
  t3 = Now();
  Lagrange(F, il);
  t4 = Now();
  F->t[0] += t1 - t0;
  F->t[1] += t2 - t1;
  F->t[2] += t3 - t2;
  F->t[3] += t4 - t3;
}

/* the forms, each compiled with its constants */
static void Steps(Fl *F, int form, int steps)
{
  int s;
  for (s = 0; s < steps; s++) {
    if (form == 0) Step(F, 1, 0);
    else if (form == 1) Step(F, 0, 0);
    else Step(F, 0, 1);
  }
}

/* form il's arrays: an array per quantity, or interleaved (CS, ES, HS, VS) */
static int Alloc(Fl *F, int il)
{
  const size_t nc = (size_t)F->n * F->n, nv = (size_t)(F->n + 1) * (F->n + 1);
  double     **cell3[3] = {&F->M, &F->V, &F->E}, **cellE[2] = {&F->p, &F->c}, **cellH[3] = {&F->qh, &F->gx, &F->gy}, **cell1[2] = {&F->Q, &F->ph};
  double     **nodeV[12] = {&F->Px, &F->Py, &F->vx, &F->vy, &F->fx, &F->fy, &F->sx, &F->sy, &F->hx, &F->hy, &F->dx, &F->dy};
  int          i, k = 0;
  for (i = 0; i < 8; i++)
    if (!(F->mem[i] = calloc(12 * nv, sizeof(double)))) return 0;
  /* (each group in an allocation of its own, interleaved or in consecutive planes) */
  for (i = 0; i < 3; i++) *cell3[i] = F->mem[0] + (il ? (size_t)i : i * nc);
  for (i = 0; i < 2; i++) *cellE[i] = F->mem[1] + (il ? (size_t)i : i * nc);
  for (i = 0; i < 3; i++) *cellH[i] = F->mem[2] + (il ? (size_t)i : i * nc);
  for (i = 0; i < 2; i++) *cell1[i] = F->mem[3] + i * nc;
  for (i = 0; i < 12; i += 2, k++) {
    *nodeV[i]     = F->mem[4 + k % 3] + (k / 3) * 2 * nv;
    *nodeV[i + 1] = *nodeV[i] + (il ? 1 : nv);
  }
  F->m = F->mem[7];
  F->R = F->mem[7] + nv;
  F->S = F->R + 9 * F->n;
  return 1;
}

/* a gas of density 1 at rest, pressure 1 with a bump of 0.5 at the centre,
   gamma 1.4 */
static void Init(Fl *F, int il)
{
  const int n = F->n, nn = n + 1;
  int       i, j, a;
  for (j = 0; j < n; j++)
    for (i = 0; i < n; i++) {
      const int    ci = j * n + i;
      const double x = (i + 0.5) * F->h - 0.5, y = (j + 0.5) * F->h - 0.5, p0 = 1.0 + 0.5 * exp(-(x * x + y * y) / 0.01);
      F->M[CS * ci] = F->Vc;
      F->V[CS * ci] = F->Vc;
      F->E[CS * ci] = p0 * F->Vc / F->g1;
      F->Q[ci]      = 0.0;
    }
  for (i = 0; i < nn * nn; i++) F->m[i] = F->Px[VS * i] = F->Py[VS * i] = 0.0;
  for (j = 0; j < n; j++)
    for (i = 0; i < n; i++)
      for (a = 0; a < 4; a++) F->m[(j + (a >> 1)) * nn + i + (a & 1)] += F->M[CS * (j * n + i)] / 4;
  F->smax = 0.0;
  for (i = 0; i < 4; i++) F->t[i] = 0.0;
}

static double Energy(const Fl *F, int il)
{
  const int n = F->n, nn = n + 1;
  double    e = 0.0;
  int       x;
  for (x = 0; x < n * n; x++) e += F->E[CS * x];
  for (x = 0; x < nn * nn; x++) e += 0.5 * (F->Px[VS * x] * F->Px[VS * x] + F->Py[VS * x] * F->Py[VS * x]) / F->m[x];
  return e;
}

/* form f's value of quantity q (0 E, 1 V, 2 Q, 3 gx: cells; 4 Px, 5 Py: nodes) of cell or node x */
static double Value(const Fl *F, int form, int q, int x)
{
  const int il = form == 2;
  const double *a[6] = {F->E, F->V, F->Q, F->gx, F->Px, F->Py};
  const int     st[6] = {CS, CS, 1, HS, VS, VS};
  return a[q][st[q] * x];
}

int main(int argc, char **argv)
{
  const int   n = argc > 1 ? atoi(argv[1]) : 256, steps = argc > 2 ? atoi(argv[2]) : 100, nn = n + 1;
  const char *name[3] = {"one pass", "passes", "passes, interleaved"}, *phase[4] = {"P2G", "grid", "predictor", "Lagrange"};
  const char *key[4] = {"p2g", "grid", "predictor", "lagrange"}, *fkey[3] = {"_onepass", "", "_interleaved"};
  Fl          F[3];
  double      best[3] = {1e300, 1e300, 1e300}, bt[3][4] = {{0}}, e0 = 0.0, e1[3] = {0, 0, 0};
  int         form, run, i, q, ok = 1, same = 1, cons = 1;

  if (n < 4 || steps < 1) {
    fprintf(stderr, "lagrange_floor: n must be >= 4 and steps >= 1 (got %d, %d)\n", n, steps);
    return 2;
  }
  for (form = 0; form < 3; form++) {
    Fl *f = &F[form];
    memset(f, 0, sizeof(*f));
    f->n   = n;
    f->h   = 1.0 / n;
    f->Vc  = f->h * f->h;
    f->gam = 1.4;
    f->g1  = f->gam - 1.0;
    f->cl  = 0.2; /* run.artificial_viscosity's defaults */
    f->cq  = 2.0;
    f->khg = 0.1 / f->h / 4; /* cells.c: kappa 0.1 / min h / 2^dim */
    f->dt  = 0.4 * f->h / 1.6; /* run.cfl 0.4 over c (at most 1.53 here) + |v| */
    ok     = ok && Alloc(f, form == 2);
  }
  if (!ok) {
    fprintf(stderr, "lagrange_floor: out of memory\n");
    return 2;
  }
  for (run = 0; run < 5; run++)
    for (form = 0; form < 3; form++) {
      double t;
      Init(&F[form], form == 2);
      if (!run && !form) e0 = Energy(&F[0], 0);
      Steps(&F[form], form, steps);
      t = F[form].t[0] + F[form].t[1] + F[form].t[2] + F[form].t[3];
      if (t < best[form]) {
        best[form] = t;
        for (i = 0; i < 4; i++) bt[form][i] = F[form].t[i];
      }
      e1[form] = Energy(&F[form], form == 2);
    }
  /* the total energy (the cells' internal, the nodes' kinetic) to round-off;
     the forms the same, every value finite */
  for (form = 0; form < 3; form++) {
    cons = cons && fabs(e1[form] - e0) <= 1e-12 * e0;
    for (q = 0; q < 6; q++)
      for (i = 0; i < (q < 4 ? n * n : nn * nn); i++) same = same && isfinite(Value(&F[1], 1, q, i)) && Value(&F[form], form, q, i) == Value(&F[1], 1, q, i);
    same = same && F[form].smax == F[1].smax;
  }
  if (!cons || !same) {
    fprintf(stderr, "lagrange_floor: energy %.17g, %.17g, %.17g after the steps, %.17g before; the forms %s\n", e1[0], e1[1], e1[2], e0, same ? "agree, finite" : "differ, or a value is not finite");
    return 1;
  }
  printf("Lagrangian-phase floor (one gas, 2D, %d^2 cells, %d steps, best of 5 runs of each form), ns per cell-update:\n", n, steps);
  for (form = 0; form < 3; form++) {
    printf("  %s: total %.1f (", name[form], 1e9 * best[form] / ((double)steps * n * n));
    for (i = 0; i < 4; i++) printf("%s %.1f%s", phase[i], 1e9 * bt[form][i] / ((double)steps * n * n), i < 3 ? ", " : ")\n");
  }
  printf("  (the forms bitwise the same; energy conserved to %.1e; largest signal speed %.3f m/s)\n", fabs(e1[1] - e0) / e0, F[1].smax);
  for (form = 0; form < 3; form++) {
    printf("BENCH lagrange_floor%s_ns_%d %.6e\n", fkey[form], n, 1e9 * best[form] / ((double)steps * n * n));
    for (i = 0; i < 4; i++) printf("BENCH lagrange_floor%s_%s_ns_%d %.6e\n", fkey[form], key[i], n, 1e9 * bt[form][i] / ((double)steps * n * n));
  }
  return 0;
}
