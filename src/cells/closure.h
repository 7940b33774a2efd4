/*
  closure.h - mixed cells: how a cell's volume change is shared among its
  materials, the markers' part and void, and how cell materials are fitted
  around the markers (closure.c).
*/
#ifndef PLYSHOCK_CLOSURE_H
#define PLYSHOCK_CLOSURE_H

#include "cells.h"

PETSC_INTERN PetscErrorCode PSCellsEOSCache(PSSolver *);
PETSC_INTERN PetscErrorCode PSCellsEOSSlots(PSSolver *);
PETSC_INTERN PetscErrorCode PSCellsEOSRow(PSSolver *, PetscInt j, PetscInt k, PetscInt n0);

/* The pressure a cell's materials exert together: the compliance-weighted
   mean sum chi_k p_k / sum chi_k.  It is the pressure whose work on the
   cell's volume change equals the work the closure's shares do
   (sum_k p_k dV_k with dV_k proportional to chi_k), so the nodal force and
   the materials' energies agree; at equilibrium it is the common pressure.
   ec: the cell's cached EOS values (PSCellsEOSCache); [m0, m1) the cell's
   materials with mass (PSCellsPresent; ShareVolume's too, whose dVk and dVr
   are set for those only).  Inline: the cells' P2G and the predictor call it
   for every cell */
static inline PetscReal PSCellsForcePressure(const PetscReal *ec, PetscInt m0, PetscInt m1)
{
  PetscReal sc = 0.0, sp = 0.0;
  PetscInt  m;
  if (m1 == m0 + 1) return ec[PS_EC * m0 + 2] > 0.0 ? ec[PS_EC * m0] : 0.0; /* (one material: its p exactly, not chi p / chi) */
  for (m = m0; m < m1; m++) {
    sc += ec[PS_EC * m + 2];
    sp += ec[PS_EC * m + 2] * ec[PS_EC * m];
  }
  return sc > 0.0 ? sp / sc : 0.0;
}

/* void below this fraction of a cell is a trace (what a discarded trace of
   material, or round-off, leaves): it takes no share of an expansion, which
   goes to the materials by compliance; the relaxation still fills it, a
   free expansion at p* = 0.  Where a trace took the expansion (from 1e-12
   of the cell) while the nodal force, the materials' pressure, did its
   work, energy was made from nothing: +0.5% of a 3D charge of a gas of its
   own in air in 30 steps (now 2e-8, with the discarded traces booked) */
#define PS_VOID_TRACE 1e-4

#define PS_VOID_ROUNDOFF 1e-12 /* void below this fraction of a cell is round-off: none (no relaxation toward p* = 0) */

/* part 1 of the share (closure.c): void V0 (m^3) takes a compression
   first, and an expansion where there is void worth the name (a sliver of
   metal in a void cell must not be stretched by the cell's whole growth);
   returns the rest of dV (m^3), for the materials and the markers, and
   updates V0 */
static inline PetscReal PSCellsVoidShare(const PSCells *C, PetscReal dV, PetscReal *V0)
{
  PetscReal rest = dV;
  if (dV < 0.0) {
    const PetscReal take = PetscMin(-dV, *V0);
    rest += take;
    *V0 -= take;
  } else if (*V0 > PS_VOID_TRACE * C->Vc) {
    *V0 += dV;
    rest = 0.0;
  }
  return rest;
}

/* a material's share of the rest by its compliance chi among the materials'
   sumchi and the markers' chiM; a material gives up at most half its volume
   V in one step (a trace of gas against a stiff marker would otherwise be
   asked for more than it has; the markers' part takes the rest) */
static inline PetscReal PSCellsMaterialShare(PetscReal rest, PetscReal chi, PetscReal sumchi, PetscReal chiM, PetscReal V)
{
  if (chi == sumchi && chiM == 0.0) return sumchi > 0.0 ? PetscMax(rest, -0.5 * V) : 0.0; /* (the only compliance: all of the rest exactly, not rest chi / chi) */
  return sumchi > 0.0 ? PetscMax(rest * chi / (sumchi + chiM), -0.5 * V) : 0.0;
}

PETSC_INTERN PetscErrorCode PSCellsShareVolumeGeneral(const PSSolver *, PetscInt ci, const PetscReal *ec, PetscInt m0, PetscInt m1, PetscReal dV, PetscReal dVk[], PetscReal dVr[], PetscReal *pr);

/* The volume change dV (m^3) of a cell with materials [m0, m1)
   (PSCellsPresent) shared: dVk[m] each material's, dVr[m] its part that is
   the relaxation's exchange, *pr the relaxation's pressure p* (Pa); dVr and
   pr may be NULL (closure.c).  Nearly every cell holds one material and no
   void (beyond PS_VOID_ROUNDOFF, after a compression has closed it): there
   the general case comes down to part 1 with one material (sumchi = chi)
   and no relaxation, done here with the same pieces, without its loops or
   a call (the cells' Lagrangian phases call
   it twice per cell and step); anything else, the general case.  ci: the
   ghosted cell's index. */
static inline PetscErrorCode PSCellsShareVolume(const PSSolver *S, PetscInt ci, const PetscReal *ec, PetscInt m0, PetscInt m1, PetscReal dV, PetscReal dVk[], PetscReal dVr[], PetscReal *pr)
{
  const PSCells   *C   = S->cells;
  const PetscReal *blk = PSCellsBlk(C, ci, m0);

  if (m1 == m0 + 1 && blk[PS_CM] > 0.0 && blk[PS_CV] > 0.0) {
    const PetscReal VM = *PSCellsX(C, ci, PS_CX_AM) * C->Vc, chiM = *PSCellsX(C, ci, PS_CX_CM), chi = ec[PS_EC * m0 + 2];
    PetscReal       V0 = PetscMax(C->Vc - blk[PS_CV] - VM, 0.0), rest = PSCellsVoidShare(C, dV, &V0);
    if (V0 <= PS_VOID_ROUNDOFF * C->Vc) {
      dVk[m0] = PSCellsMaterialShare(rest, chi, chi, chiM, blk[PS_CV]);
      if (dVr) dVr[m0] = 0.0;
      if (pr) *pr = 0.0;
      return PETSC_SUCCESS;
    }
  }
  return PSCellsShareVolumeGeneral(S, ci, ec, m0, m1, dV, dVk, dVr, pr);
}

#endif
