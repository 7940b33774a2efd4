/*
  stress.c - the stress phase of the step (PSStress, solver.h step 5): each
  marker's velocity gradient L_p (the MUSL gradient of the re-projected nodal
  velocity, computed by the transfer, with the hoop rate L_tt = v_r/r_p in
  axisymmetric runs; or APIC's C_p), optionally F-bar
  averaged over its cell, then the
  constitutive update of its material (materials/), four 3D markers at a time
  where the material has a 4-lane kernel; then x_p += dx_p and the largest
  wave speed for the next dt.
*/
#include "step.h"

/* this rank's local index of the cell holding x (a marker's cell is owned here) */
static inline PetscInt LocalCell(const PSSolver *S, const PetscReal *x)
{
  PetscInt d, k = 0;
  for (d = S->dim - 1; d >= 0; d--) {
    PetscInt c = (PetscInt)PetscFloorReal((x[d] - S->scene->lower[d]) * S->ih[d]);
    c = PetscMin(PetscMax(c, S->cs[d]), S->ce[d] - 1);
    k = k * (S->ce[d] - S->cs[d]) + (c - S->cs[d]);
  }
  return k;
}

/* APIC's L_p = C_p as a 3x3 */
static inline void AffineL(PetscInt dim, const PetscReal *C, PetscReal L[9])
{
  PetscInt d, e;
  for (d = 0; d < 3; d++)
    for (e = 0; e < 3; e++) L[3 * d + e] = (d < dim && e < dim) ? C[d * dim + e] : 0.0;
}

/* pointers to marker p's state for the constitutive kernels */
static inline void MarkerState(const PSSolver *S, const PSFields *f, PetscInt p, PSMarkerState *st)
{
  const PetscInt dim = S->dim, ns = PSStressComponents(dim);
  memset(st, 0, sizeof(*st));
  st->F     = &f->F[p * dim * dim];
  st->V0    = f->V0[p];
  if (S->axi) {
    /* the hoop stretch from what the marker carries: V = det(F_rz) F_tt V0
       (F block diagonal in r-z and theta) */
    const PetscReal *F = st->F;
    st->Ftt = f->vol[p] / (f->V0[p] * (F[0] * F[3] - F[1] * F[2]));
  }
  st->vol   = &f->vol[p];
  st->sdev  = &f->sdev[p * ns];
  st->sig   = &f->sig[p * ns];
  st->p     = &f->p[p];
  st->q     = &f->q[p];
  st->e     = &f->e[p];
  st->eps_p = f->eps_p ? &f->eps_p[p] : NULL;
  st->T     = f->T ? &f->T[p] : NULL;
  st->D     = f->D ? &f->D[p * S->scene->ndamage] : NULL;
  if (f->axes) {
    /* a ply's axes at t = 0 from its body and ply (identity outside laminates) */
    static const PetscReal I9[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const PetscInt         k     = f->ply ? f->ply[p] : -1;
    st->axes0 = k >= 0 ? &S->scene->bodies[f->body[p]].ply_axes[9 * k] : I9;
    st->axes  = &f->axes[9 * p];
    st->smat  = &f->smat[6 * p];
  }
}

/* 5. velocity gradient, stress update; then move the markers.  Leaves the
   largest wave speed + |v| + viscous term of this rank's markers in S->smax. */
PetscErrorCode PSStressUpdate(PSSolver *S, PSFields *fp, PetscReal dt)
{
  const PetscInt dim = S->dim;
  PSFields       f   = *fp;
  PetscReal      smax = 0.0, hm = 0.0;
  PetscInt       p, d;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_Stress, 0, 0, 0, 0));
  if (S->run.fbar) {
    /* Delta-F-bar (Coombs, Augarde et al. 2018; Uintah's pressure
       stabilisation): each marker's volumetric rate is replaced by its cell's
       volume-weighted mean, which removes the volumetric locking of
       near-incompressible (plastic) flow.  A marker's cell at x^n is owned by
       this rank (migration), so the means need no communication. */
    PetscCall(PetscArrayzero(S->cell_V, S->ncell));
    PetscCall(PetscArrayzero(S->cell_trL, S->ncell));
    for (p = 0; p < f.n; p++) {
      PetscReal     *Lp = &S->Lp[9 * p];
      const PetscInt c  = LocalCell(S, &f.x[p * dim]);
      if (f.C) AffineL(dim, &f.C[p * dim * dim], Lp); /* musl: the transfer left it there */
      S->cell_V[c] += f.vol[p];
      S->cell_trL[c] += f.vol[p] * (Lp[0] + Lp[4] + Lp[8]);
    }
    for (p = 0; p < f.n; p++) {
      PetscReal     *Lp = &S->Lp[9 * p];
      const PetscInt c  = LocalCell(S, &f.x[p * dim]);
      if (S->axi) {
        /* axisymmetric: the hoop rate is a volumetric direction too, so the
           shift goes to all three diagonal terms (the 3D form) */
        const PetscReal shift = (S->cell_trL[c] / S->cell_V[c] - (Lp[0] + Lp[4] + Lp[8])) / 3.0;
        for (d = 0; d < 3; d++) Lp[4 * d] += shift;
      } else {
        const PetscReal shift = (S->cell_trL[c] / S->cell_V[c] - (Lp[0] + Lp[4] + Lp[8])) / dim;
        for (d = 0; d < dim; d++) Lp[4 * d] += shift;
      }
    }
  }
  for (d = 0; d < dim; d++) hm = PetscMax(hm, S->h[d]);
  for (p = 0; p < f.n;) {
    const PSMaterial *M = &S->mat[f.mat[p]];
    PetscReal         Lc[4][3][3], J[4], cs[4];
    const PetscReal(*L)[3][3];
    PSMarkerState st[4];
    PetscInt      k, nb = 1;

    /* four 3D markers of one material in a row go through the 4-lane kernel */
    if (dim == 3 && S->run.lanes == 4 && M->update4_fn && p + 4 <= f.n && f.mat[p + 1] == f.mat[p] && f.mat[p + 2] == f.mat[p] && f.mat[p + 3] == f.mat[p]) nb = 4;
    /* L_p: the MUSL gradient the transfer left in S->Lp (F-bar: averaged
       there), read in place; or APIC's C_p */
    if (f.C && !S->run.fbar) {
      for (k = 0; k < nb; k++) AffineL(dim, &f.C[(p + k) * dim * dim], &Lc[k][0][0]);
      L = (const PetscReal(*)[3][3])Lc;
    } else L = (const PetscReal(*)[3][3])&S->Lp[9 * p];
    for (k = 0; k < nb; k++) MarkerState(S, &f, p + k, &st[k]);
    if (nb == 4) PetscCall(M->update4_fn(M, L, dt, hm, S->run.c_linear, S->run.c_quadratic, st, J, cs));
    else PetscCall(M->update_fn(M, dim, L[0], dt, hm, S->run.c_linear, S->run.c_quadratic, &st[0], &J[0], &cs[0]));
    for (k = 0; k < nb; k++, p++) {
      PetscReal v2 = 0.0;
      if (PetscUnlikely(J[k] <= 0.0)) PetscCall(PSMarkerCheckJ(J[k], f.id[p], f.mat[p], S->step + 1, S->t));
      for (d = 0; d < dim; d++) {
        f.x[p * dim + d] += S->dx[p * dim + d];
        v2 += f.v[p * dim + d] * f.v[p * dim + d];
      }
      /* the viscous term tightens the CFL limit in compression (q / (rho c)) */
      smax = PetscMax(smax, cs[k] + PetscSqrtReal(v2) + (f.q[p] > 0.0 ? f.q[p] * f.vol[p] / (f.mass[p] * PetscMax(cs[k], 1e-300)) : 0.0));
    }
  }
  PetscCall(PetscLogEventEnd(PS_EV_Stress, 0, 0, 0, 0));
  S->smax = smax;
  PetscFunctionReturn(PETSC_SUCCESS);
}
