/*
  materials.h - constitutive models, registered by name (internal).

  Each model is a small function in its own file under src/materials/ and one
  line in registry.c.  An EOS gives p = A + B e (e specific internal energy) for
  the current state, so the energy equation can be solved exactly for the
  trapezoidal pressure work; strength models give the flow stress; failure
  models the strain to failure.
*/
#ifndef PLYSHOCK_MATERIALS_H
#define PLYSHOCK_MATERIALS_H

#include "solver.h"

PETSC_INTERN PetscErrorCode PSMaterialsRegisterAll(void);

PETSC_INTERN PetscErrorCode PSEOSHydroelastic(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *, PetscReal *, PetscReal *);
PETSC_INTERN PetscErrorCode PSEOSMieGruneisen(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *, PetscReal *, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthNone(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthElasticPlastic(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthJohnsonCook(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSFailureJohnsonCook(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);

/* One marker's stress update over a step (materials/update.c).  Returns
   J = det F_new in *J (the caller stops on J <= 0) and the marker's wave speed. */
typedef struct {
  PetscReal *F;     /* dim x dim, updated */
  PetscReal  V0;    /* m^3 */
  PetscReal *vol;   /* current volume, updated */
  PetscReal *sdev;  /* unrotated deviator, updated */
  PetscReal *sig;   /* Cauchy stress (no q), updated */
  PetscReal *p, *q, *e;
  PetscReal *eps_p, *T, *D; /* NULL when not registered */
} PSMarkerState;

PETSC_INTERN PetscErrorCode PSMarkerUpdate(const PSMaterial *, PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState *, PetscReal *J, PetscReal *c);
PETSC_INTERN PetscErrorCode PSMarkerSoundSpeed(const PSMaterial *, PetscReal J, PetscReal e, PetscReal p, PetscReal *c);

#endif
