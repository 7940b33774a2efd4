/*
  timestep.c - the time step from the CFL condition (PSTimeStep):
    dt = cfl h_min / max_p (c_p + |v_p| + q_p / (rho_p c_p)),
  capped in growth (dt_growth), by dt_max and by the next output or end time.
  The maximum is gathered during the stress phase (stress.c); PSSolverMaxSpeed
  computes it afresh for the first step and after a restart.
*/
#include "step.h"
#include "cells/cells.h"


/* wave speed + |v| over all markers (for the first dt and after restarts) */
PetscErrorCode PSSolverMaxSpeed(PSSolver *S)
{
  PSFields  f;
  PetscInt  p, d, dim = S->dim;
  PetscReal smax = 0.0;

  PetscFunctionBeginUser;
  PetscCall(PSFieldsGet(S, &f));
  for (p = 0; p < f.n; p++) {
    PetscReal c, v2 = 0.0, J = f.vol[p] / f.V0[p];
    PetscCall(PSMarkerSoundSpeed(&S->mat[f.mat[p]], J, f.e[p], f.p[p], &c));
    for (d = 0; d < dim; d++) v2 += f.v[p * dim + d] * f.v[p * dim + d];
    smax = PetscMax(smax, c + PetscSqrtReal(v2));
  }
  PetscCall(PSFieldsRestore(S, &f));
  if (S->cells) {
    PetscCall(PSCellsMaxSpeed(S));
    smax = PetscMax(smax, S->cells->smax);
  }
  PetscCallMPI(MPI_Allreduce(&smax, &S->smax, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)S->sw)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* dt = cfl h_min / max(c + |v|), capped in growth, by dt_max and the next stop */
PetscErrorCode PSComputeDt(PSSolver *S, PetscReal t_stop)
{
  PetscReal hmin = PETSC_MAX_REAL, dt;
  PetscInt  d;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_Dt, 0, 0, 0, 0));
  for (d = 0; d < S->dim; d++) hmin = PetscMin(hmin, S->h[d]);
  dt = S->run.cfl * hmin / PetscMax(S->smax, 1e-300);
  if (S->dt > 0) dt = PetscMin(dt, S->run.dt_growth * S->dt);
  if (S->run.dt_max > 0) dt = PetscMin(dt, S->run.dt_max);
  if (S->t + dt > t_stop) dt = t_stop - S->t;
  else if (S->t + 1.5 * dt > t_stop) dt = 0.5 * (t_stop - S->t); /* no sliver step before a stop */
  S->dt = dt;
  PetscCall(PetscLogEventEnd(PS_EV_Dt, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
