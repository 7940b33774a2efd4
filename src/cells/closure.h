/*
  closure.h - mixed cells: how a cell's volume change is shared among its
  materials, the markers' part and void, and how cell materials are fitted
  around the markers (closure.c).
*/
#ifndef PLYSHOCK_CLOSURE_H
#define PLYSHOCK_CLOSURE_H

#include "cells.h"

#define PS_EC 3 /* cached per cell and material: p (Pa), c (m/s), compliance V/(rho c^2) (m^3/Pa) */
PETSC_INTERN PetscErrorCode PSCellsEOSCache(PSSolver *);
PETSC_INTERN PetscReal      PSCellsForcePressure(const PSCells *, const PetscReal *ec, PetscInt m0, PetscInt m1);
PETSC_INTERN PetscErrorCode PSCellsShareVolumeGeneral(const PSSolver *, const PetscReal *u, const PetscReal *ec, PetscInt m0, PetscInt m1, PetscReal dV, PetscReal dVk[], PetscReal dVr[], PetscReal *pr);

/* The volume change dV (m^3) of a cell with materials [m0, m1)
   (PSCellsPresent) shared: dVk[m] each material's, dVr[m] its part that is
   the relaxation's exchange, *pr the relaxation's pressure p* (Pa); dVr and
   pr may be NULL (closure.c).  Nearly every cell holds one material and no
   void (beyond round-off, 1e-12 of the cell, after a compression has closed
   it): there the general case's arithmetic, in its order, comes down to the
   material's share of dV beside the markers' compliance (no relaxation),
   done here without its loops or a call (the cells' Lagrangian phases call
   it twice per cell and step); anything else, the general case. */
static inline PetscErrorCode PSCellsShareVolume(const PSSolver *S, const PetscReal *u, const PetscReal *ec, PetscInt m0, PetscInt m1, PetscReal dV, PetscReal dVk[], PetscReal dVr[], PetscReal *pr)
{
  const PSCells   *C   = S->cells;
  const PetscReal *blk = &u[m0 * C->ms];

  if (m1 == m0 + 1 && blk[PS_CM] > 0.0 && blk[PS_CV] > 0.0) {
    const PetscReal VM = u[C->nmat * C->ms + PS_CX_AM] * C->Vc, chiM = u[C->nmat * C->ms + PS_CX_CM], chi = ec[PS_EC * m0 + 2];
    PetscReal       V0 = PetscMax(C->Vc - blk[PS_CV] - VM, 0.0), rest = dV;
    if (dV < 0.0) {
      const PetscReal take = PetscMin(-dV, V0);
      rest += take;
      V0 -= take;
    }
    if (V0 <= 1e-12 * C->Vc) { /* (an expansion goes to void only above PS_VOID_TRACE) */
      dVk[m0] = chi > 0.0 ? PetscMax(rest * chi / (chi + chiM), -0.5 * blk[PS_CV]) : 0.0;
      if (dVr) dVr[m0] = 0.0;
      if (pr) *pr = 0.0;
      return PETSC_SUCCESS;
    }
  }
  return PSCellsShareVolumeGeneral(S, u, ec, m0, m1, dV, dVk, dVr, pr);
}

#endif
