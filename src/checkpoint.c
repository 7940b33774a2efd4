/*
  checkpoint.c - checkpoint and restart of a run.

  OUTDIR/checkpoint.h5 holds every registered marker field as /checkpoint/<name>
  (N x block size, each rank's markers a contiguous slab in rank order), the
  per-rank marker counts and booked losses, and the solver's time, step, dt and
  wave speed.  Restarting on the same rank count gives every rank back its own
  markers in their order, so the run continues bitwise as if uninterrupted; on
  another rank count the markers are read in equal slabs and migrated.
*/
#include <hdf5.h>
#include "solver.h"

#define H5CHK(e, what) PetscCheck((e) >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "HDF5 call %s failed", what)

static hid_t H5Type(PetscDataType t)
{
  return t == PETSC_REAL ? H5T_NATIVE_DOUBLE : t == PETSC_INT64 ? H5T_NATIVE_INT64 : (sizeof(PetscInt) == 8 ? H5T_NATIVE_INT64 : H5T_NATIVE_INT);
}

/* collective slab I/O of an (N, bs) dataset */
static PetscErrorCode Slab(hid_t ds, hid_t type, void *buf, PetscInt n, PetscInt bs, PetscInt64 off, PetscBool write)
{
  hsize_t ld[2] = {(hsize_t)n, (hsize_t)bs}, st[2] = {(hsize_t)off, 0};
  hid_t   fs = H5Dget_space(ds), ms = H5Screate_simple(2, ld, NULL), xfer = H5Pcreate(H5P_DATASET_XFER);

  PetscFunctionBeginUser;
  if (n > 0) H5CHK(H5Sselect_hyperslab(fs, H5S_SELECT_SET, st, NULL, ld, NULL), "select");
  else {
    H5CHK(H5Sselect_none(fs), "select");
    H5CHK(H5Sselect_none(ms), "select");
  }
  H5CHK(H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE), "dxpl");
  if (write) H5CHK(H5Dwrite(ds, type, ms, fs, xfer, buf), "H5Dwrite");
  else H5CHK(H5Dread(ds, type, ms, fs, xfer, buf), "H5Dread");
  H5Pclose(xfer);
  H5Sclose(ms);
  H5Sclose(fs);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSSolverCheckpoint(PSSolver *S, const char filename[])
{
  MPI_Comm      comm = PetscObjectComm((PetscObject)S->sw);
  PetscMPIInt   rank, size;
  PetscInt      nf, bs[PS_MAX_FIELDS], n, f;
  const char   *names[PS_MAX_FIELDS];
  PetscDataType types[PS_MAX_FIELDS];
  PetscInt64    nl, off = 0, N = 0;
  hid_t         fapl, file, grp, sp, ds;
  hsize_t       dims[2];
  PetscReal     state[4] = {S->t, S->dt, S->smax, (PetscReal)S->step}, lost[6];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PSMarkersFieldList(S->scene, &nf, names, bs, types));
  PetscCall(DMSwarmGetLocalSize(S->sw, &n));
  nl = n;
  PetscCallMPI(MPI_Exscan(&nl, &off, 1, MPIU_INT64, MPI_SUM, comm));
  if (!rank) off = 0;
  PetscCallMPI(MPI_Allreduce(&nl, &N, 1, MPIU_INT64, MPI_SUM, comm));
  fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5CHK(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), "fapl");
  file = H5Fcreate(filename, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  PetscCheck(file >= 0, comm, PETSC_ERR_FILE_OPEN, "cannot create checkpoint %s", filename);
  H5Pclose(fapl);
  grp = H5Gcreate2(file, "/checkpoint", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  for (f = 0; f < nf; f++) {
    void *buf;
    dims[0] = (hsize_t)N;
    dims[1] = (hsize_t)bs[f];
    sp      = H5Screate_simple(2, dims, NULL);
    ds      = H5Dcreate2(grp, names[f], H5Type(types[f]), sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5CHK(ds, names[f]);
    PetscCall(DMSwarmGetField(S->sw, names[f], NULL, NULL, &buf));
    PetscCall(Slab(ds, H5Type(types[f]), buf, n, bs[f], off, PETSC_TRUE));
    PetscCall(DMSwarmRestoreField(S->sw, names[f], NULL, NULL, &buf));
    H5Dclose(ds);
    H5Sclose(sp);
  }
  /* per rank: marker count and booked losses; the solver state */
  {
    PetscReal row[7] = {(PetscReal)n, S->lost_local.mass, S->lost_local.p[0], S->lost_local.p[1], S->lost_local.p[2], S->lost_local.kinetic + S->lost_local.internal, (PetscReal)S->lost_local.markers};
    dims[0] = (hsize_t)size;
    dims[1] = 7;
    sp      = H5Screate_simple(2, dims, NULL);
    ds      = H5Dcreate2(grp, "ranks", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    PetscCall(Slab(ds, H5T_NATIVE_DOUBLE, row, 1, 7, rank, PETSC_TRUE));
    H5Dclose(ds);
    H5Sclose(sp);
    dims[0] = 4;
    sp      = H5Screate_simple(1, dims, NULL);
    ds      = H5Dcreate2(grp, "state", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    {
      hid_t xfer = H5Pcreate(H5P_DATASET_XFER);
      H5CHK(H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE), "dxpl");
      H5CHK(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, xfer, state), "state");
      H5Pclose(xfer);
    }
    H5Dclose(ds);
    H5Sclose(sp);
  }
  (void)lost;
  H5Gclose(grp);
  H5Fclose(file);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Read a checkpoint into an empty swarm whose fields are registered. */
PetscErrorCode PSSolverRestart(PSSolver *S, const char filename[])
{
  MPI_Comm      comm = PetscObjectComm((PetscObject)S->sw);
  PetscMPIInt   rank, size;
  PetscInt      nf, bs[PS_MAX_FIELDS], n, f, r, nranks;
  const char   *names[PS_MAX_FIELDS];
  PetscDataType types[PS_MAX_FIELDS];
  PetscInt64    off = 0, N;
  hid_t         fapl, file, grp, ds, sp;
  hsize_t       dims[2];
  PetscReal     state[4], *rows;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5CHK(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), "fapl");
  file = H5Fopen(filename, H5F_ACC_RDONLY, fapl);
  PetscCheck(file >= 0, comm, PETSC_ERR_FILE_OPEN, "cannot open checkpoint %s", filename);
  H5Pclose(fapl);
  grp = H5Gopen2(file, "/checkpoint", H5P_DEFAULT);
  H5CHK(grp, "/checkpoint");
  ds = H5Dopen2(grp, "ranks", H5P_DEFAULT);
  sp = H5Dget_space(ds);
  H5Sget_simple_extent_dims(sp, dims, NULL);
  H5Sclose(sp);
  nranks = (PetscInt)dims[0];
  PetscCall(PetscMalloc1(7 * nranks, &rows));
  H5CHK(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows), "ranks");
  H5Dclose(ds);
  ds = H5Dopen2(grp, "state", H5P_DEFAULT);
  H5CHK(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, state), "state");
  H5Dclose(ds);
  N = 0;
  for (r = 0; r < nranks; r++) N += (PetscInt64)rows[7 * r];
  if (nranks == size) {
    /* same rank count: every rank its own slab, its own order, its own books */
    for (r = 0; r < rank; r++) off += (PetscInt64)rows[7 * r];
    n                        = (PetscInt)rows[7 * rank];
    S->lost_local.mass       = rows[7 * rank + 1];
    S->lost_local.p[0]       = rows[7 * rank + 2];
    S->lost_local.p[1]       = rows[7 * rank + 3];
    S->lost_local.p[2]       = rows[7 * rank + 4];
    S->lost_local.kinetic    = rows[7 * rank + 5];
    S->lost_local.internal   = 0.0;
    S->lost_local.markers    = (PetscInt64)rows[7 * rank + 6];
  } else {
    /* another rank count: equal slabs, books summed on rank 0, then migrate */
    off = N * rank / size;
    n   = (PetscInt)(N * (rank + 1) / size - off);
    PetscCall(PetscMemzero(&S->lost_local, sizeof(S->lost_local)));
    if (!rank)
      for (r = 0; r < nranks; r++) {
        S->lost_local.mass += rows[7 * r + 1];
        S->lost_local.p[0] += rows[7 * r + 2];
        S->lost_local.p[1] += rows[7 * r + 3];
        S->lost_local.p[2] += rows[7 * r + 4];
        S->lost_local.kinetic += rows[7 * r + 5];
        S->lost_local.markers += (PetscInt64)rows[7 * r + 6];
      }
  }
  PetscCall(PetscFree(rows));
  PetscCall(DMSwarmSetLocalSizes(S->sw, n, PetscMax(16, n / 16)));
  PetscCall(PSMarkersFieldList(S->scene, &nf, names, bs, types));
  for (f = 0; f < nf; f++) {
    void *buf;
    ds = H5Dopen2(grp, names[f], H5P_DEFAULT);
    PetscCheck(ds >= 0, comm, PETSC_ERR_FILE_UNEXPECTED, "checkpoint %s has no field %s: was it written for this deck?", filename, names[f]);
    PetscCall(DMSwarmGetField(S->sw, names[f], NULL, NULL, &buf));
    PetscCall(Slab(ds, H5Type(types[f]), buf, n, bs[f], off, PETSC_FALSE));
    PetscCall(DMSwarmRestoreField(S->sw, names[f], NULL, NULL, &buf));
    H5Dclose(ds);
  }
  H5Gclose(grp);
  H5Fclose(file);
  S->t    = state[0];
  S->dt   = state[1];
  S->smax = state[2];
  S->step = (PetscInt)state[3];
  if (nranks != size) PetscCall(PSSolverMigrate(S));
  PetscFunctionReturn(PETSC_SUCCESS);
}
