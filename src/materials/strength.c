/*
  Flow stress models for J2 plasticity.

  elastic-plastic: Y = yield_stress (constant).
  johnson-cook:    Y = (A + B eps_p^n)(1 + C ln(max(eps_dot/eps_dot0, 1)))(1 - T*^m),
                   T* = (T - T_room)/(T_melt - T_room) in [0, 1]
                   (Johnson & Cook, 7th Int. Symp. Ballistics, 1983).
*/
#include "../materials.h"

PetscErrorCode PSStrengthElasticPlastic(const PSMaterial *M, PetscReal eps_p, PetscReal eps_dot, PetscReal T, PetscReal *Y)
{
  PetscFunctionBeginUser;
  (void)eps_p;
  (void)eps_dot;
  (void)T;
  *Y = M->Y0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSStrengthJohnsonCook(const PSMaterial *M, PetscReal eps_p, PetscReal eps_dot, PetscReal T, PetscReal *Y)
{
  const PetscReal rate = PetscMax(eps_dot / M->eps_dot0, 1.0);
  const PetscReal Ts   = PetscMin(1.0, PetscMax(0.0, (T - M->T_room) / (M->T_melt - M->T_room)));

  PetscFunctionBeginUser;
  *Y = (M->A + M->B * PetscPowReal(PetscMax(eps_p, 0.0), M->n)) * (1.0 + M->C * PetscLogReal(rate)) * (1.0 - PetscPowReal(Ts, M->m));
  PetscFunctionReturn(PETSC_SUCCESS);
}
