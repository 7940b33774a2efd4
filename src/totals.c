/*
  totals.c - the conserved totals over all ranks (mass, momentum, kinetic and
  internal energy of markers and cell materials) with the booked losses and
  the contact's friction work, for history.csv and the tests.  With nothing left the peak pressure is 0 (there
  is no material to carry one), never the -DBL_MAX the maximum starts from.
*/
#include "step.h"
#include "cells/cells.h"
#include "contact.h"

/* Global totals now, with the booked losses. */
PetscErrorCode PSSolverTotals(PSSolver *S, PSTotals *T)
{
  const PetscInt dim = S->dim;
  PSFields       f;
  PetscInt       p, d;
  PetscReal      loc[12] = {0}, glob[12], pmax = -PETSC_MAX_REAL, lost[8], glost[8];
  PetscInt64     nl[2], ng[2];
  MPI_Comm       comm = PetscObjectComm((PetscObject)S->sw);

  PetscFunctionBeginUser;
  PetscCall(PSFieldsGet(S, &f));
  for (p = 0; p < f.n; p++) {
    PetscReal v2 = 0.0;
    loc[0] += f.mass[p];
    for (d = 0; d < dim; d++) {
      loc[1 + d] += f.mass[p] * f.v[p * dim + d];
      v2 += f.v[p * dim + d] * f.v[p * dim + d];
    }
    loc[4] += 0.5 * f.mass[p] * v2;
    loc[5] += f.mass[p] * f.e[p];
    pmax = PetscMax(pmax, f.p[p]);
  }
  PetscCall(PSFieldsRestore(S, &f));
  /* the cell materials: mass, nodal momentum and kinetic energy, internal
     energy, and the remap's and the markers' fit's bookkeeping */
  if (S->cells) {
    PetscCall(PSCellsTotals(S, loc, &pmax));
    loc[6] = S->cells->remap_heat;
    loc[7] = S->cells->coupling_work;
  }
  if (S->contact) {
    loc[8] = S->contact->friction_work;
    loc[9] = S->contact->interface_energy;
  }
  PetscCallMPI(MPI_Allreduce(loc, glob, 10, MPIU_REAL, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(&pmax, &T->max_pressure, 1, MPIU_REAL, MPI_MAX, comm));
  lost[0] = S->lost_local.mass;
  lost[1] = S->lost_local.p[0];
  lost[2] = S->lost_local.p[1];
  lost[3] = S->lost_local.p[2];
  lost[4] = S->lost_local.kinetic + S->lost_local.internal;
  PetscCallMPI(MPI_Allreduce(lost, glost, 5, MPIU_REAL, MPI_SUM, comm));
  nl[0] = f.n;
  nl[1] = S->lost_local.markers;
  PetscCallMPI(MPI_Allreduce(nl, ng, 2, MPIU_INT64, MPI_SUM, comm));
  T->mass     = glob[0];
  T->p[0]     = glob[1];
  T->p[1]     = glob[2];
  T->p[2]     = glob[3];
  T->kinetic  = glob[4];
  T->internal = glob[5];
  T->remap_heat    = glob[6];
  T->coupling_work = glob[7];
  T->friction_work = glob[8];
  T->interface_energy = glob[9];
  T->lost_mass = glost[0];
  T->lost_p[0] = glost[1];
  T->lost_p[1] = glost[2];
  T->lost_p[2] = glost[3];
  T->lost_energy = glost[4];
  T->markers      = ng[0];
  T->lost_markers = ng[1];
  if (T->max_pressure == -PETSC_MAX_REAL) T->max_pressure = 0.0; /* no material left anywhere */
  PetscFunctionReturn(PETSC_SUCCESS);
}
