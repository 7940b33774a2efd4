/*
  fields.c - the scene's registered marker fields, got and restored together
  (a field a scene does not need is not registered and stays NULL).
*/
#include "step.h"

PetscErrorCode PSGridIndex(DM da, PSIndex *ix)
{
  PetscFunctionBeginUser;
  PetscCall(DMDAGetGhostCorners(da, &ix->gs[0], &ix->gs[1], &ix->gs[2], &ix->gm[0], &ix->gm[1], &ix->gm[2]));
  PetscCall(DMDAGetCorners(da, &ix->os[0], &ix->os[1], &ix->os[2], &ix->om[0], &ix->om[1], &ix->om[2]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSFieldsGet(PSSolver *S, PSFields *f)
{
  DM sw = S->sw;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(f, sizeof(*f)));
  PetscCall(DMSwarmGetLocalSize(sw, &f->n));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_X, NULL, NULL, (void **)&f->x));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&f->v));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&f->mass));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&f->vol));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_V0, NULL, NULL, (void **)&f->V0));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_F, NULL, NULL, (void **)&f->F));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&f->sig));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_SDEV, NULL, NULL, (void **)&f->sdev));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&f->p));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_Q, NULL, NULL, (void **)&f->q));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&f->e));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&f->mat));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_ID, NULL, NULL, (void **)&f->id));
  if (S->scene->need_plastic) PetscCall(DMSwarmGetField(sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&f->eps_p));
  if (S->scene->need_temperature) PetscCall(DMSwarmGetField(sw, PS_FIELD_TEMP, NULL, NULL, (void **)&f->T));
  if (S->scene->ndamage) PetscCall(DMSwarmGetField(sw, PS_FIELD_DAMAGE, NULL, NULL, (void **)&f->D));
  if (S->scene->need_affine) PetscCall(DMSwarmGetField(sw, PS_FIELD_AFFINE, NULL, NULL, (void **)&f->C));
  if (S->scene->need_interface) PetscCall(DMSwarmGetField(sw, PS_FIELD_IDAMAGE, NULL, NULL, (void **)&f->Di));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&f->body)); /* every scene registers it: orthotropic kernels, contact fields, the dt guard */
  if (S->scene->anisotropic) {
    PetscCall(DMSwarmGetField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&f->axes));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_SMAT, NULL, NULL, (void **)&f->smat));
  }
  if (S->has_ply) PetscCall(DMSwarmGetField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&f->ply)); /* ply fields of cohesive interfaces, orthotropic kernels */
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSFieldsRestore(PSSolver *S, PSFields *f)
{
  DM sw = S->sw;

  PetscFunctionBeginUser;
  if (f->C) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_AFFINE, NULL, NULL, (void **)&f->C));
  if (f->Di) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_IDAMAGE, NULL, NULL, (void **)&f->Di));
  if (f->ply) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&f->ply));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&f->body));
  if (f->smat) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_SMAT, NULL, NULL, (void **)&f->smat));
  if (f->axes) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&f->axes));
  if (f->D) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_DAMAGE, NULL, NULL, (void **)&f->D));
  if (f->T) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_TEMP, NULL, NULL, (void **)&f->T));
  if (f->eps_p) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&f->eps_p));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_ID, NULL, NULL, (void **)&f->id));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&f->mat));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&f->e));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_Q, NULL, NULL, (void **)&f->q));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&f->p));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_SDEV, NULL, NULL, (void **)&f->sdev));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&f->sig));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_F, NULL, NULL, (void **)&f->F));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_V0, NULL, NULL, (void **)&f->V0));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&f->vol));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&f->mass));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&f->v));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_X, NULL, NULL, (void **)&f->x));
  PetscFunctionReturn(PETSC_SUCCESS);
}
