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
PETSC_INTERN PetscErrorCode PSEOSIdealGas(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *, PetscReal *, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthNone(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthElasticPlastic(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthJohnsonCook(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthZerilliArmstrongFCC(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthZerilliArmstrongBCC(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthZerilliArmstrongCheck(const PSMaterial *);
PETSC_INTERN PetscErrorCode PSStrengthMTS(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSStrengthMTSCheck(const PSMaterial *);
PETSC_INTERN PetscErrorCode PSFailureJohnsonCook(const PSMaterial *, PetscReal, PetscReal, PetscReal, PetscReal *);
PETSC_INTERN PetscErrorCode PSPlyFailureHashin(const PSMaterial *, const PetscReal[6], PetscReal[4]);

/* One marker's stress update over a step (materials/update.c).  Returns
   J = det F_new in *J (the caller stops on J <= 0) and the marker's wave speed. */
typedef struct PSMarkerState_ {
  PetscReal *F;     /* dim x dim, updated */
  PetscReal  Ftt;   /* axisymmetric: the hoop stretch F_tt = r/r0 at the step's start (stress.c
                       recovers it as V / (V0 det F_rz)); 0 otherwise: F_zz = 1 in plane strain */
  PetscReal  V0;    /* m^3 */
  PetscReal *vol;   /* current volume, updated */
  PetscReal *sdev;  /* unrotated deviator, updated */
  PetscReal *sig;   /* Cauchy stress (no q), updated */
  PetscReal *p, *q, *e;
  PetscReal *eps_p, *T, *D; /* NULL when not registered; D: damage (1 or 4 components) */
  /* orthotropic plies */
  const PetscReal *axes0; /* material axes at t = 0, rows a_1, a_2, a_3 */
  PetscReal       *axes;  /* current axes a_k = R a_k^0, updated */
  PetscReal       *smat;  /* stress in material axes less the volumetric part, Voigt (Pa), updated */
} PSMarkerState;

PETSC_INTERN PetscErrorCode PSMarkerUpdate(const PSMaterial *, PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState *, PetscReal *J, PetscReal *c);
PETSC_INTERN PetscErrorCode PSMarkerUpdate4(const PSMaterial *, const PetscReal L[4][3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState s[4], PetscReal J[4], PetscReal c[4]);
PETSC_INTERN PetscErrorCode PSMarkerUpdate4Elastic(const PSMaterial *, const PetscReal L[4][3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState s[4], PetscReal J[4], PetscReal c[4]);
PETSC_INTERN PetscErrorCode PSMarkerUpdateOrthotropic(const PSMaterial *, PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState *, PetscReal *J, PetscReal *c);

/* Y = Q X Q^T, or Q^T X Q when transpose: a tensor turned between frames
   (inline: called per marker with a constant transpose) */
static inline void PSTurn(const PetscReal Q[3][3], PetscBool transpose, const PetscReal X[3][3], PetscReal Y[3][3])
{
  PetscReal T[3][3];
  PetscInt  i, j, k;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      T[i][j] = 0.0;
      for (k = 0; k < 3; k++) T[i][j] += X[i][k] * (transpose ? Q[k][j] : Q[j][k]);
    }
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      Y[i][j] = 0.0;
      for (k = 0; k < 3; k++) Y[i][j] += (transpose ? Q[k][i] : Q[i][k]) * T[k][j];
    }
}

/* Symmetric tensors inside the isotropic kernels (update.c, update4.c) are
   6 components in the 3D storage order xx,yy,zz,yz,xz,xy: a frame change of
   a symmetric X computes only the 6 distinct components of Y (45 products,
   not 54), and a contraction A:B weighs the shear pairs twice.  Both kernels
   spell these the same way, so their results stay bitwise equal. */
static const PetscInt PS_SYM[3][3] = {{0, 5, 4}, {5, 1, 3}, {4, 3, 2}};
static const PetscInt PS_SYM_I[6] = {0, 1, 2, 1, 0, 0}, PS_SYM_J[6] = {0, 1, 2, 2, 2, 1};

/* Y = Q X Q^T, or Q^T X Q when transpose, for symmetric X and Y */
static inline void PSTurnSym(const PetscReal Q[3][3], PetscBool transpose, const PetscReal X[6], PetscReal Y[6])
{
  PetscReal T[3][3];
  PetscInt  a, k, j;
  for (k = 0; k < 3; k++) /* T = X Q, or X Q^T */
    for (j = 0; j < 3; j++) T[k][j] = X[PS_SYM[k][0]] * (transpose ? Q[0][j] : Q[j][0]) + X[PS_SYM[k][1]] * (transpose ? Q[1][j] : Q[j][1]) + X[PS_SYM[k][2]] * (transpose ? Q[2][j] : Q[j][2]);
  for (a = 0; a < 6; a++) { /* Y = Q^T T, or Q T */
    const PetscInt i = PS_SYM_I[a];
    j                = PS_SYM_J[a];
    Y[a]             = (transpose ? Q[0][i] : Q[i][0]) * T[0][j] + (transpose ? Q[1][i] : Q[i][1]) * T[1][j] + (transpose ? Q[2][i] : Q[i][2]) * T[2][j];
  }
}

/* A : B of two symmetric tensors */
static inline PetscReal PSSymDot(const PetscReal A[6], const PetscReal B[6])
{
  return (A[0] * B[0] + A[1] * B[1] + A[2] * B[2]) + 2.0 * (A[3] * B[3] + A[4] * B[4] + A[5] * B[5]);
}

/* symmetric 3x3 -> stored components (3D xx,yy,zz,yz,xz,xy; 2D xx,yy,zz,xy) */
static inline void PSStressPack(const PetscInt dim, const PetscReal S[3][3], PetscReal *v)
{
  v[0] = S[0][0];
  v[1] = S[1][1];
  v[2] = S[2][2];
  if (dim == 3) {
    v[3] = 0.5 * (S[1][2] + S[2][1]);
    v[4] = 0.5 * (S[0][2] + S[2][0]);
    v[5] = 0.5 * (S[0][1] + S[1][0]);
  } else v[3] = 0.5 * (S[0][1] + S[1][0]);
}

/* Step 1 of every kernel: F_new = (I + dt L) F (stored dim x dim, plane strain
   F_zz = 1), V = J V0, both stored only when J = det F_new > 0; D = sym L.
   Returns J (the caller names a marker with J <= 0).  Inline: the kernels
   call it with a constant dim. */
static inline PetscReal PSKinematics(const PetscInt dim, const PetscReal L[3][3], PetscReal dt, PSMarkerState *s, PetscReal Fn[3][3], PetscReal D[3][3], PetscReal *trD)
{
  PetscReal F[3][3], J;
  PetscInt  i, j, k;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) F[i][j] = (i < dim && j < dim) ? s->F[i * dim + j] : (i == j ? 1.0 : 0.0);
  /* axisymmetric: F = diag(F_rz, F_tt), and L_tt = v_r/r advances F_tt
     like any diagonal term, so J and V = J V0 carry the hoop stretch */
  if (dim == 2 && s->Ftt > 0.0) F[2][2] = s->Ftt;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      Fn[i][j] = F[i][j];
      for (k = 0; k < 3; k++) Fn[i][j] += dt * L[i][k] * F[k][j];
      D[i][j] = 0.5 * (L[i][j] + L[j][i]);
    }
  *trD = D[0][0] + D[1][1] + D[2][2];
  J    = Fn[0][0] * (Fn[1][1] * Fn[2][2] - Fn[1][2] * Fn[2][1]) - Fn[0][1] * (Fn[1][0] * Fn[2][2] - Fn[1][2] * Fn[2][0]) + Fn[0][2] * (Fn[1][0] * Fn[2][1] - Fn[1][1] * Fn[2][0]);
  if (J > 0.0) {
    for (i = 0; i < dim; i++)
      for (j = 0; j < dim; j++) s->F[i * dim + j] = Fn[i][j];
    *s->vol = J * s->V0;
  }
  return J;
}
PETSC_INTERN void      PSPolarRotation(const PetscReal F[3][3], PetscReal R[3][3]);
PETSC_INTERN PetscErrorCode PSMarkerCheckJ(PetscReal J, PetscInt64 id, PetscInt material, PetscInt step, PetscReal t);
/* The end-of-step energy e1 and pressure p1 of an isotropic marker from the
   EOS p = A + B e (implicit in e1, trapezoidal pressure work, the step's mean
   q; a = dt tr(D) / rho, w = dt wdev / rho).  Spalled (below spall_pressure)
   or failed in tension, it carries no tension: the step ends at p = 0 and its
   pressure work is that of (p0 + 0)/2.  One expression for update.c and
   update4.c, so the two stay bitwise equal. */
static inline void PSPressureEnergy(const PSMaterial *M, PetscBool failed, PetscReal e, PetscReal w, PetscReal a, PetscReal p0, PetscReal A, PetscReal B, PetscReal q, PetscReal *e1, PetscReal *p1)
{
  *e1 = (e + w - a * (0.5 * p0 + 0.5 * A + q)) / (1.0 + 0.5 * a * B);
  *p1 = A + B * *e1;
  if ((M->spall < 0.0 && *p1 < M->spall) || (failed && *p1 < 0.0)) {
    *p1 = 0.0;
    *e1 = e + w - a * (0.5 * p0 + q);
  }
}

/* q = rho h (c_q h tr(D)^2 + c_l c |tr D|) in compression only (von
   Neumann-Richtmyer + linear, Wilkins 1980).  Inline: the cells call it
   twice per cell and step */
static inline PetscReal PSViscosity(PetscReal rho, PetscReal h, PetscReal trD, PetscReal c, PetscReal c_linear, PetscReal c_quadratic)
{
  return trD < 0.0 ? rho * h * (c_quadratic * h * trD * trD + c_linear * c * PetscAbsReal(trD)) : 0.0;
}
PETSC_INTERN PetscErrorCode PSMarkerSoundSpeed(const PSMaterial *, PetscReal J, PetscReal e, PetscReal p, PetscReal *c);

#endif
