/*
  step.c - one explicit MPM time step as named phases (solver.h gives the
  algorithms; step.h lists the file of each phase):

    dt        timestep.c   CFL, growth limit, next stop
    reset     grid.c       zero the nodes the last step wrote, note this step's box
    transfer  transfer_musl.c | transfer_apic.c   P2G, grid update, G2P
    stress    stress.c     L_p, constitutive update, x_p += dx_p
    migrate   migrate.c    out-of-domain markers booked, the rest to their owners
*/
#include "step.h"

/* scratch arrays sized for n markers (kept between steps) */
static PetscErrorCode EnsureScratch(PSSolver *S, PetscInt n)
{
  PetscFunctionBeginUser;
  if (n <= S->ncache) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree(S->dx));
  PetscCall(PetscFree(S->shape));
  PetscCall(PetscFree(S->Lp));
  S->ncache = (PetscInt)(1.2 * n) + 16;
  PetscCall(PetscMalloc1(S->ncache * S->dim, &S->dx));
  if (S->run.transfer == PS_TRANSFER_MUSL) PetscCall(PetscMalloc1(S->ncache, &S->shape));
  if (S->run.transfer == PS_TRANSFER_MUSL || S->run.fbar) PetscCall(PetscMalloc1(9 * S->ncache, &S->Lp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSSolverStep(PSSolver *S, PetscReal t_stop)
{
  PSIndex  ix;
  PSFields f;
  PetscInt box[3][2];
  PetscReal smax;

  PetscFunctionBeginUser;
  PetscCall(PSComputeDt(S, t_stop));
  PetscCall(PSGridIndex(S->da, &ix));
  PetscCall(PSFieldsGet(S, &f));
  PetscCall(EnsureScratch(S, f.n));

  PetscCall(PSGridActiveBox(S, &f, box));
  PetscCall(PSGridReset(S, &ix, box));
  if (S->run.transfer == PS_TRANSFER_APIC) PetscCall(PSTransferAPIC(S, &f, &ix, S->dt));
  else PetscCall(PSTransferMUSL(S, &f, &ix, S->dt));
  PetscCall(PSStressUpdate(S, &f, S->dt));
  PetscCall(PSFieldsRestore(S, &f));
  smax = S->smax;
  PetscCallMPI(MPI_Allreduce(&smax, &S->smax, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)S->sw)));

  PetscCall(PSSolverMigrate(S));
  S->t += S->dt;
  S->step++;
  PetscFunctionReturn(PETSC_SUCCESS);
}
