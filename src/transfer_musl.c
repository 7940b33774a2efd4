/*
  transfer_musl.c - the MUSL transfers (Sulsky, Zhou & Schreyer 1995; solver.h
  steps 1-4), in the paper's order:
    1. P2G        m_i, (mv)_i, f_i = -sum_p V_p (sigma_p - q_p I) grad N_ip   (PSP2G)
    2. grid       v_i^new = v_i + dt f_i / m_i, boundary conditions         (PSGridUpdate, grid.c)
    3. G2P        v_p FLIP/PIC blend, dx_p = dt sum_i N_ip v_i^new            (PSG2P)
    4. re-project (mv)_i = sum_p N_ip m_p v_p^{n+1}, v_i = (mv)_i / m_i     (PSReproject)
  The step's transfers all use N_ip at x_p^n: each marker's shape functions
  are evaluated once, in P2G, and kept in S->shape for G2P and the velocity
  gradient (stress.c).
*/
#include "step.h"

/* MUSL transfers (solver.h, steps 1-4): leaves the re-projected nodal
   velocity in S->Hl and each marker's shape functions in S->shape */
PetscErrorCode PSTransferMUSL(PSSolver *S, PSFields *fp, const PSIndex *ixp, PetscReal dt)
{
  const PetscInt  dim = S->dim, dof = 1 + 2 * dim;
  const PetscReal *lower = S->scene->lower;
  const PSIndex   ix = *ixp;
  PSFields        f  = *fp;
  PSShape         sh;
  PetscReal      *g, *hv;
  PetscInt        p, d, e, a, b, c, n3[3];

  PetscFunctionBeginUser;
  /* 1. P2G: mass, momentum, internal force -(sigma - q I) grad N V */
  PetscCall(PetscLogEventBegin(PS_EV_P2G, 0, 0, 0, 0));
  PetscCall(VecGetArray(S->Gl, &g));
  for (p = 0; p < f.n; p++) {
    const PetscReal *x = &f.x[p * dim], *v = &f.v[p * dim], m = f.mass[p], V = f.vol[p];
    PetscReal        s[3][3];
    ForceStress(dim, &f.sig[p * PSStressComponents(dim)], f.q[p], s);
    PSShapeEval(S->run.shape, dim, lower, S->h, x, S->run.shape == PS_SHAPE_GIMP ? HalfSize(dim, f.V0[p]) : 0.0, &S->shape[p]);
    sh    = S->shape[p]; /* the step's transfers all use N_ip at x_p^n (MUSL) */
    n3[0] = n3[1] = sh.n;
    n3[2] = dim == 3 ? sh.n : 1;
    {
      /* per marker: m v and the stress rows, then 27 (9) nodes of w, grad w */
      PetscReal mv[3], Vs[3][3];
      for (d = 0; d < dim; d++) {
        mv[d] = m * v[d];
        for (e = 0; e < dim; e++) Vs[d][e] = V * s[d][e];
      }
      for (c = 0; c < n3[2]; c++)
        for (b = 0; b < n3[1]; b++) {
          const PetscReal wyz = sh.w[1][b] * sh.w[2][c], dyz = sh.dw[1][b] * sh.w[2][c], wydz = sh.w[1][b] * sh.dw[2][c];
          PetscReal      *gr  = &g[dof * Lidx(&ix, sh.i0[0], sh.i0[1] + b, sh.i0[2] + c)];
          for (a = 0; a < n3[0]; a++) {
            const PetscReal w     = sh.w[0][a] * wyz;
            const PetscReal gw[3] = {sh.dw[0][a] * wyz, sh.w[0][a] * dyz, sh.w[0][a] * wydz};
            PetscReal      *gn    = gr + dof * a;
            gn[0] += w * m;
            for (d = 0; d < dim; d++) {
              PetscReal fd = 0.0;
              for (e = 0; e < dim; e++) fd += Vs[d][e] * gw[e];
              gn[1 + d] += w * mv[d];
              gn[1 + dim + d] -= fd;
            }
          }
        }
    }
  }
  PetscCall(PetscLogEventEnd(PS_EV_P2G, 0, 0, 0, 0));
  PetscCall(PSHaloReduce(S->sfg, g));

  /* 2. grid: v_new = v_old + dt f/m with the boundary conditions (grid.c) */
  PetscCall(PetscLogEventBegin(PS_EV_Grid, 0, 0, 0, 0));
  PSGridUpdateMUSL(S, &ix, dt, g);
  PetscCall(PetscLogEventEnd(PS_EV_Grid, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(S->sfg, g));

  /* 3. G2P: v_p = (1 - a)(v_p + sum N dv) + a sum N v_new; dx_p = dt sum N v_new;
     4. and in the same pass the re-projection (mv)_i = sum_p N_ip m_p v_p^{n+1} */
  PetscCall(PetscLogEventBegin(PS_EV_G2P, 0, 0, 0, 0));
  PetscCall(VecGetArray(S->Hl, &hv));
  for (p = 0; p < f.n; p++) {
    PetscReal      vpic[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, mv[3];
    const PSShape *sp      = &S->shape[p];
    n3[0] = n3[1] = sp->n;
    n3[2] = dim == 3 ? sp->n : 1;
    {
      /* accumulate in registers: v_pic = sum N v_new, dv = sum N (v_new - v_old) */
      PetscReal a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;
      for (c = 0; c < n3[2]; c++)
        for (b = 0; b < n3[1]; b++) {
          const PetscReal  wyz = sp->w[1][b] * sp->w[2][c];
          const PetscReal *gr  = &g[dof * Lidx(&ix, sp->i0[0], sp->i0[1] + b, sp->i0[2] + c)];
          if (dim == 3)
            for (a = 0; a < n3[0]; a++) {
              const PetscReal  w  = sp->w[0][a] * wyz;
              const PetscReal *gn = gr + 7 * a;
              a0 += w * gn[1];
              a1 += w * gn[2];
              a2 += w * gn[3];
              b0 += w * gn[4];
              b1 += w * gn[5];
              b2 += w * gn[6];
            }
          else
            for (a = 0; a < n3[0]; a++) {
              const PetscReal  w  = sp->w[0][a] * wyz;
              const PetscReal *gn = gr + 5 * a;
              a0 += w * gn[1];
              a1 += w * gn[2];
              b0 += w * gn[3];
              b1 += w * gn[4];
            }
        }
      vpic[0] = a0;
      vpic[1] = a1;
      vpic[2] = a2;
      dv[0]   = b0;
      dv[1]   = b1;
      dv[2]   = b2;
    }
    for (d = 0; d < dim; d++) {
      f.v[p * dim + d]   = (1.0 - S->run.pic_fraction) * (f.v[p * dim + d] + dv[d]) + S->run.pic_fraction * vpic[d];
      S->dx[p * dim + d] = dt * vpic[d];
      mv[d]              = f.mass[p] * f.v[p * dim + d];
    }
    for (c = 0; c < n3[2]; c++)
      for (b = 0; b < n3[1]; b++) {
        const PetscReal wyz = sp->w[1][b] * sp->w[2][c];
        PetscReal      *hr  = &hv[dim * Lidx(&ix, sp->i0[0], sp->i0[1] + b, sp->i0[2] + c)];
        for (a = 0; a < n3[0]; a++) {
          const PetscReal w  = sp->w[0][a] * wyz;
          PetscReal      *hn = hr + dim * a;
          for (d = 0; d < dim; d++) hn[d] += w * mv[d];
        }
      }
  }
  PetscCall(PetscLogEventEnd(PS_EV_G2P, 0, 0, 0, 0));

  PetscCall(PetscLogEventBegin(PS_EV_Reproject, 0, 0, 0, 0));
  PetscCall(PSHaloReduce(S->sfh, hv));
  PSGridVelocity(S, &ix, g, dof, hv, dim); /* v_i = (mv)_i / m_i, boundary conditions */
  PetscCall(PetscLogEventEnd(PS_EV_Reproject, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(S->sfh, hv));
  PetscCall(VecRestoreArray(S->Hl, &hv));
  PetscCall(VecRestoreArray(S->Gl, &g));
  PetscFunctionReturn(PETSC_SUCCESS);
}
