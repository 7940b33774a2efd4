/*
  Models by name: adding a model means a file and one line here.
*/
#include "../materials.h"

static PetscFunctionList PSEOSList = NULL, PSStrengthList = NULL, PSStrengthCheckList = NULL, PSFailureList = NULL, PSPlyFailureList = NULL;

PetscErrorCode PSMaterialsRegisterAll(void)
{
  PetscFunctionBeginUser;
  if (PSEOSList) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFunctionListAdd(&PSEOSList, "none", PSEOSHydroelastic));
  PetscCall(PetscFunctionListAdd(&PSEOSList, "mie-gruneisen", PSEOSMieGruneisen));
  PetscCall(PetscFunctionListAdd(&PSEOSList, "ideal-gas", PSEOSIdealGas));
  PetscCall(PetscFunctionListAdd(&PSStrengthList, "elastic-plastic", PSStrengthElasticPlastic));
  PetscCall(PetscFunctionListAdd(&PSStrengthList, "johnson-cook", PSStrengthJohnsonCook));
  PetscCall(PetscFunctionListAdd(&PSStrengthList, "zerilli-armstrong-fcc", PSStrengthZerilliArmstrongFCC));
  PetscCall(PetscFunctionListAdd(&PSStrengthList, "zerilli-armstrong-bcc", PSStrengthZerilliArmstrongBCC));
  PetscCall(PetscFunctionListAdd(&PSStrengthList, "mts", PSStrengthMTS));
  /* checks of a strength model's constants, by the same name (optional) */
  PetscCall(PetscFunctionListAdd(&PSStrengthCheckList, "zerilli-armstrong-fcc", PSStrengthZerilliArmstrongCheck));
  PetscCall(PetscFunctionListAdd(&PSStrengthCheckList, "zerilli-armstrong-bcc", PSStrengthZerilliArmstrongCheck));
  PetscCall(PetscFunctionListAdd(&PSStrengthCheckList, "mts", PSStrengthMTSCheck));
  PetscCall(PetscFunctionListAdd(&PSFailureList, "johnson-cook", PSFailureJohnsonCook));
  PetscCall(PetscFunctionListAdd(&PSPlyFailureList, "hashin", PSPlyFailureHashin));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Models of a material by name; "none" strength or failure: no function.
   M->aniso (set by the caller) picks the orthotropic kernel and ply failure models. */
PetscErrorCode PSMaterialInit(PSMaterial *M, const char eos[], const char strength[], const char failure[])
{
  PetscBool none;

  PetscFunctionBeginUser;
  PetscCall(PSMaterialsRegisterAll());
  PetscCall(PetscFunctionListFind(PSEOSList, eos, &M->eos_fn));
  PetscCheck(M->eos_fn, PETSC_COMM_SELF, PETSC_ERR_ARG_UNKNOWN_TYPE, "unknown EOS type %s", eos);
  PetscCall(PetscStrcmp(strength, "none", &none));
  M->strength_fn = NULL;
  if (!none) {
    PetscCall(PetscFunctionListFind(PSStrengthList, strength, &M->strength_fn));
    PetscCheck(M->strength_fn, PETSC_COMM_SELF, PETSC_ERR_ARG_UNKNOWN_TYPE, "unknown strength type %s", strength);
    {
      PSStrengthCheckFn check = NULL;
      PetscCall(PetscFunctionListFind(PSStrengthCheckList, strength, &check));
      if (check) PetscCall(check(M));
    }
  }
  PetscCheck(!M->aniso || !M->strength_fn, PETSC_COMM_SELF, PETSC_ERR_SUP, "strength type %s: orthotropic plies have no plasticity", strength);
  PetscCall(PetscStrcmp(failure, "none", &none));
  M->failure_fn     = NULL;
  M->ply_failure_fn = NULL;
  if (!none && M->aniso) {
    PetscCall(PetscFunctionListFind(PSPlyFailureList, failure, &M->ply_failure_fn));
    PetscCheck(M->ply_failure_fn, PETSC_COMM_SELF, PETSC_ERR_ARG_UNKNOWN_TYPE, "unknown ply failure type %s", failure);
  } else if (!none) {
    PetscCall(PetscFunctionListFind(PSFailureList, failure, &M->failure_fn));
    PetscCheck(M->failure_fn, PETSC_COMM_SELF, PETSC_ERR_ARG_UNKNOWN_TYPE, "unknown failure type %s", failure);
  }
  M->update_fn  = M->aniso ? PSMarkerUpdateOrthotropic : PSMarkerUpdate;
  M->update4_fn = (M->aniso || M->failure_fn) ? NULL : PSMarkerUpdate4;
  /* no EOS model and no spall: the 4-lane kernel with the pressure and energy in lanes */
  if (M->update4_fn && M->eos_fn == PSEOSHydroelastic && !(M->spall < 0.0)) M->update4_fn = PSMarkerUpdate4Elastic;
  PetscFunctionReturn(PETSC_SUCCESS);
}
