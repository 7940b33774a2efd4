/*
  Mie-Grueneisen EOS with a linear Us-up Hugoniot reference and Gamma rho
  constant (Gamma rho = Gamma0 rho0), e.g. Steinberg UCRL-MA-106439 (1996):

    mu = rho/rho0 - 1 = 1/J - 1
    compression: p_H = rho0 c0^2 mu (1 + mu) / (1 - (s - 1) mu)^2,
                 e_H = p_H mu / (2 rho0 (1 + mu)),
                 p   = p_H + Gamma0 rho0 (e - e_H) = p_H (1 - Gamma0 mu / (2 (1 + mu))) + Gamma0 rho0 e
    tension:     p   = rho0 c0^2 mu + Gamma0 rho0 e

  Parameters: rho0 (kg/m^3), c0 (m/s), s (-), gamma0 (-).
*/
#include "../materials.h"

static PetscReal ColdPart(const PSMaterial *M, PetscReal mu)
{
  const PetscReal k = M->rho0 * M->c0 * M->c0;
  if (mu <= 0.0) return k * mu;
  {
    /* the Hugoniot diverges at mu = 1/(s-1); a cap keeps the rate finite and
       the time step then shrinks through the sound speed */
    const PetscReal den = PetscMax(1.0 - (M->s - 1.0) * mu, 0.05);
    const PetscReal pH  = k * mu * (1.0 + mu) / (den * den);
    return pH * (1.0 - 0.5 * M->gamma0 * mu / (1.0 + mu));
  }
}

PetscErrorCode PSEOSMieGruneisen(const PSMaterial *M, PetscReal J, PetscReal p_old, PetscReal dvol, PetscReal *A, PetscReal *B, PetscReal *c2)
{
  const PetscReal mu = 1.0 / J - 1.0, dmu = 1e-6 * PetscMax(1.0, PetscAbsReal(mu));
  const PetscReal rho = M->rho0 / J;

  PetscFunctionBeginUser;
  (void)p_old;
  (void)dvol;
  *A = ColdPart(M, mu);
  *B = M->gamma0 * M->rho0;
  /* isentropic: dp/drho|_s = (1/rho0) dA/dmu + (p / rho^2) B, with p ~ A here */
  *c2 = (ColdPart(M, mu + dmu) - ColdPart(M, mu - dmu)) / (2.0 * dmu * M->rho0) + PetscMax(*A, 0.0) * (*B) / (rho * rho);
  *c2 = PetscMax(*c2, 0.25 * M->c0 * M->c0);
  PetscFunctionReturn(PETSC_SUCCESS);
}
