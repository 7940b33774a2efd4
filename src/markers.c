/*
  markers.c - the marker swarm: which fields a scene needs, and which cells a
  rank owns.

  The swarm is DMSWARM_BASIC (see ../shared/NOTES.md: PIC migration with a
  DMDA cell DM loses markers in PETSc 3.18); owners are computed from the DMDA
  ownership ranges.  Cell c (between nodes c and c+1) belongs to the rank that
  owns node c, so the last rank in each direction owns one cell fewer than nodes.
*/
#include "plyshock.h"

typedef struct {
  const char   *name;
  PetscInt      bs;    /* block size; -1 = dim, -2 = dim^2, -3 = stress components, -4 = damage components */
  PetscDataType type;
} PSField;

static PetscInt BlockSize(const PSScene *scene, PetscInt bs)
{
  const PetscInt dim = scene->dim;
  return bs == -1 ? dim : bs == -2 ? dim * dim : bs == -3 ? PSStressComponents(dim) : bs == -4 ? scene->ndamage : bs;
}

/* Every field a marker may carry, and when it is registered. */
static PetscBool FieldNeeded(const PSScene *scene, const char *name)
{
  PetscInt b;
  if (!strcmp(name, PS_FIELD_AXES)) return scene->anisotropic;
  if (!strcmp(name, PS_FIELD_EPS_P)) return scene->need_plastic;
  if (!strcmp(name, PS_FIELD_TEMP)) return scene->need_temperature;
  if (!strcmp(name, PS_FIELD_DAMAGE)) return scene->ndamage > 0;
  if (!strcmp(name, PS_FIELD_SMAT)) return scene->anisotropic;
  if (!strcmp(name, PS_FIELD_AFFINE)) return scene->need_affine;
  if (!strcmp(name, PS_FIELD_IDAMAGE)) return scene->need_interface;
  if (!strcmp(name, PS_FIELD_PLY)) {
    for (b = 0; b < scene->nbody; b++)
      if (scene->bodies[b].kind == PS_BODY_LAMINATE) return PETSC_TRUE;
    return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

static const PSField PSFields[] = {
  {PS_FIELD_X,        -1, PETSC_REAL },
  {PS_FIELD_VELOCITY, -1, PETSC_REAL },
  {PS_FIELD_MASS,     1,  PETSC_REAL },
  {PS_FIELD_VOLUME,   1,  PETSC_REAL },
  {PS_FIELD_AXES,     9,  PETSC_REAL },
  {PS_FIELD_ID,       1,  PETSC_INT64},
  {PS_FIELD_BODY,     1,  PETSC_INT  },
  {PS_FIELD_PLY,      1,  PETSC_INT  },
  {PS_FIELD_MATERIAL, 1,  PETSC_INT  },
  {PS_FIELD_F,        -2, PETSC_REAL },
  {PS_FIELD_V0,       1,  PETSC_REAL },
  {PS_FIELD_STRESS,   -3, PETSC_REAL },
  {PS_FIELD_SDEV,     -3, PETSC_REAL },
  {PS_FIELD_PRESSURE, 1,  PETSC_REAL },
  {PS_FIELD_Q,        1,  PETSC_REAL },
  {PS_FIELD_ENERGY,   1,  PETSC_REAL },
  {PS_FIELD_EPS_P,    1,  PETSC_REAL },
  {PS_FIELD_TEMP,     1,  PETSC_REAL },
  {PS_FIELD_DAMAGE,   -4, PETSC_REAL },
  {PS_FIELD_SMAT,     6,  PETSC_REAL },
  {PS_FIELD_AFFINE,   -2, PETSC_REAL },
  {PS_FIELD_IDAMAGE,  1,  PETSC_REAL },
};

/* Register the scene's fields on a fresh swarm. */
PetscErrorCode PSMarkersRegisterFields(const PSScene *scene, DM sw, PetscInt *bytes_per_marker)
{
  size_t   f;
  PetscInt bytes = 0, bs;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmInitializeFieldRegister(sw));
  for (f = 0; f < sizeof(PSFields) / sizeof(PSFields[0]); f++) {
    if (!FieldNeeded(scene, PSFields[f].name)) continue;
    bs = BlockSize(scene, PSFields[f].bs);
    PetscCall(DMSwarmRegisterPetscDatatypeField(sw, PSFields[f].name, bs, PSFields[f].type));
  }
  PetscCall(DMSwarmFinalizeFieldRegister(sw));
  /* what the swarm adds itself is counted once local sizes are set */
  if (bytes_per_marker) {
    PetscCall(PSMarkersBytes(scene, NULL, &bytes));
    *bytes_per_marker = bytes;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The fields a scene registers, in registration order (for checkpoints). */
PetscErrorCode PSMarkersFieldList(const PSScene *scene, PetscInt *n, const char *names[], PetscInt bs[], PetscDataType types[])
{
  size_t f;

  PetscFunctionBeginUser;
  *n = 0;
  for (f = 0; f < sizeof(PSFields) / sizeof(PSFields[0]); f++) {
    if (!FieldNeeded(scene, PSFields[f].name)) continue;
    names[*n] = PSFields[f].name;
    bs[*n]    = BlockSize(scene, PSFields[f].bs);
    types[*n] = PSFields[f].type;
    (*n)++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Bytes per marker: every registered field, the swarm's own fields included.
   With sw == NULL, what the scene would register (for `plyshock check`). */
PetscErrorCode PSMarkersBytes(const PSScene *scene, DM sw, PetscInt *bytes)
{
  size_t        f, sz;
  PetscInt      bs;
  PetscDataType type;
  const char   *own[] = {DMSwarmField_pid, DMSwarmField_rank};

  PetscFunctionBeginUser;
  *bytes = 0;
  for (f = 0; f < sizeof(PSFields) / sizeof(PSFields[0]); f++) {
    if (!FieldNeeded(scene, PSFields[f].name)) continue;
    bs = BlockSize(scene, PSFields[f].bs);
    PetscCall(PetscDataTypeGetSize(PSFields[f].type, &sz));
    *bytes += bs * (PetscInt)sz;
  }
  for (f = 0; f < 2; f++) {
    if (sw) {
      void *ptr;
      PetscCall(DMSwarmGetField(sw, own[f], &bs, &type, &ptr));
      PetscCall(DMSwarmRestoreField(sw, own[f], &bs, &type, &ptr));
    } else {
      bs   = 1;
      type = f == 0 ? PETSC_INT64 : PETSC_INT;
    }
    PetscCall(PetscDataTypeGetSize(type, &sz));
    *bytes += bs * (PetscInt)sz;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Cells owned by this rank: [cs, ce) per direction (ce = cs + 1 unused dims).
   The DMDA carries PS_PAD nodes outside the domain on each side: cell c lies
   between DMDA nodes c + PS_PAD and c + PS_PAD + 1 and belongs to the owner of
   the first. */
PetscErrorCode PSCellOwnership(DM da, PetscInt cs[3], PetscInt ce[3])
{
  PetscInt xs[3], xm[3], M[3], dim, d;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(da, &dim));
  PetscCall(DMDAGetCorners(da, &xs[0], &xs[1], &xs[2], &xm[0], &xm[1], &xm[2]));
  PetscCall(DMDAGetInfo(da, NULL, &M[0], &M[1], &M[2], NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  for (d = 0; d < 3; d++) {
    if (d >= dim) {
      cs[d] = 0;
      ce[d] = 1;
      continue;
    }
    cs[d] = PetscMax(0, xs[d] - PS_PAD);
    ce[d] = PetscMax(cs[d], PetscMin(xs[d] + xm[d] - PS_PAD, M[d] - 1 - 2 * PS_PAD));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
