/*
  transfer_apic.c - the APIC transfer (Jiang et al. 2015) in the MLS-MPM form
  (Hu et al., ACM TOG 37, 2018; solver.h), quadratic B-splines only:
    1. P2G   m_i, (mv)_i with the affine term and the internal force         (PSP2G)
    2. grid  v_i = (mv)_i / m_i, boundary conditions                          (PSGridUpdate, grid.c)
    3. G2P   v_p, C_p, dx_p = dt v_p                                          (PSG2P)
  L_p = C_p (stress.c).
*/
#include "step.h"

/* quadratic B-spline weights w and offsets r = x_i - x_p (m) per direction,
   first node i0 (DMDA index); unused directions get w = (1, 0, 0), r = 0 */
typedef struct {
  PetscInt  i0[3];
  PetscReal w[3][3], r[3][3];
} PSBspline;

static inline void BsplineEval(PetscInt dim, const PetscReal lower[], const PetscReal h[], const PetscReal ih[], const PetscReal x[], PSBspline *B)
{
  PetscInt d, a;
  for (d = 0; d < 3; d++) {
    if (d < dim) {
      const PetscReal xi = (x[d] - lower[d]) * ih[d], b = PetscFloorReal(xi - 0.5), fx = xi - b;
      B->i0[d]   = (PetscInt)b + PS_PAD;
      B->w[d][0] = 0.5 * (1.5 - fx) * (1.5 - fx);
      B->w[d][1] = 0.75 - (fx - 1.0) * (fx - 1.0);
      B->w[d][2] = 0.5 * (fx - 0.5) * (fx - 0.5);
      for (a = 0; a < 3; a++) B->r[d][a] = (a - fx) * h[d];
    } else {
      B->i0[d]   = 0;
      B->w[d][0] = 1.0;
      B->w[d][1] = B->w[d][2] = 0.0;
      for (a = 0; a < 3; a++) B->r[d][a] = 0.0;
    }
  }
}

/* APIC P2G in the MLS-MPM form (solver.h): per marker the affine matrix
   Q = m_p C_p - dt V_p (sigma_p - q_p I) D_p^-1, D_p^-1 = diag(4/h^2), then per
   node (m, m v + Q (x_i - x_p)) weighted by N_ip.  dim is a constant at each
   call (always inlined: a 2D and a 3D kernel). */
static inline __attribute__((always_inline)) void P2GAPIC(const PSSolver *S, const PSFields *f, const PSIndex *ix, PetscReal dt, const PetscInt dim, PetscReal *g)
{
  /* row and plane strides of the local array, read once (the extension is
     built with -fno-strict-aliasing: an index read per row is re-read after
     every store into g) */
  const PetscInt dof = 1 + dim, nz = dim == 3 ? 3 : 1, ns = PSStressComponents(dim), sy = dof * ix->gm[0], sz = sy * ix->gm[1];
  const PetscReal *Dinv = S->Dinv, *ih = S->ih;
  PetscInt        p, d, e, a, b, c;

  for (p = 0; p < f->n; p++) {
    const PetscReal m = f->mass[p], V = f->vol[p], *Cp = &f->C[p * dim * dim];
    PetscReal       s[3][3], Q[3][3], mv[3], *g0;
    PSBspline       B;
    BsplineEval(dim, S->scene->lower, S->h, ih, &f->x[p * dim], &B);
    ForceStress(dim, &f->sig[p * ns], f->q[p], s);
    for (d = 0; d < dim; d++) {
      mv[d] = m * f->v[p * dim + d];
      for (e = 0; e < dim; e++) Q[d][e] = m * Cp[d * dim + e] - dt * V * s[d][e] * Dinv[e];
    }
    /* per row of 3 nodes along x: T = (m, m v + Q_.1 r_y + Q_.2 r_z), node a
       adds w_a (T + r_x,a Qx) with Qx = (0, Q_.0): dof-wide multiply-adds */
    g0 = &g[dof * Lidx(ix, B.i0[0], B.i0[1], B.i0[2])]; /* first node; rows sy, planes sz apart */
    if (dim == 3) {
      /* the same, 4-wide */
      const PSv4 Qx = {0.0, Q[0][0], Q[1][0], Q[2][0]}, Qy = {0.0, Q[0][1], Q[1][1], Q[2][1]}, Qz = {0.0, Q[0][2], Q[1][2], Q[2][2]};
      const PSv4 T0 = {m, mv[0], mv[1], mv[2]};
      for (c = 0; c < 3; c++) {
        const PSv4 Tz = T0 + B.r[2][c] * Qz;
        for (b = 0; b < 3; b++) {
          const PetscReal wyz = B.w[1][b] * B.w[2][c];
          const PSv4      T   = Tz + B.r[1][b] * Qy;
          PetscReal      *gr  = g0 + c * sz + b * sy;
          for (a = 0; a < 3; a++) Store4(gr + 4 * a, Load4(gr + 4 * a) + (B.w[0][a] * wyz) * (T + B.r[0][a] * Qx));
        }
      }
      continue;
    }
    for (c = 0; c < nz; c++)
      for (b = 0; b < 3; b++) {
        const PetscReal wyz = B.w[1][b] * B.w[2][c];
        PetscReal       T[4], Qx[4], *gr = g0 + c * sz + b * sy;
        T[0]  = m;
        Qx[0] = 0.0;
        for (d = 0; d < dim; d++) {
          T[1 + d]  = mv[d] + Q[d][1] * B.r[1][b] + (dim == 3 ? Q[d][2] * B.r[2][c] : 0.0);
          Qx[1 + d] = Q[d][0];
        }
        for (a = 0; a < 3; a++) {
          const PetscReal w = B.w[0][a] * wyz, ra = B.r[0][a];
          PetscReal      *gn = gr + dof * a;
          for (e = 0; e < dof; e++) gn[e] += w * (T[e] + ra * Qx[e]);
        }
      }
  }
}

/* APIC G2P: v_p = sum N v_i, C_p = sum N v_i (x_i - x_p)^T D^-1 (sums over a
   row of nodes first: per node 2 dim multiply-adds), displacement dt v_p */
static inline __attribute__((always_inline)) void G2PAPIC(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscReal *g)
{
  const PetscInt   dof = 1 + dim, nz = dim == 3 ? 3 : 1, sy = dof * ix->gm[0], sz = sy * ix->gm[1];
  const PetscReal *Dinv = S->Dinv, *ih = S->ih, *gb;
  PetscInt         p, d, e, a, b, c;

  for (p = 0; p < f->n; p++) {
    PetscReal v[4] = {0, 0, 0, 0}, Bm[3][4] = {{0}}; /* lane 1 + d: velocity component d; Bm[e][1 + d] = sum N v_d r_e */
    PSBspline B;
    BsplineEval(dim, S->scene->lower, S->h, ih, &f->x[p * dim], &B);
    gb = &g[dof * Lidx(ix, B.i0[0], B.i0[1], B.i0[2])]; /* first node; rows sy, planes sz apart */
    if (dim == 3) {
      /* the same, 4-wide */
      PSv4 vv = {0, 0, 0, 0}, B0 = {0, 0, 0, 0}, B1 = {0, 0, 0, 0}, B2 = {0, 0, 0, 0};
      for (c = 0; c < 3; c++)
        for (b = 0; b < 3; b++) {
          const PetscReal  wyz = B.w[1][b] * B.w[2][c];
          const PetscReal *gr  = gb + c * sz + b * sy;
          const PSv4       g0 = Load4(gr), g1 = Load4(gr + 4), g2 = Load4(gr + 8);
          const PSv4       sw = B.w[0][0] * g0 + B.w[0][1] * g1 + B.w[0][2] * g2;
          const PSv4       sx = (B.w[0][0] * B.r[0][0]) * g0 + (B.w[0][1] * B.r[0][1]) * g1 + (B.w[0][2] * B.r[0][2]) * g2;
          vv += wyz * sw;
          B0 += wyz * sx;
          B1 += (wyz * B.r[1][b]) * sw;
          B2 += (wyz * B.r[2][c]) * sw;
        }
      for (d = 0; d < 4; d++) {
        v[d]     = vv[d];
        Bm[0][d] = B0[d];
        Bm[1][d] = B1[d];
        Bm[2][d] = B2[d];
      }
    } else
    for (c = 0; c < nz; c++)
      for (b = 0; b < 3; b++) {
        /* a row of 3 nodes: sw = sum_a w_a g_a, sx = sum_a w_a r_x,a g_a (dof wide, lane 0 the mass) */
        const PetscReal  wyz = B.w[1][b] * B.w[2][c], ry = B.r[1][b], rz = B.r[2][c];
        const PetscReal *gr  = gb + c * sz + b * sy;
        PetscReal        sw[4] = {0, 0, 0, 0}, sx[4] = {0, 0, 0, 0};
        for (a = 0; a < 3; a++) {
          const PetscReal  w = B.w[0][a] * wyz, wr = w * B.r[0][a];
          const PetscReal *gn = gr + dof * a;
          for (e = 0; e < dof; e++) {
            sw[e] += w * gn[e];
            sx[e] += wr * gn[e];
          }
        }
        for (e = 0; e < dof; e++) {
          v[e] += sw[e];
          Bm[0][e] += sx[e];
          Bm[1][e] += ry * sw[e];
          Bm[2][e] += rz * sw[e];
        }
      }
    for (d = 0; d < dim; d++) {
      f->v[p * dim + d]  = v[1 + d];
      S->dx[p * dim + d] = dt * v[1 + d];
      for (e = 0; e < dim; e++) f->C[p * dim * dim + d * dim + e] = Bm[e][1 + d] * Dinv[e];
    }
  }
}

/* 1. P2G of the markers: mass and momentum with the affine and force terms */
PetscErrorCode PSAPICP2G(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_P2G, 0, 0, 0, 0));
  if (S->dim == 3) P2GAPIC(S, f, ix, dt, 3, S->g);
  else P2GAPIC(S, f, ix, dt, 2, S->g);
  PetscCall(PetscLogEventEnd(PS_EV_P2G, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3. G2P: velocity, affine velocity, displacement */
PetscErrorCode PSAPICG2P(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_G2P, 0, 0, 0, 0));
  if (S->dim == 3) G2PAPIC(S, f, ix, dt, 3, S->g);
  else G2PAPIC(S, f, ix, dt, 2, S->g);
  PetscCall(PetscLogEventEnd(PS_EV_G2P, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
