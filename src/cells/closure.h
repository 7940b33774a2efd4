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
PETSC_INTERN PetscErrorCode PSCellsShareVolume(const PSSolver *, const PetscReal *u, const PetscReal *ec, PetscInt m0, PetscInt m1, PetscReal dV, PetscReal dVk[], PetscReal dVr[], PetscReal *pr);

#endif
