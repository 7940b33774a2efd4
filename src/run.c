/*
  run.c - the time loop: steps, outputs every output_interval, history rows,
  per-body rows, progress on rank 0, periodic checkpoints.  No Python runs
  inside the loop.

  OUTDIR/markers_NNNNN.h5   markers (io.c schema + state), root attribute time
  OUTDIR/grid_NNNNN.h5      /grid/mass, /grid/velocity_x|y|z (natural DMDA order,
                            PS_PAD nodes outside the domain on each side); with cell
                            materials /cells/volume_fraction (ny, nx, nmat; attribute
                            materials), density, pressure, velocity (ny, nx, dim),
                            specific_energy, cell-centred (cells/cells.c)
  OUTDIR/history.csv        step, time, dt, markers, mass, px, py[, pz], kinetic,
                            internal, total (= kinetic + internal + lost_energy +
                            friction_work + interface_energy), lost_mass, lost_energy,
                            max_pressure (0 once nothing is left), of markers and cell
                            materials together; with cell materials also remap_heat and
                            coupling_work (J, cumulative, both included in internal);
                            then interface_energy (J, cumulative: the energy the cohesive ply
                            interfaces' law took as they opened, contact.c)
                            and friction_work (J, cumulative: the kinetic energy the
                            contact's friction removed, contact.c)
  OUTDIR/bodies.csv         time, body, mass, px, py[, pz], kinetic, vx, vy[, vz]
  OUTDIR/gauges.csv         time, gauge, marker id, present, position, velocity, pressure,
                            Cauchy stress (Pa, tension positive) of the marker each gauge follows
  OUTDIR/checkpoint.h5      the state to continue from with --restart (checkpoint.c):
                            refreshed at every output time (run.checkpoint_interval > 0:
                            every that much simulated time instead), every
                            run.checkpoint_wall_interval seconds of wall time if set, and
                            at the end.  Checkpoints never change the steps taken.

  A restart continues the same output times and numbers (the schedule is in
  the checkpoint) and writes no output for its first state; into the same
  OUTDIR it appends to the .csv files (the front end first cuts them back to
  the checkpoint's step), so a killed run resumed there ends with the files
  of an uninterrupted one.

  Guards: a run that would need more steps than the step counter holds stops
  before its first step (run.t_end); the time step's floor is in timestep.c.
  A run whose markers all leave the grid warns once and runs on, empty, to
  t_end.
*/
#include <stdio.h>
#include <petscviewerhdf5.h>
#include <petsctime.h>
#include "step.h"
#include "cells/cells.h"

typedef struct {
  const char        *outdir;
  PetscInt           nattr;
  const char *const *attr_names, *const *attr_values, *const *body_names, *const *material_names;
  FILE              *hist, *bodies, *gauges;
  DM                 da1;  /* dof-1 grid for output */
  Vec                out1;
  PetscInt           hstep;  /* step of the last history row */
  PetscReal          t_last; /* time of the last output (s) */
  char               ckpt[PETSC_MAX_PATH_LEN]; /* OUTDIR/checkpoint.h5 */
  PetscInt           ckpt_step;     /* step of the last checkpoint (-1: none yet) */
  PetscReal          t_next_ckpt;   /* next checkpoint time with run.checkpoint_interval (s) */
  PetscLogDouble     ckpt_wall;     /* wall time of the last checkpoint (s, rank 0's clock) */
  PetscBool          warned_empty;  /* the warning that no marker is left was given */
} PSRunIO;

static PetscErrorCode WriteGrid(PSSolver *S, PSRunIO *io, const char *fn)
{
  PetscViewer     v;
  PetscInt        d;
  const char     *names[] = {"velocity_x", "velocity_y", "velocity_z"};
  const PetscBool rep     = PSSolverReprojects(S); /* the velocity is the re-projected one (H), else G's */

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(PetscObjectComm((PetscObject)S->da), fn, FILE_MODE_WRITE, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, "/grid"));
  /* the step works on the local arrays: their owned values into the global vectors */
  PetscCall(DMLocalToGlobal(S->dag, S->Gl, INSERT_VALUES, S->G));
  if (rep) PetscCall(DMLocalToGlobal(S->dav, S->Hl, INSERT_VALUES, S->H));
  PetscCall(VecStrideGather(S->G, 0, io->out1, INSERT_VALUES));
  PetscCall(PetscObjectSetName((PetscObject)io->out1, "mass"));
  PetscCall(VecView(io->out1, v));
  for (d = 0; d < S->dim; d++) {
    /* nodal velocity: the re-projected one (musl, PSSolverReprojects) or
       v_i of G = (m, v) (apic; musl's v^{n+1} in a scene of cells alone) */
    PetscCall(VecStrideGather(rep ? S->H : S->G, rep ? PSReprojectDof(S) - S->dim + d : 1 + d, io->out1, INSERT_VALUES));
    PetscCall(PetscObjectSetName((PetscObject)io->out1, names[d]));
    PetscCall(VecView(io->out1, v));
  }
  PetscCall(PetscViewerHDF5PopGroup(v));
  if (S->cells) PetscCall(PSCellsWrite(S, v, io->material_names)); /* /cells: the Eulerian cell fields */
  PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, "time", PETSC_REAL, &S->t));
  PetscCall(PetscViewerDestroy(&v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode Output(PSSolver *S, PSRunIO *io)
{
  char fn[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/markers_%05" PetscInt_FMT ".h5", io->outdir, S->out.index));
  PetscCall(PSWriteMarkers(S->scene, S->sw, fn, S->t, io->nattr, io->attr_names, io->attr_values, io->body_names, io->material_names));
  PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/grid_%05" PetscInt_FMT ".h5", io->outdir, S->out.index));
  PetscCall(WriteGrid(S, io, fn));
  S->out.index++;
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
  if (!T.markers && T.mass == 0.0 && !io->warned_empty) { /* nothing left: no marker, no cell material */
    io->warned_empty = PETSC_TRUE;
    PetscCall(PetscPrintf(comm, "warning: no marker is left in the grid at t = %g s (step %" PetscInt_FMT "): %lld markers, %g kg%s and %g J left through free faces and are booked as lost (history.csv); the run goes on, empty, to t_end\n",
                          (double)S->t, S->step, (long long)T.lost_markers, (double)T.lost_mass, dim == 2 ? "/m" : "", (double)T.lost_energy));
  }
  if (!rank && io->hist) {
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, "%" PetscInt_FMT ",%.10e,%.6e,%lld,%.12e,%.12e,%.12e", S->step, (double)S->t, (double)S->dt, (long long)T.markers, (double)T.mass, (double)T.p[0], (double)T.p[1]));
    if (dim == 3) PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, ",%.12e", (double)T.p[2]));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.6e", (double)T.kinetic, (double)T.internal, (double)(T.kinetic + T.internal + T.lost_energy + T.friction_work + T.interface_energy), (double)T.lost_mass, (double)T.lost_energy, (double)T.max_pressure));
    if (S->cells) PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, ",%.12e,%.12e", (double)T.remap_heat, (double)T.coupling_work));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, ",%.12e,%.12e", (double)T.interface_energy, (double)T.friction_work));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, io->hist, "\n"));
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

/* a CSV file of rank 0: a fresh one with its header, or after a restart an
   existing one appended to (the front end has cut it back to the checkpoint) */
static PetscErrorCode OpenCSV(PSSolver *S, const char *outdir, const char *name, const char *header, FILE **fp)
{
  char      fn[PETSC_MAX_PATH_LEN];
  PetscBool exists = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(fn, sizeof(fn), "%s/%s", outdir, name));
  if (S->restarted) PetscCall(PetscTestFile(fn, 'r', &exists));
  PetscCall(PetscFOpen(PETSC_COMM_SELF, fn, exists ? "a" : "w", fp));
  if (!exists) PetscCall(PetscFPrintf(PETSC_COMM_SELF, *fp, "%s", header));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteCheckpoint(PSSolver *S, PSRunIO *io)
{
  PetscFunctionBeginUser;
  /* the .csv rows so far are on disk before the checkpoint that a resumed run cuts them back to */
  if (io->hist) (void)fflush(io->hist);
  if (io->bodies) (void)fflush(io->bodies);
  if (io->gauges) (void)fflush(io->gauges);
  PetscCall(PSSolverCheckpoint(S, io->ckpt));
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)S->sw), "checkpoint: step %" PetscInt_FMT ", t = %.6e s in %s\n", S->step, (double)S->t, io->ckpt));
  io->ckpt_step = S->step;
  PetscCall(PetscTime(&io->ckpt_wall));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Is a checkpoint due after this step?  (output: an output was just written) */
static PetscErrorCode CheckpointDue(PSSolver *S, PSRunIO *io, PetscBool output, PetscBool *due)
{
  const PetscReal ci = S->run.checkpoint_interval;

  PetscFunctionBeginUser;
  *due = (output && ci == 0) ? PETSC_TRUE : PETSC_FALSE;
  if (ci > 0 && S->t >= io->t_next_ckpt * (1.0 - 1e-12)) {
    *due = PETSC_TRUE;
    while (io->t_next_ckpt <= S->t * (1.0 + 1e-12)) io->t_next_ckpt += ci;
  }
  if (S->run.checkpoint_wall_interval > 0) {
    /* rank 0's clock decides for all: the ranks' clocks differ */
    MPI_Comm       comm = PetscObjectComm((PetscObject)S->sw);
    PetscMPIInt    rank;
    PetscLogDouble now;
    int            wall = 0;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    if (!rank) {
      PetscCall(PetscTime(&now));
      wall = now - io->ckpt_wall >= S->run.checkpoint_wall_interval;
    }
    PetscCallMPI(MPI_Bcast(&wall, 1, MPI_INT, 0, comm));
    if (wall) *due = PETSC_TRUE;
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
  PetscReal      t_start = S->t;
  PetscInt       dim = S->dim, step0 = S->step, nout = 0;
  char           head[256];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&io, sizeof(io)));
  io.outdir = outdir;
  io.nattr = nattr;
  io.attr_names = attr_names;
  io.attr_values = attr_values;
  io.body_names = body_names;
  io.material_names = material_names;
  io.ckpt_step = -1;
  S->body_names = body_names;
  S->material_names = material_names;
  PetscCall(PetscSNPrintf(io.ckpt, sizeof(io.ckpt), "%s/checkpoint.h5", outdir));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(DMDACreateCompatibleDMDA(S->da, 1, &io.da1));
  PetscCall(DMCreateGlobalVector(io.da1, &io.out1));
  if (!rank) {
    PetscCall(PetscSNPrintf(head, sizeof(head), "step,time,dt,markers,mass,px,py%s,kinetic,internal,total,lost_mass,lost_energy,max_pressure%s,interface_energy,friction_work\n", dim == 3 ? ",pz" : "", S->cells ? ",remap_heat,coupling_work" : ""));
    PetscCall(OpenCSV(S, outdir, "history.csv", head, &io.hist));
    PetscCall(PetscSNPrintf(head, sizeof(head), "time,body,mass,px,py%s,kinetic,vx,vy%s\n", dim == 3 ? ",pz" : "", dim == 3 ? ",vz" : ""));
    PetscCall(OpenCSV(S, outdir, "bodies.csv", head, &io.bodies));
    if (S->ngauge) {
      /* present = 0 once the gauge's marker has left the domain */
      PetscCall(PetscSNPrintf(head, sizeof(head), "time,gauge,id,present,x,y%s,vx,vy%s,pressure,%s\n", dim == 3 ? ",z" : "", dim == 3 ? ",vz" : "", dim == 3 ? "sxx,syy,szz,syz,sxz,sxy" : "sxx,syy,szz,sxy"));
      PetscCall(OpenCSV(S, outdir, "gauges.csv", head, &io.gauges));
    }
  }
  if (S->smax == 0.0) PetscCall(PSSolverMaxSpeed(S)); /* fresh start; a restart brings its own */
  /* the outputs' schedule: a restart keeps its checkpoint's, unless the interval changed */
  if (!S->restarted || S->out.interval != S->run.output_interval || S->run.output_interval == 0 || !(S->out.t_next > S->t)) {
    S->out.t_next   = S->run.output_interval > 0 ? S->t + S->run.output_interval : S->run.t_end;
    S->out.interval = S->run.output_interval;
  }
  if (!S->restarted) S->out.index = 0;
  if (S->run.checkpoint_interval > 0) io.t_next_ckpt = (PetscFloorReal(S->t / S->run.checkpoint_interval) + 1) * S->run.checkpoint_interval;
  /* guard: a run the step counter cannot hold (a deck with absurd speeds, materials or t_end) */
  {
    PetscReal dt = PSSolverCFLTimeStep(S), hmin = PETSC_MAX_REAL, need, room = (PetscReal)(PETSC_MAX_INT - S->step);
    PetscInt  d;
    for (d = 0; d < dim; d++) hmin = PetscMin(hmin, S->h[d]);
    if (S->run.dt_max > 0) dt = PetscMin(dt, S->run.dt_max);
    need = (S->run.t_end - S->t) / dt;
    if (!(S->run.max_steps > 0 || need < room)) {
      char msg[512]; /* plain %g: 100, not PETSc's 100. */
      snprintf(msg, sizeof(msg), "run.t_end: %g s needs about %.3g steps of %g s (the fastest marker moves at %g m/s, cells are %g m), more than the step counter holds (%.0f); shorten run.t_end, set run.max_steps, or check the deck's velocities and material data",
               (double)S->run.t_end, (double)need, (double)dt, (double)S->smax, (double)hmin, (double)room);
      SETERRQ(comm, PS_ERR_RUN, "%s", msg);
    }
  }
  /* the initial state (a restart's was written by the run it continues) */
  if (!S->restarted) PetscCall(Output(S, &io));
  else io.t_last = S->t;
  PetscCall(History(S, &io));
  PetscCall(PetscTime(&w0));
  wlast       = w0;
  io.ckpt_wall = w0;
  while (S->t < S->run.t_end * (1.0 - 1e-12) && (S->run.max_steps <= 0 || S->step - step0 < S->run.max_steps)) {
    const PetscReal t_stop = PetscMin(S->out.t_next, S->run.t_end);
    PetscBool       output = PETSC_FALSE, due;
    PetscCall(PSSolverStep(S, t_stop));
    if (S->t >= t_stop * (1.0 - 1e-12) || (S->run.history_interval > 0 && S->step % S->run.history_interval == 0)) PetscCall(History(S, &io));
    if (S->t >= S->out.t_next * (1.0 - 1e-12)) {
      PetscCall(Output(S, &io));
      nout++;
      output        = PETSC_TRUE;
      S->out.t_next = S->run.output_interval > 0 ? S->out.t_next + S->run.output_interval : S->run.t_end;
    }
    PetscCall(CheckpointDue(S, &io, output, &due));
    if (due) PetscCall(WriteCheckpoint(S, &io));
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
    nout++;
    PetscCall(History(S, &io));
  }
  if (io.ckpt_step != S->step) PetscCall(WriteCheckpoint(S, &io)); /* and checkpointed */
  PetscCall(PetscTime(&now));
  PetscCall(PetscPrintf(comm, "done: %" PetscInt_FMT " steps to t = %.6e s in %.2f s wall, %" PetscInt_FMT " outputs in %s\n", S->step - step0, (double)S->t, (double)(now - w0), nout + (S->restarted ? 0 : 1), outdir));
  if (!rank) {
    PetscCall(PetscFClose(PETSC_COMM_SELF, io.hist));
    PetscCall(PetscFClose(PETSC_COMM_SELF, io.bodies));
    if (io.gauges) PetscCall(PetscFClose(PETSC_COMM_SELF, io.gauges));
  }
  S->body_names = S->material_names = NULL;
  PetscCall(VecDestroy(&io.out1));
  PetscCall(DMDestroy(&io.da1));
  PetscFunctionReturn(PETSC_SUCCESS);
}
