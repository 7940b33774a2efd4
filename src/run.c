/*
  run.c - the time loop: steps, outputs every output_interval, history rows,
  per-body rows, progress on rank 0.  No Python runs inside the loop.

  OUTDIR/markers_NNNNN.h5   markers (io.c schema + state), root attribute time
  OUTDIR/grid_NNNNN.h5      /grid/mass, /grid/velocity_x|y|z (natural DMDA order,
                            PS_PAD nodes outside the domain on each side)
  OUTDIR/history.csv        step, time, dt, markers, mass, px, py[, pz], kinetic,
                            internal, total (= kinetic + internal + lost_energy),
                            lost_mass, lost_energy, max_pressure
  OUTDIR/bodies.csv         time, body, mass, px, py[, pz], kinetic, vx, vy[, vz]
  OUTDIR/gauges.csv         time, gauge, marker id, present, position, velocity, pressure,
                            Cauchy stress (Pa, tension positive) of the marker each gauge follows
  OUTDIR/checkpoint.h5      the end state, to continue with --restart (checkpoint.c)
*/
#include <petscviewerhdf5.h>
#include <petsctime.h>
#include "step.h"

typedef struct {
  const char        *outdir;
  PetscInt           nattr;
  const char *const *attr_names, *const *attr_values, *const *body_names, *const *material_names;
  FILE              *hist, *bodies, *gauges;
  DM                 da1;  /* dof-1 grid for output */
  Vec                out1;
  PetscInt           index;  /* next output number */
  PetscInt           hstep;  /* step of the last history row */
  PetscReal          t_last; /* time of the last output (s) */
} PSRunIO;

static PetscErrorCode WriteGrid(PSSolver *S, PSRunIO *io, const char *fn)
{
  PetscViewer v;
  PetscInt    d;
  const char *names[] = {"velocity_x", "velocity_y", "velocity_z"};

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(PetscObjectComm((PetscObject)S->da), fn, FILE_MODE_WRITE, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, "/grid"));
  /* the step works on the local arrays: their owned values into the global vectors */
  PetscCall(DMLocalToGlobal(S->dag, S->Gl, INSERT_VALUES, S->G));
  if (S->H) PetscCall(DMLocalToGlobal(S->dav, S->Hl, INSERT_VALUES, S->H));
  PetscCall(VecStrideGather(S->G, 0, io->out1, INSERT_VALUES));
  PetscCall(PetscObjectSetName((PetscObject)io->out1, "mass"));
  PetscCall(VecView(io->out1, v));
  for (d = 0; d < S->dim; d++) {
    /* nodal velocity: the re-projected one (musl) or v_i of G = (m, v) (apic) */
    PetscCall(VecStrideGather(S->H ? S->H : S->G, S->H ? PSReprojectDof(S) - S->dim + d : 1 + d, io->out1, INSERT_VALUES));
    PetscCall(PetscObjectSetName((PetscObject)io->out1, names[d]));
    PetscCall(VecView(io->out1, v));
  }
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, "time", PETSC_REAL, &S->t));
  PetscCall(PetscViewerDestroy(&v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode Output(PSSolver *S, PSRunIO *io)
{
  char fn[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/markers_%05" PetscInt_FMT ".h5", io->outdir, io->index));
  PetscCall(PSWriteMarkers(S->scene, S->sw, fn, S->t, io->nattr, io->attr_names, io->attr_values, io->body_names, io->material_names));
  PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/grid_%05" PetscInt_FMT ".h5", io->outdir, io->index));
  PetscCall(WriteGrid(S, io, fn));
  io->index++;
  io->t_last = S->t;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* one history row and the bodies' rows */
static PetscErrorCode History(PSSolver *S, PSRunIO *io)
{
  PSTotals    T;
  PetscInt    dim = S->dim, nb = S->scene->nbody, p, d, b, n, *body;
  PetscReal  *loc, *glob, *x, *v, *mass;
  PetscMPIInt rank;
  MPI_Comm    comm = PetscObjectComm((PetscObject)S->sw);

  PetscFunctionBeginUser;
  if (io->hstep == S->step && S->step > 0) PetscFunctionReturn(PETSC_SUCCESS); /* written already */
  io->hstep = S->step;
  PetscCall(PSSolverTotals(S, &T));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank && io->hist) {
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, "%" PetscInt_FMT ",%.10e,%.6e,%lld,%.12e,%.12e,%.12e", S->step, (double)S->t, (double)S->dt, (long long)T.markers, (double)T.mass, (double)T.p[0], (double)T.p[1]));
    if (dim == 3) PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, ",%.12e", (double)T.p[2]));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.6e\n", (double)T.kinetic, (double)T.internal, (double)(T.kinetic + T.internal + T.lost_energy), (double)T.lost_mass, (double)T.lost_energy, (double)T.max_pressure));
  }
  /* per body: mass, momentum, kinetic energy */
  PetscCall(PetscCalloc2(nb * 5, &loc, nb * 5, &glob));
  PetscCall(DMSwarmGetLocalSize(S->sw, &n));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_MASS, NULL, NULL, (void **)&mass));
  for (p = 0; p < n; p++) {
    PetscReal *r = &loc[5 * body[p]], v2 = 0.0;
    r[0] += mass[p];
    for (d = 0; d < dim; d++) {
      r[1 + d] += mass[p] * v[p * dim + d];
      v2 += v[p * dim + d] * v[p * dim + d];
    }
    r[4] += 0.5 * mass[p] * v2;
  }
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_MASS, NULL, NULL, (void **)&mass));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  (void)x;
  PetscCallMPI(MPI_Allreduce(loc, glob, 5 * nb, MPIU_REAL, MPI_SUM, comm));
  if (!rank && io->bodies)
    for (b = 0; b < nb; b++) {
      const PetscReal *r = &glob[5 * b], m = PetscMax(r[0], 1e-300);
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->bodies, "%.10e,%s,%.12e,%.12e,%.12e", (double)S->t, io->body_names[b], (double)r[0], (double)r[1], (double)r[2]));
      if (dim == 3) PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->bodies, ",%.12e", (double)r[3]));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->bodies, ",%.12e,%.12e,%.12e", (double)r[4], (double)(r[1] / m), (double)(r[2] / m)));
      if (dim == 3) PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->bodies, ",%.12e", (double)(r[3] / m)));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->bodies, "\n"));
    }
  PetscCall(PetscFree2(loc, glob));
  /* gauges: the rank holding each gauge's marker contributes, the rest add zeros */
  if (S->ngauge) {
    const PetscInt ns = PSStressComponents(dim), nv = 1 + 2 * dim + 1 + ns;
    PetscReal     *gl, *gg, *sg, *pr;
    PetscInt64    *id;
    PetscInt       k;
    PetscCall(PetscCalloc2(nv * S->ngauge, &gl, nv * S->ngauge, &gg));
    PetscCall(DMSwarmGetLocalSize(S->sw, &n));
    PetscCall(DMSwarmGetField(S->sw, PS_FIELD_ID, NULL, NULL, (void **)&id));
    PetscCall(DMSwarmGetField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&x));
    PetscCall(DMSwarmGetField(S->sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
    PetscCall(DMSwarmGetField(S->sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&pr));
    PetscCall(DMSwarmGetField(S->sw, PS_FIELD_STRESS, NULL, NULL, (void **)&sg));
    for (p = 0; p < n; p++)
      for (k = 0; k < S->ngauge; k++) {
        PetscReal *r = &gl[nv * k];
        if (id[p] != S->gauge_id[k]) continue;
        r[0] = 1.0;
        for (d = 0; d < dim; d++) {
          r[1 + d]       = x[p * dim + d];
          r[1 + dim + d] = v[p * dim + d];
        }
        r[1 + 2 * dim] = pr[p];
        for (d = 0; d < ns; d++) r[2 + 2 * dim + d] = sg[p * ns + d];
      }
    PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_STRESS, NULL, NULL, (void **)&sg));
    PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&pr));
    PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
    PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&x));
    PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_ID, NULL, NULL, (void **)&id));
    PetscCallMPI(MPI_Allreduce(gl, gg, nv * S->ngauge, MPIU_REAL, MPI_SUM, comm));
    if (!rank && io->gauges)
      for (k = 0; k < S->ngauge; k++) {
        const PetscReal *r = &gg[nv * k];
        PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->gauges, "%.10e,%" PetscInt_FMT ",%lld,%d", (double)S->t, k, (long long)S->gauge_id[k], r[0] > 0.5 ? 1 : 0));
        for (d = 1; d < nv; d++) PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->gauges, ",%.10e", (double)r[d]));
        PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->gauges, "\n"));
      }
    PetscCall(PetscFree2(gl, gg));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Run from the current state to run.t_end (or max_steps). */
PetscErrorCode PSSolverRun(PSSolver *S, const char outdir[], PetscInt nattr, const char *const attr_names[], const char *const attr_values[], const char *const body_names[], const char *const material_names[])
{
  PSRunIO        io;
  PetscMPIInt    rank;
  MPI_Comm       comm = PetscObjectComm((PetscObject)S->sw);
  PetscLogDouble w0, wlast, now;
  PetscReal      t_next_out, t_start = S->t;
  PetscInt       dim = S->dim, step0 = S->step;
  char           fn[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&io, sizeof(io)));
  io.outdir = outdir;
  io.nattr = nattr;
  io.attr_names = attr_names;
  io.attr_values = attr_values;
  io.body_names = body_names;
  io.material_names = material_names;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(DMDACreateCompatibleDMDA(S->da, 1, &io.da1));
  PetscCall(DMCreateGlobalVector(io.da1, &io.out1));
  if (!rank) {
    PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/history.csv", outdir));
    PetscCall(PetscFOpen(PETSC_COMM_SELF, fn, "w", &io.hist));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io.hist, "step,time,dt,markers,mass,px,py%s,kinetic,internal,total,lost_mass,lost_energy,max_pressure\n", dim == 3 ? ",pz" : ""));
    PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/bodies.csv", outdir));
    PetscCall(PetscFOpen(PETSC_COMM_SELF, fn, "w", &io.bodies));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io.bodies, "time,body,mass,px,py%s,kinetic,vx,vy%s\n", dim == 3 ? ",pz" : "", dim == 3 ? ",vz" : ""));
    if (S->ngauge) {
      PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/gauges.csv", outdir));
      PetscCall(PetscFOpen(PETSC_COMM_SELF, fn, "w", &io.gauges));
      /* present = 0 once the gauge's marker has left the domain */
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, io.gauges, "time,gauge,id,present,x,y%s,vx,vy%s,pressure,%s\n", dim == 3 ? ",z" : "", dim == 3 ? ",vz" : "",
                             dim == 3 ? "sxx,syy,szz,syz,sxz,sxy" : "sxx,syy,szz,sxy"));
    }
  }
  if (S->smax == 0.0) PetscCall(PSSolverMaxSpeed(S)); /* fresh start; a restart brings its own */
  /* the initial state: the grid's local arrays are empty until the first step */
  PetscCall(Output(S, &io));
  PetscCall(History(S, &io));
  t_next_out = S->run.output_interval > 0 ? t_start + S->run.output_interval : S->run.t_end;
  PetscCall(PetscTime(&w0));
  wlast = w0;
  while (S->t < S->run.t_end * (1.0 - 1e-12) && (S->run.max_steps <= 0 || S->step - step0 < S->run.max_steps)) {
    const PetscReal t_stop = PetscMin(t_next_out, S->run.t_end);
    PetscCall(PSSolverStep(S, t_stop));
    if (S->t >= t_stop * (1.0 - 1e-12) || (S->run.history_interval > 0 && S->step % S->run.history_interval == 0)) PetscCall(History(S, &io));
    if (S->t >= t_next_out * (1.0 - 1e-12)) {
      PetscCall(Output(S, &io));
      t_next_out = S->run.output_interval > 0 ? t_next_out + S->run.output_interval : S->run.t_end;
    }
    /* progress on rank 0: step, time, dt, ETA */
    PetscCall(PetscTime(&now));
    if (S->run.progress_interval > 0 ? S->step % S->run.progress_interval == 0 : now - wlast > 2.0) {
      PetscReal frac = (S->t - t_start) / (S->run.t_end - t_start);
      if (S->run.max_steps > 0) frac = PetscMax(frac, (PetscReal)(S->step - step0) / S->run.max_steps);
      PetscCall(PetscPrintf(comm, "step %7" PetscInt_FMT "  t %.6e s  dt %.3e s  %5.1f%%  ETA %.1f s\n", S->step, (double)S->t, (double)S->dt, (double)(100 * frac), (double)(frac > 0 ? (now - w0) * (1 - frac) / frac : 0)));
      wlast = now;
    }
  }
  if (S->t > io.t_last) { /* the end state is always written */
    PetscCall(Output(S, &io));
    PetscCall(History(S, &io));
  }
  PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/checkpoint.h5", outdir));
  PetscCall(PSSolverCheckpoint(S, fn));
  PetscCall(PetscTime(&now));
  PetscCall(PetscPrintf(comm, "done: %" PetscInt_FMT " steps to t = %.6e s in %.2f s wall, %" PetscInt_FMT " outputs in %s\n", S->step - step0, (double)S->t, (double)(now - w0), io.index, outdir));
  if (!rank) {
    PetscCall(PetscFClose(PETSC_COMM_SELF, io.hist));
    PetscCall(PetscFClose(PETSC_COMM_SELF, io.bodies));
    if (io.gauges) PetscCall(PetscFClose(PETSC_COMM_SELF, io.gauges));
  }
  PetscCall(VecDestroy(&io.out1));
  PetscCall(DMDestroy(&io.da1));
  PetscFunctionReturn(PETSC_SUCCESS);
}
