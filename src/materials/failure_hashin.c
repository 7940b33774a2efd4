/*
  Hashin's 3D failure criteria for a unidirectional ply (Z. Hashin, "Failure
  criteria for unidirectional fiber composites", J. Appl. Mech. 47, 1980),
  stress s in material axes (Voigt 11,22,33,23,13,12, tension positive),
  strengths Xt, Xc, Yt, Yc, S12 (in-plane shear), S23 (transverse shear):

    fiber tension     (s11 >= 0):  (s11/Xt)^2 + (s12^2 + s13^2)/S12^2
    fiber compression (s11 <  0):  (s11/Xc)^2
    matrix tension    (s22 + s33 >= 0):
        ((s22 + s33)/Yt)^2 + (s23^2 - s22 s33)/S23^2 + (s12^2 + s13^2)/S12^2
    matrix compression (s22 + s33 < 0):
        ((Yc/(2 S23))^2 - 1)(s22 + s33)/Yc + ((s22 + s33)/(2 S23))^2
        + (s23^2 - s22 s33)/S23^2 + (s12^2 + s13^2)/S12^2

  A mode initiates when its index reaches 1; the inactive mode of each pair
  is 0.
*/
#include "../materials.h"

PetscErrorCode PSPlyFailureHashin(const PSMaterial *M, const PetscReal s[6], PetscReal F[4])
{
  const PetscReal *X = M->ply.X; /* Xt, Xc, Yt, Yc, S12, S23 */
  const PetscReal  s23 = s[3], s13 = s[4], s12 = s[5], t = s[1] + s[2];
  const PetscReal  sh = (s12 * s12 + s13 * s13) / (X[4] * X[4]), tr = (s23 * s23 - s[1] * s[2]) / (X[5] * X[5]);

  PetscFunctionBeginUser;
  F[0] = s[0] >= 0.0 ? (s[0] / X[0]) * (s[0] / X[0]) + sh : 0.0;
  F[1] = s[0] < 0.0 ? (s[0] / X[1]) * (s[0] / X[1]) : 0.0;
  F[2] = t >= 0.0 ? (t / X[2]) * (t / X[2]) + tr + sh : 0.0;
  F[3] = t < 0.0 ? ((X[3] / (2.0 * X[5])) * (X[3] / (2.0 * X[5])) - 1.0) * t / X[3] + (t / (2.0 * X[5])) * (t / (2.0 * X[5])) + tr + sh : 0.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}
