/*
  timestep.c - the time step from the CFL condition (PSTimeStep):
    dt = cfl h_min / max_p (c_p + |v_p| + q_p / (rho_p c_p)),
  capped in growth (dt_growth), by dt_max and by the next output or end time.
  The maximum is gathered during the stress phase (stress.c); PSSolverMaxSpeed
  computes it afresh for the first step and after a restart.

  Guard (run.dt_floor): when the CFL step falls below dt_floor times the run's
  first one (S->dt0), a marker is being crushed or flung and the run would
  crawl on for ever; it stops with an error naming the marker that limits the
  step, where it is and which term of its speed does it.  The markers are
  scanned for it only then, never in the step.
*/
#include "step.h"
#include "cells/cells.h"

/* a marker's share of the CFL limit: wave speed + |v| + viscous term (as stress.c gathers it) */
static PetscErrorCode MarkerSpeed(const PSSolver *S, const PSFields *f, PetscInt p, PetscReal parts[3])
{
  PetscReal c, v2 = 0.0;
  PetscInt  d;

  PetscFunctionBeginUser;
  PetscCall(PSMarkerSoundSpeed(&S->mat[f->mat[p]], f->vol[p] / f->V0[p], f->e[p], f->p[p], &c));
  for (d = 0; d < S->dim; d++) v2 += f->v[p * S->dim + d] * f->v[p * S->dim + d];
  parts[0] = c;
  parts[1] = PetscSqrtReal(v2);
  parts[2] = f->q[p] > 0.0 ? f->q[p] * f->vol[p] / (f->mass[p] * PetscMax(c, 1e-300)) : 0.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* wave speed + |v| over all markers (for the first dt and after restarts) */
PetscErrorCode PSSolverMaxSpeed(PSSolver *S)
{
  PSFields  f;
  PetscInt  p;
  PetscReal smax = 0.0, s[3];

  PetscFunctionBeginUser;
  PetscCall(PSFieldsGet(S, &f));
  for (p = 0; p < f.n; p++) {
    PetscCall(MarkerSpeed(S, &f, p, s));
    smax = PetscMax(smax, s[0] + s[1]);
  }
  PetscCall(PSFieldsRestore(S, &f));
  if (S->cells) {
    PetscCall(PSCellsMaxSpeed(S));
    smax = PetscMax(smax, S->cells->smax);
  }
  PetscCallMPI(MPI_Allreduce(&smax, &S->smax, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)S->sw)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* cfl h_min / max(c + |v| + q/(rho c)): the step the CFL condition allows now (s) */
PetscReal PSSolverCFLTimeStep(const PSSolver *S)
{
  PetscReal hmin = PETSC_MAX_REAL;
  PetscInt  d;

  for (d = 0; d < S->dim; d++) hmin = PetscMin(hmin, S->h[d]);
  return S->run.cfl * hmin / PetscMax(S->smax, 1e-300);
}

/* The guard has tripped and cells are in the scene: when a cell sets the
   step (its speed is the global one), stop naming it, its place and state;
   otherwise return (a marker sets it). */
static PetscErrorCode DtFloorCellError(PSSolver *S, PetscReal dt)
{
  MPI_Comm        comm = PetscObjectComm((PetscObject)S->sw);
  const PSCells  *C    = S->cells;
  PetscReal       sat[7];
  PetscMPIInt     rank;
  struct {
    double v;
    int    r;
  } loc, glob;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  loc.v = C->smax;
  loc.r = rank;
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm));
  if (glob.v < S->smax) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscArraycpy(sat, C->sat, 7));
  PetscCallMPI(MPI_Bcast(sat, 7, MPIU_REAL, glob.r, comm));
  SETERRQ(comm, PS_ERR_RUN,
          "run.dt_floor: the time step fell to %g s at step %" PetscInt_FMT " (t = %g s), below %g of the run's first step %g s. "
          "The cell at (%g, %g, %g) m limits it: sound speed %g + |v| %g + viscous term %g m/s, density %g kg/m^3%s. "
          "Check the deck's pressures and material data, lower run.cfl or refine the grid; run.dt_floor: 0 lets the run go on",
          (double)dt, S->step, (double)S->t, (double)S->run.dt_floor, (double)S->dt0, (double)sat[0], (double)sat[1], (double)sat[2], (double)sat[3], (double)sat[4], (double)sat[5], (double)sat[6],
          sat[5] > 0.25 * (sat[3] + sat[4] + sat[5]) ? " (its artificial viscosity dominates: a strong compression in one step)" : "");
}

/* The guard has tripped (on every rank: smax is global): find the marker with
   the largest speed over all ranks and stop with its id, place and state. */
static PetscErrorCode DtFloorError(PSSolver *S, PetscReal dt)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)S->sw);
  PSFields    f;
  PetscInt    p, d, *body, best = -1;
  PetscMPIInt rank;
  PetscReal   s[3], info[12] = {0}; /* speed parts (3), -, body, material, J, p, x (3), found */
  PetscInt64  id = -1;
  struct {
    double v;
    int    r;
  } loc = {-1.0, 0}, glob;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (S->cells) PetscCall(DtFloorCellError(S, dt)); /* the cells set the step: name the cell */
  PetscCall(PSFieldsGet(S, &f));
  body = f.body;
  for (p = 0; p < f.n; p++) {
    PetscReal v;
    PetscCall(MarkerSpeed(S, &f, p, s));
    v = s[0] + s[1] + s[2];
    if (!(v == v) || v > PETSC_MAX_REAL) v = PETSC_MAX_REAL; /* a NaN or infinite speed wins */
    if (v > loc.v) {
      loc.v = v;
      best  = p;
    }
  }
  loc.r = rank;
  if (best >= 0) {
    PetscCall(MarkerSpeed(S, &f, best, s));
    info[0] = s[0];
    info[1] = s[1];
    info[2] = s[2];
    id      = f.id[best];
    info[4] = (PetscReal)body[best];
    info[5] = (PetscReal)f.mat[best];
    info[6] = f.vol[best] / f.V0[best];
    info[7] = f.p[best];
    for (d = 0; d < S->dim; d++) info[8 + d] = f.x[best * S->dim + d];
    info[11] = 1.0;
  }
  PetscCall(PSFieldsRestore(S, &f));
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm));
  PetscCallMPI(MPI_Bcast(info, 12, MPIU_REAL, glob.r, comm));
  PetscCallMPI(MPI_Bcast(&id, 1, MPIU_INT64, glob.r, comm));
  PetscCheck(info[11] > 0.0, comm, PS_ERR_RUN, "run.dt_floor: the time step fell to %g s at step %" PetscInt_FMT " (t = %g s), below %g of the run's first step %g s, with no marker left to blame", (double)dt, S->step, (double)S->t, (double)S->run.dt_floor, (double)S->dt0);
  {
    const PetscInt  b = (PetscInt)info[4], m = (PetscInt)info[5];
    const PetscReal speed = info[0] + info[1] + info[2];
    PetscReal       c1, hmin = S->h[0], s0;
    char            where[128], why[640] = "", msg[1600];
    size_t          l;
    /* why: what about this marker is out of the ordinary */
    for (d = 1; d < S->dim; d++) hmin = PetscMin(hmin, S->h[d]);
    s0 = S->run.cfl * hmin / S->dt0; /* the fastest marker's speed at the first step */
    PetscCall(PSMarkerSoundSpeed(&S->mat[m], 1.0, 0.0, 0.0, &c1));
    if (!(speed < PETSC_MAX_REAL)) snprintf(why, sizeof(why), "its state is not finite (NaN or infinity): its update has broken down; ");
    else snprintf(why, sizeof(why), "its speed is %g times the fastest marker's at the first step (%g m/s); ", (double)(speed / s0), (double)s0);
    if (info[6] < 0.7) snprintf(why + strlen(why), sizeof(why) - strlen(why), "it is compressed to J = V/V0 = %g, which stiffens its sound speed to %g times the material's at rest; ", (double)info[6], (double)(info[0] / c1));
    if (info[6] > 1.5) snprintf(why + strlen(why), sizeof(why) - strlen(why), "it is stretched to J = V/V0 = %g; ", (double)info[6]);
    if (info[2] > 0.25 * speed) snprintf(why + strlen(why), sizeof(why) - strlen(why), "its artificial viscosity is %.0f%% of its speed (a strong shock, or the marker crushed in one step); ", (double)(100 * info[2] / speed));
    if (info[1] > info[0]) snprintf(why + strlen(why), sizeof(why) - strlen(why), "it moves faster than its sound speed; ");
    l = strlen(why);
    why[l - 2] = 0; /* the last "; " */
    snprintf(where, sizeof(where), S->dim == 3 ? "(%g, %g, %g)" : "(%g, %g)", (double)info[8], (double)info[9], (double)info[10]);
    snprintf(msg, sizeof(msg),
             "run.dt_floor: the time step fell to %g s at step %d (t = %g s), below %g of the run's first step %g s. "
             "Marker %lld (body %s, material %s) at %s m limits it: wave speed %g + |v| %g + viscous term %g = %g m/s; J = V/V0 = %g, p = %g Pa; %s. "
             "Check the deck's velocities and material data, lower run.cfl or refine the grid; run.dt_floor: 0 lets the run go on",
             (double)dt, (int)S->step, (double)S->t, (double)S->run.dt_floor, (double)S->dt0, (long long)id, S->body_names ? S->body_names[b] : "?", S->material_names ? S->material_names[m] : "?", where,
             (double)info[0], (double)info[1], (double)info[2], (double)speed, (double)info[6], (double)info[7], why);
    SETERRQ(comm, PS_ERR_RUN, "%s", msg);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* dt = cfl h_min / max(c + |v|), capped in growth, by dt_max and the next stop */
PetscErrorCode PSComputeDt(PSSolver *S, PetscReal t_stop)
{
  PetscReal dt;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_Dt, 0, 0, 0, 0));
  dt = PSSolverCFLTimeStep(S);
  if (S->dt0 <= 0) S->dt0 = dt; /* the run's first step (a restart brings its own) */
  if (PetscUnlikely(S->run.dt_floor > 0 && !(dt >= S->run.dt_floor * S->dt0))) PetscCall(DtFloorError(S, dt)); /* NaN too */
  if (S->dt > 0) dt = PetscMin(dt, S->run.dt_growth * S->dt);
  if (S->run.dt_max > 0) dt = PetscMin(dt, S->run.dt_max);
  if (S->t + dt > t_stop) dt = t_stop - S->t;
  else if (S->t + 1.5 * dt > t_stop) dt = 0.5 * (t_stop - S->t); /* no sliver step before a stop */
  S->dt = dt;
  PetscCall(PetscLogEventEnd(PS_EV_Dt, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
