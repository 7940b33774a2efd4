/*
  Models by name: adding a model means a file and one line here.
*/
#include "../materials.h"

static PetscFunctionList PSEOSList = NULL, PSStrengthList = NULL, PSFailureList = NULL;

PetscErrorCode PSMaterialsRegisterAll(void)
{
  PetscFunctionBeginUser;
  if (PSEOSList) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFunctionListAdd(&PSEOSList, "none", PSEOSHydroelastic));
  PetscCall(PetscFunctionListAdd(&PSEOSList, "mie-gruneisen", PSEOSMieGruneisen));
  PetscCall(PetscFunctionListAdd(&PSStrengthList, "elastic-plastic", PSStrengthElasticPlastic));
  PetscCall(PetscFunctionListAdd(&PSStrengthList, "johnson-cook", PSStrengthJohnsonCook));
  PetscCall(PetscFunctionListAdd(&PSFailureList, "johnson-cook", PSFailureJohnsonCook));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Models of a material by name; "none" strength or failure: no function. */
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
  }
  PetscCall(PetscStrcmp(failure, "none", &none));
  M->failure_fn = NULL;
  if (!none) {
    PetscCall(PetscFunctionListFind(PSFailureList, failure, &M->failure_fn));
    PetscCheck(M->failure_fn, PETSC_COMM_SELF, PETSC_ERR_ARG_UNKNOWN_TYPE, "unknown failure type %s", failure);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
