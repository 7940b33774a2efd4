/*
  No EOS: the pressure follows the hypoelastic rate dp = -K tr(D) dt with a
  constant bulk modulus K = E / (3 (1 - 2 nu)) (isotropic elastic materials).
  Parameters: K (Pa), rho0 (kg/m^3).
*/
#include "../materials.h"

PetscErrorCode PSEOSHydroelastic(const PSMaterial *M, PetscReal J, PetscReal p_old, PetscReal dvol, PetscReal *A, PetscReal *B, PetscReal *c2)
{
  PetscFunctionBeginUser;
  *A  = p_old - M->K * dvol;
  *B  = 0.0;
  *c2 = M->K * J / M->rho0; /* K / rho */
  PetscFunctionReturn(PETSC_SUCCESS);
}
