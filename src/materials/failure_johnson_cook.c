/*
  Johnson-Cook failure strain (Johnson & Cook, Eng. Fract. Mech. 21, 1985):
    eps_f = (D1 + D2 exp(D3 sigma*))(1 + D4 ln(max(eps_dot/eps_dot0, 1)))(1 + D5 T*),
    sigma* = sigma_m / sigma_eq (triaxiality, tension positive).
  Damage D = sum d(eps_p)/eps_f; at D >= 1 the marker carries no deviatoric
  stress and no tension (it keeps its mass and momentum).
*/
#include "../materials.h"

PetscErrorCode PSFailureJohnsonCook(const PSMaterial *M, PetscReal triax, PetscReal eps_dot, PetscReal T, PetscReal *eps_f)
{
  const PetscReal rate = PetscMax(eps_dot / M->eps_dot0, 1.0);
  const PetscReal Ts   = PetscMin(1.0, PetscMax(0.0, (T - M->T_room) / (M->T_melt - M->T_room)));

  PetscFunctionBeginUser;
  *eps_f = (M->D[0] + M->D[1] * PetscExpReal(M->D[2] * PetscMin(triax, 10.0))) * (1.0 + M->D[3] * PetscLogReal(rate)) * (1.0 + M->D[4] * Ts);
  *eps_f = PetscMax(*eps_f, 1e-6);
  PetscFunctionReturn(PETSC_SUCCESS);
}
