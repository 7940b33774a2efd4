/*
  step.c - one explicit time step as named phases (solver.h gives the MPM
  algorithms, cells/cells.h the Eulerian cells; step.h lists the file of each
  phase):

    dt          timestep.c        CFL over markers and cells, growth limit, next stop
    reset       grid.c            zero the nodes the last step wrote, note this step's box
    P2G         transfer_*.c      markers' mass, momentum, force to the nodes
                contact.c         (bodies in contact) the fields' masses, the shared nodes, the markers near
                                  them; for those the same per velocity field, and its mass gradient
                cells/lagrange.c  cells' nodal mass, momentum, force (same nodes)
    grid        grid.c            ghost sums, v_i with the boundary conditions, ghosts back
    contact     contact.c         (bodies in contact) each field's v_i (with its share of the cells'), the contact law where fields meet
    predict     cells/lagrange.c  the cells' half-step state and force; v_i corrected by its change
                contact.c         (bodies in contact) the correction to each field where fields meet
    G2P         transfer_*.c      markers' velocity and displacement (musl: re-projection)
                contact.c         (bodies in contact) redone for the markers near shared nodes, from their field
    Lagrange    cells/lagrange.c  cells deform with the nodal velocity: closure, EOS, strength
    re-project  transfer_musl.c   (musl) the re-projected velocity and L_p (none without markers)
                contact.c         (bodies in contact) the fields' re-projected velocity, contact law, L_p
                                  redone for the markers near shared nodes
    stress      stress.c          markers' constitutive update, x_p += dx_p
    remap       cells/remap.c     cell materials and their momentum back to the fixed grid
    migrate     migrate.c         out-of-domain markers booked, the rest to their owners
    fit         cells/closure.c   cell materials fitted around the markers' new volume (discarded, booked,
                                  where bodies meet in contact)
    huge pages  memory.c          (after the first step, then every PS_HUGE_EVERY) the large arrays on
                                  transparent huge pages
*/
#include "step.h"
#include "cells/cells.h"
#include "contact.h"

#define PS_HUGE_EVERY 1000 /* steps between the huge pages' advice (memory.c) */

/* scratch arrays sized for n markers (kept between steps) */
static PetscErrorCode EnsureScratch(PSSolver *S, PetscInt n)
{
  PetscFunctionBeginUser;
  if (n <= S->ncache) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree(S->dx));
  PetscCall(PetscFree(S->at));
  PetscCall(PetscFree(S->Lp));
  S->ncache = (PetscInt)(1.2 * n) + 16;
  PetscCall(PetscMalloc1(S->ncache * S->dim, &S->dx));
  if (S->run.transfer == PS_TRANSFER_MUSL) PetscCall(PetscMalloc1(S->ncache, &S->at));
  if (S->run.transfer == PS_TRANSFER_MUSL || S->run.fbar) PetscCall(PetscMalloc1(9 * S->ncache, &S->Lp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSSolverStep(PSSolver *S, PetscReal t_stop)
{
  const PetscBool musl = S->run.transfer == PS_TRANSFER_MUSL;
  PSIndex         ix;
  PSFields        f;
  PetscInt        box[3][2];
  PetscReal       smax, dt;

  PetscFunctionBeginUser;
  PetscCall(PSComputeDt(S, t_stop));
  dt = S->dt;
  PetscCall(PSGridIndex(S->da, &ix));
  PetscCall(PSFieldsGet(S, &f));
  PetscCall(EnsureScratch(S, f.n));

  PetscCall(PSGridActiveBox(S, &f, box));
  PetscCall(PSGridReset(S, &ix, box, PSCellsSums(S))); /* (with the sums the cells' P2G writes the grid's every node itself: lagrange.c) */
  if (musl) PetscCall(PSMUSLP2G(S, &f, &ix));
  else PetscCall(PSAPICP2G(S, &f, &ix, dt));
  if (S->contact) PetscCall(PSContactP2G(S, &f, &ix));
  if (PSCellsPipelined(S, &ix)) PetscCall(PSCellsPipeline(S, &ix, dt)); /* the three phases below as one pipeline of units (lagrange.c) */
  else {
    if (S->cells) PetscCall(PSCellsToGrid(S, &ix, dt));
    PetscCall(PSGridSolve(S, &ix, dt));
    if (S->contact) PetscCall(PSContactGridSolve(S, &ix, dt));
    if (S->cells) PetscCall(PSCellsPredict(S, &ix, dt)); /* the cells' half-step force, v^{n+1} corrected */
  }
  if (S->cells && S->contact) PetscCall(PSContactCellsSync(S, &ix)); /* that correction to the fields where bodies meet */
  if (musl) PetscCall(PSMUSLG2P(S, &f, &ix, dt)); /* with contact too: contact.c redoes the markers near shared nodes */
  else PetscCall(PSAPICG2P(S, &f, &ix, dt));
  if (S->contact) PetscCall(PSContactG2P(S, &f, &ix, dt));
  if (S->cells) PetscCall(PSCellsLagrange(S, &ix, dt));
  if (PSSolverReprojects(S)) PetscCall(PSMUSLReproject(S, &f, &ix));
  if (S->contact) PetscCall(PSContactReproject(S, &f, &ix));
  PetscCall(PSStressUpdate(S, &f, dt));
  if (S->cells) PetscCall(PSCellsRemap(S, &ix, dt));
  PetscCall(PSFieldsRestore(S, &f));
  smax = S->smax;
  if (S->cells) smax = PetscMax(smax, S->cells->smax);
  PetscCallMPI(MPI_Allreduce(&smax, &S->smax, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)S->sw)));

  PetscCall(PSSolverMigrate(S));
  if (S->cells) PetscCall(PSCellsFitMarkers(S, PETSC_TRUE));
  S->t += dt;
  S->step++;
  /* the large arrays on huge pages (memory.c): after this solver's first
     step, when every array of the step exists, and every PS_HUGE_EVERY
     steps after it */
  if (S->run.hugepages && S->nstep_here % PS_HUGE_EVERY == 0) {
    PetscLogDouble bytes;
    PetscCall(PetscLogEventBegin(PS_EV_Huge, 0, 0, 0, 0));
    PetscCall(PSMemoryHugePages(&bytes));
    PetscCall(PetscLogEventEnd(PS_EV_Huge, 0, 0, 0, 0));
    PetscCall(PetscInfo(NULL, "step %" PetscInt_FMT ": huge pages advised over %.1f MB\n", S->step, bytes / 1048576.0));
  }
  S->nstep_here++;
  PetscFunctionReturn(PETSC_SUCCESS);
}
