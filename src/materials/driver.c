/*
  Single-marker material driver: the solver's own kernel (M->update_fn) applied
  to one 3D marker under a prescribed velocity-gradient history, with no grid
  and no artificial viscosity.  For constitutive tests and for looking at a
  model on its own.

  Input:  axes0 (rows a_1, a_2, a_3; ignored for isotropic materials), L
          (nsteps x 3 x 3, 1/s, row major), dt (s), h (m; the length of the
          damage regularisation).
  Output: after each step, sig (3 x 3 Cauchy stress, Pa), axes (3 x 3, rows),
          dmg (4 damage variables; JC damage in the first), pe (pressure Pa,
          specific internal energy J/kg, J).  The marker starts unstressed at
          F = I, T = T_room.
*/
#include "../materials.h"

PetscErrorCode PSMaterialDrive(const PSMaterial *M, const PetscReal axes0[9], PetscInt nsteps, const PetscReal Lh[], PetscReal dt, PetscReal h, PetscReal sig[], PetscReal axes[], PetscReal dmg[], PetscReal pe[])
{
  PetscReal     F[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, vol = 1.0, sdev[6] = {0}, sg[6] = {0}, smat[6] = {0}, ax[9], D[4] = {0};
  PetscReal     p = 0.0, q = 0.0, e = 0.0, eps_p = 0.0, T = M->T_room, J, c, L[3][3];
  PSMarkerState st;
  PetscInt      n, i, j;

  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy(ax, axes0, 9));
  st.F     = F;
  st.Ftt   = 0.0;
  st.V0    = 1.0;
  st.vol   = &vol;
  st.sdev  = sdev;
  st.sig   = sg;
  st.p     = &p;
  st.q     = &q;
  st.e     = &e;
  st.eps_p = &eps_p;
  st.T     = &T;
  st.D     = D;
  st.axes0 = axes0;
  st.axes  = ax;
  st.smat  = smat;
  for (n = 0; n < nsteps; n++) {
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) L[i][j] = Lh[9 * n + 3 * i + j];
    PetscCall(M->update_fn(M, 3, L, dt, h, 0.0, 0.0, &st, &J, &c));
    PetscCall(PSMarkerCheckJ(J, 0, 0, n + 1, (n + 1) * dt));
    /* 3D stored stress xx,yy,zz,yz,xz,xy -> 3 x 3 */
    sig[9 * n + 0] = sg[0];
    sig[9 * n + 4] = sg[1];
    sig[9 * n + 8] = sg[2];
    sig[9 * n + 5] = sig[9 * n + 7] = sg[3];
    sig[9 * n + 2] = sig[9 * n + 6] = sg[4];
    sig[9 * n + 1] = sig[9 * n + 3] = sg[5];
    for (i = 0; i < 9; i++) axes[9 * n + i] = ax[i];
    for (i = 0; i < 4; i++) dmg[4 * n + i] = D[i];
    pe[3 * n + 0] = p;
    pe[3 * n + 1] = e;
    pe[3 * n + 2] = J;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
