/*
  Zerilli-Armstrong flow stress (F. J. Zerilli & R. W. Armstrong,
  "Dislocation-mechanics-based constitutive relations for material dynamics
  calculations", J. Appl. Phys. 61 (1987) 1816), the two forms of that paper:

    fcc (zerilli-armstrong-fcc): Y = C0 + C2 eps_p^(1/2) exp(-C3 T + C4 T ln eps_dot)
    bcc (zerilli-armstrong-bcc): Y = C0 + C1 exp(-C3 T + C4 T ln eps_dot) + C5 eps_p^n

  C0 = delta sigma_G' + k l^(-1/2) (athermal stress with the grain-size term),
  C1, C2, C5 (Pa), C3, C4 (1/K), n (-), eps_dot in 1/s as in the paper (no
  reference rate), T in K.  exp(C4 T ln eps_dot) is written eps_dot^(C4 T), so
  a marker at rest (eps_dot = 0) has the thermal term 0, its limit.  The rate
  is the marker's total equivalent deviatoric rate, as for Johnson-Cook
  (update.c); T from the plastic work (Taylor-Quinney).
*/
#include "../materials.h"

PetscErrorCode PSStrengthZerilliArmstrongFCC(const PSMaterial *M, PetscReal eps_p, PetscReal eps_dot, PetscReal T, PetscReal *Y)
{
  const PSZerilliArmstrong *z = &M->za;

  PetscFunctionBeginUser;
  *Y = z->C0 + z->C2 * PetscSqrtReal(PetscMax(eps_p, 0.0)) * PetscExpReal(-z->C3 * T) * PetscPowReal(PetscMax(eps_dot, 0.0), z->C4 * T);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSStrengthZerilliArmstrongBCC(const PSMaterial *M, PetscReal eps_p, PetscReal eps_dot, PetscReal T, PetscReal *Y)
{
  const PSZerilliArmstrong *z = &M->za;

  PetscFunctionBeginUser;
  *Y = z->C0 + z->C1 * PetscExpReal(-z->C3 * T) * PetscPowReal(PetscMax(eps_dot, 0.0), z->C4 * T) + z->C5 * PetscPowReal(PetscMax(eps_p, 0.0), z->n);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Constants of either form (the front end checks them first, naming the deck key). */
PetscErrorCode PSStrengthZerilliArmstrongCheck(const PSMaterial *M)
{
  const PSZerilliArmstrong *z = &M->za;

  PetscFunctionBeginUser;
  PetscCheck(z->C0 >= 0.0 && z->C1 >= 0.0 && z->C2 >= 0.0 && z->C5 >= 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "Zerilli-Armstrong stresses C0 %g, C1 %g, C2 %g, C5 %g Pa must be >= 0", (double)z->C0, (double)z->C1, (double)z->C2, (double)z->C5);
  PetscCheck(z->C3 >= 0.0 && z->C4 >= 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Zerilli-Armstrong C3 %g, C4 %g 1/K must be >= 0", (double)z->C3, (double)z->C4);
  PetscCheck(z->n >= 0.0 && z->n <= 1.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Zerilli-Armstrong n %g must be in [0, 1]", (double)z->n);
  PetscFunctionReturn(PETSC_SUCCESS);
}
