/*
  migrate.c - after the stress update (PSMigrate): markers outside the domain
  (or with a NaN position) are removed with their mass, momentum and energy
  booked in S->lost_local; the rest are sent to the rank that owns their cell
  (DMSWARM_BASIC with owner ranks computed from the DMDA ownership ranges: the
  cell-DM migration of PETSc 3.18 can lose markers, see NOTES).
*/
#include "step.h"

/* Remove markers outside the domain (booking mass, momentum, energy), then send
   every marker to the rank that owns its cell. */
PetscErrorCode PSSolverMigrate(PSSolver *S)
{
  const PetscInt dim = S->dim;
  PSFields       f;
  PetscInt       p, d, *rank, nmove = 0, gmove;
  PetscMPIInt    me;
  PetscInt       nrm = 0, *rm = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_Migrate, 0, 0, 0, 0));
  PetscCall(PSFieldsGet(S, &f));
  PetscCall(PetscMalloc1(PetscMax(1, f.n), &rm));
  for (p = 0; p < f.n; p++) {
    PetscBool out = PETSC_FALSE;
    for (d = 0; d < dim; d++)
      if (!(f.x[p * dim + d] >= S->scene->lower[d] && f.x[p * dim + d] < S->scene->upper[d])) out = PETSC_TRUE; /* NaN too */
    if (!out) continue;
    {
      PetscReal v2 = 0.0;
      for (d = 0; d < dim; d++) {
        S->lost_local.p[d] += f.mass[p] * f.v[p * dim + d];
        v2 += f.v[p * dim + d] * f.v[p * dim + d];
      }
      S->lost_local.mass += f.mass[p];
      S->lost_local.kinetic += 0.5 * f.mass[p] * v2;
      S->lost_local.internal += f.mass[p] * f.e[p];
      S->lost_local.markers++;
    }
    rm[nrm++] = p;
  }
  PetscCall(PSFieldsRestore(S, &f));
  /* from the back: DMSwarm moves the last marker into the hole */
  for (p = nrm - 1; p >= 0; p--) PetscCall(DMSwarmRemovePointAtIndex(S->sw, rm[p]));
  PetscCall(PetscFree(rm));

  if (S->nproc[0] * S->nproc[1] * S->nproc[2] == 1) { /* one rank: nowhere to send a marker */
    PetscCall(PetscLogEventEnd(PS_EV_Migrate, 0, 0, 0, 0));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)S->sw), &me));
  PetscCall(DMSwarmGetLocalSize(S->sw, &f.n));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&f.x));
  PetscCall(DMSwarmGetField(S->sw, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  for (p = 0; p < f.n; p++) {
    PetscInt r[3] = {0, 0, 0};
    for (d = 0; d < dim; d++) {
      PetscInt cell = (PetscInt)floor((f.x[p * dim + d] - S->scene->lower[d]) * S->ih[d]), node, k = 0;
      cell = PetscMin(PetscMax(cell, 0), S->scene->cells[d] - 1);
      node = cell + S->pad;
      while (k + 1 < S->nproc[d] && node >= S->lx[d][k + 1]) k++;
      r[d] = k;
    }
    rank[p] = r[0] + S->nproc[0] * (r[1] + S->nproc[1] * r[2]);
    if (rank[p] != me) nmove++;
  }
  PetscCall(DMSwarmRestoreField(S->sw, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&f.x));
  /* most steps move no marker across a rank boundary (a marker moves less
     than a cell per step): then the swarm's exchange, with its collective
     set-up, is skipped */
  PetscCallMPI(MPI_Allreduce(&nmove, &gmove, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)S->sw)));
  if (gmove > 0) PetscCall(DMSwarmMigrate(S->sw, PETSC_TRUE));
  PetscCall(PetscLogEventEnd(PS_EV_Migrate, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
