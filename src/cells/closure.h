/*
  closure.h - mixed cells: how a cell's volume change is shared among its
  materials, the markers' part and void, and how cell materials are fitted
  around the markers (closure.c).
*/
#ifndef PLYSHOCK_CLOSURE_H
#define PLYSHOCK_CLOSURE_H

#include "cells.h"

PETSC_INTERN PetscErrorCode PSCellsShareVolume(const PSSolver *, const PetscReal *u, PetscReal dV, PetscReal dVk[]);
PETSC_INTERN PetscErrorCode PSCellsForcePressure(const PSSolver *, const PetscReal *u, PetscReal *pf);

#endif
