/*
  io.c - parallel HDF5 output of the markers.

  One file, written collectively with MPI-IO: each rank writes its own slab of
  every dataset at the offset given by an exclusive scan of the local counts;
  nothing is gathered on one rank.  Schema (later issues extend it, never
  rename it):

    /markers/x (N x dim, m)   /markers/v (N x dim, m/s)   /markers/id (int64)
    /markers/mass (kg; per metre of depth in 2D)  /markers/volume (m^3; m^2 in 2D)
    /markers/axis1, axis2, axis3 (N x 3; when a material is anisotropic)
    /markers/body, /markers/ply (-1 outside laminates), /markers/material (int32)
    /markers/stress (N x 3 x 3 Cauchy, Pa, tension positive), /markers/pressure (Pa),
    /markers/energy (J/kg), and when a material uses them /markers/plastic_strain,
    /markers/temperature (K), /markers/damage (N: Johnson-Cook; N x 4 with ply
    failure: d_ft, d_fc, d_mt, d_mc), /markers/interface_damage (N; laminates with
    interface: cohesive: damage of the ply interface next to the marker, open
    at 1); root attribute time (s).  axis1..3 are the
    current material axes (they turn with the material).
    attributes: /markers@body_names, /markers@material_names; root: deck,
    version, units, and whatever else the caller passes (petsc options, ranks).

  A ParaView .xmf beside the file is written by the Python front end.
*/
#include <hdf5.h>
#include "plyshock.h"

static PetscLogEvent PS_EVENT_Write;

#define H5CHK(e, what) PetscCheck((e) >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "HDF5 call %s failed", what)

/* Write one dataset: global shape (N), (N, b0) or (N, b0, b1) as b0, b1 are 0 or not. */
static PetscErrorCode WriteSlabN(hid_t group, const char *name, hid_t type, const void *buf, PetscInt n, PetscInt b0, PetscInt b1, PetscInt64 off, PetscInt64 N)
{
  hsize_t gdims[3] = {(hsize_t)N, (hsize_t)b0, (hsize_t)b1}, ldims[3] = {(hsize_t)n, (hsize_t)b0, (hsize_t)b1}, start[3] = {(hsize_t)off, 0, 0};
  int     rank     = b1 ? 3 : b0 ? 2 : 1;
  hid_t   fs, ms, ds, xfer;

  PetscFunctionBeginUser;
  fs = H5Screate_simple(rank, gdims, NULL);
  H5CHK(fs, "H5Screate_simple");
  ds = H5Dcreate2(group, name, type, fs, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(ds, name);
  ms = H5Screate_simple(rank, ldims, NULL);
  if (n > 0) H5CHK(H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, ldims, NULL), "H5Sselect_hyperslab");
  else {
    H5CHK(H5Sselect_none(fs), "H5Sselect_none");
    H5CHK(H5Sselect_none(ms), "H5Sselect_none");
  }
  xfer = H5Pcreate(H5P_DATASET_XFER);
  H5CHK(H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio");
  {
    /* a rank without markers still joins the collective write; HDF5 refuses a NULL buffer */
    static const double none = 0.0;
    if (N > 0) H5CHK(H5Dwrite(ds, type, ms, fs, xfer, buf ? buf : (const void *)&none), "H5Dwrite"); /* N = 0: every marker has left */
  }
  H5Pclose(xfer);
  H5Sclose(ms);
  H5Dclose(ds);
  H5Sclose(fs);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteSlab(hid_t group, const char *name, hid_t type, const void *buf, PetscInt n, PetscInt bs, PetscInt64 off, PetscInt64 N)
{
  PetscFunctionBeginUser;
  PetscCall(WriteSlabN(group, name, type, buf, n, bs, 0, off, N));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A string attribute, or an array of strings (fixed length). */
static PetscErrorCode WriteStrings(hid_t obj, const char *name, PetscInt n, const char *const s[], PetscBool scalar)
{
  size_t   len = 1;
  PetscInt i;
  char    *buf;
  hid_t    st, sp, at;
  hsize_t  dims = (hsize_t)n;

  PetscFunctionBeginUser;
  for (i = 0; i < n; i++) len = PetscMax(len, strlen(s[i]) + 1);
  PetscCall(PetscCalloc1(len * PetscMax(n, 1), &buf));
  for (i = 0; i < n; i++) PetscCall(PetscStrncpy(buf + i * len, s[i], len));
  st = H5Tcopy(H5T_C_S1);
  H5CHK(H5Tset_size(st, len), "H5Tset_size");
  H5CHK(H5Tset_strpad(st, H5T_STR_NULLTERM), "H5Tset_strpad");
  sp = scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &dims, NULL);
  at = H5Acreate2(obj, name, st, sp, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(at, name);
  H5CHK(H5Awrite(at, st, buf), "H5Awrite");
  H5Aclose(at);
  H5Sclose(sp);
  H5Tclose(st);
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSWriteMarkers(const PSScene *scene, DM sw, const char filename[], PetscReal time, PetscInt nattr, const char *const attr_names[], const char *const attr_values[], const char *const body_names[], const char *const material_names[])
{
  MPI_Comm    comm;
  PetscInt    n, dim = scene->dim, i, a;
  PetscInt64  nl, off = 0, N = 0;
  hid_t       fapl, file, grp, itype = sizeof(PetscInt) == 8 ? H5T_NATIVE_INT64 : H5T_NATIVE_INT;
  PetscReal  *x, *v, *mass, *vol, *axes, *tmp;
  PetscInt64 *id;
  PetscInt   *body, *ply, *mat;
  PetscBool   has_ply = PETSC_FALSE;
  static PetscBool registered = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (!registered) {
    PetscClassId cid;
    PetscCall(PetscClassIdRegister("plyshock io", &cid));
    PetscCall(PetscLogEventRegister("PSWriteMarkers", cid, &PS_EVENT_Write));
    registered = PETSC_TRUE;
  }
  PetscCall(PetscLogEventBegin(PS_EVENT_Write, 0, 0, 0, 0));
  PetscCall(PetscObjectGetComm((PetscObject)sw, &comm));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  nl = n;
  PetscCallMPI(MPI_Exscan(&nl, &off, 1, MPIU_INT64, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(&nl, &N, 1, MPIU_INT64, MPI_SUM, comm));
  {
    int r;
    PetscCallMPI(MPI_Comm_rank(comm, &r));
    if (!r) off = 0;
  }
  for (i = 0; i < scene->nbody; i++)
    if (scene->bodies[i].kind == PS_BODY_LAMINATE) has_ply = PETSC_TRUE;

  fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5CHK(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), "H5Pset_fapl_mpio");
  file = H5Fcreate(filename, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  PetscCheck(file >= 0, comm, PETSC_ERR_FILE_OPEN, "cannot create HDF5 file %s", filename);
  H5Pclose(fapl);
  grp = H5Gcreate2(file, "/markers", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(grp, "/markers");

  PetscCall(DMSwarmGetField(sw, PS_FIELD_X, NULL, NULL, (void **)&x));
  PetscCall(WriteSlab(grp, "x", H5T_NATIVE_DOUBLE, x, n, dim, off, N));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_X, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(WriteSlab(grp, "v", H5T_NATIVE_DOUBLE, v, n, dim, off, N));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&mass));
  PetscCall(WriteSlab(grp, "mass", H5T_NATIVE_DOUBLE, mass, n, 0, off, N));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&mass));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&vol));
  PetscCall(WriteSlab(grp, "volume", H5T_NATIVE_DOUBLE, vol, n, 0, off, N));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&vol));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_ID, NULL, NULL, (void **)&id));
  PetscCall(WriteSlab(grp, "id", H5T_NATIVE_INT64, id, n, 0, off, N));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_ID, NULL, NULL, (void **)&id));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  PetscCall(WriteSlab(grp, "body", itype, body, n, 0, off, N));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  PetscCall(WriteSlab(grp, "material", itype, mat, n, 0, off, N));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  if (has_ply) {
    PetscCall(DMSwarmGetField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&ply));
    PetscCall(WriteSlab(grp, "ply", itype, ply, n, 0, off, N));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&ply));
  } else {
    /* no laminate: every marker is outside one */
    PetscInt *m1;
    PetscCall(PetscMalloc1(PetscMax(n, 1), &m1));
    for (i = 0; i < n; i++) m1[i] = -1;
    PetscCall(WriteSlab(grp, "ply", itype, m1, n, 0, off, N));
    PetscCall(PetscFree(m1));
  }
  if (scene->anisotropic) {
    const char *nm[3] = {"axis1", "axis2", "axis3"};
    PetscCall(PetscMalloc1(3 * PetscMax(n, 1), &tmp));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&axes));
    for (a = 0; a < 3; a++) {
      for (i = 0; i < n; i++) {
        tmp[3 * i + 0] = axes[9 * i + 3 * a + 0];
        tmp[3 * i + 1] = axes[9 * i + 3 * a + 1];
        tmp[3 * i + 2] = axes[9 * i + 3 * a + 2];
      }
      PetscCall(WriteSlab(grp, nm[a], H5T_NATIVE_DOUBLE, tmp, n, 3, off, N));
    }
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&axes));
    PetscCall(PetscFree(tmp));
  }
  /* the state: Cauchy stress as N x 3 x 3 (tension positive), pressure, energy, and the optional fields */
  {
    const PetscInt ns = PSStressComponents(dim);
    PetscReal     *sg, *full, *fld;
    const char    *scal[][2] = {
      {PS_FIELD_PRESSURE, "pressure"},
      {PS_FIELD_ENERGY, "energy"},
      {PS_FIELD_EPS_P, "plastic_strain"},
      {PS_FIELD_TEMP, "temperature"},
      {PS_FIELD_DAMAGE, "damage"},
      {PS_FIELD_IDAMAGE, "interface_damage"}
    };
    const PetscBool have[] = {PETSC_TRUE, PETSC_TRUE, scene->need_plastic, scene->need_temperature, scene->ndamage > 0, scene->need_interface};
    const PetscInt  bs[]   = {0, 0, 0, 0, scene->ndamage > 1 ? scene->ndamage : 0, 0}; /* damage: N, or N x 4 for plies */
    PetscCall(PetscMalloc1(9 * PetscMax(n, 1), &full));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&sg));
    for (i = 0; i < n; i++) {
      const PetscReal *v = &sg[i * ns];
      PetscReal       *S = &full[9 * i];
      S[0] = v[0];
      S[4] = v[1];
      S[8] = v[2];
      if (dim == 3) {
        S[5] = S[7] = v[3];
        S[2] = S[6] = v[4];
        S[1] = S[3] = v[5];
      } else {
        S[1] = S[3] = v[3];
        S[2] = S[6] = S[5] = S[7] = 0.0;
      }
    }
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&sg));
    PetscCall(WriteSlabN(grp, "stress", H5T_NATIVE_DOUBLE, full, n, 3, 3, off, N));
    PetscCall(PetscFree(full));
    for (a = 0; a < 6; a++) {
      if (!have[a]) continue;
      PetscCall(DMSwarmGetField(sw, scal[a][0], NULL, NULL, (void **)&fld));
      PetscCall(WriteSlab(grp, scal[a][1], H5T_NATIVE_DOUBLE, fld, n, bs[a], off, N));
      PetscCall(DMSwarmRestoreField(sw, scal[a][0], NULL, NULL, (void **)&fld));
    }
  }
  PetscCall(WriteStrings(grp, "body_names", scene->nbody, body_names, PETSC_FALSE));
  PetscCall(WriteStrings(grp, "material_names", scene->nmaterial, material_names, PETSC_FALSE));
  H5Gclose(grp);
  {
    const char *ver = PLYSHOCK_VERSION, *units = "SI: m, kg, s, Pa, K; 2D quantities per metre of depth";
    PetscCall(WriteStrings(file, "version", 1, &ver, PETSC_TRUE));
    PetscCall(WriteStrings(file, "units", 1, &units, PETSC_TRUE));
    for (a = 0; a < nattr; a++) PetscCall(WriteStrings(file, attr_names[a], 1, &attr_values[a], PETSC_TRUE));
    {
      hid_t sp = H5Screate(H5S_SCALAR), at = H5Acreate2(file, "time", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT);
      H5CHK(H5Awrite(at, H5T_NATIVE_DOUBLE, &time), "H5Awrite time");
      H5Aclose(at);
      H5Sclose(sp);
    }
  }
  H5Fclose(file);
  PetscCall(PetscLogEventEnd(PS_EVENT_Write, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
