/*
  Ideal-gas EOS (gamma law): p = (gamma - 1) rho e, rho = rho0 / J, so in the
  form p = A + B e: A = 0, B = (gamma - 1) rho.  Isentropic sound speed
  c^2 = gamma p / rho, from the current pressure p_old (the caller passes the
  state's pressure).  Parameters: gamma (> 1), rho0 (kg/m^3; the material's
  density, its initial density).
*/
#include "../materials.h"

PetscErrorCode PSEOSIdealGas(const PSMaterial *M, PetscReal J, PetscReal p_old, PetscReal dvol, PetscReal *A, PetscReal *B, PetscReal *c2)
{
  const PetscReal rho = M->rho0 / J;

  PetscFunctionBeginUser;
  (void)dvol;
  *A  = 0.0;
  *B  = (M->gamma - 1.0) * rho;
  *c2 = M->gamma * PetscMax(p_old, 0.0) / rho;
  PetscFunctionReturn(PETSC_SUCCESS);
}
