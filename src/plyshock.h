/*
  plyshock.h - public C API of the plyshock solver.

  plyshock follows Schumacher, Bruner, Harstad & Key, "Modeling layered
  composite materials using MPM in an Eulerian shock physics code" (Sandia):
  material points (markers) ride through a fixed Eulerian grid (a DMDA) and are
  held in a DMSwarm.  Each ply of a laminate is inserted exactly: the piece of a
  (sub-)cell that the ply cuts out is a convex polygon/polyhedron whose exact
  area/volume and centroid give the marker's mass and position.

  Units are SI throughout: m, kg, s, Pa, K.

  Naming: suffix _p for per-marker quantities, _c for cells, _i for grid nodes.
*/
#ifndef PLYSHOCK_H
#define PLYSHOCK_H

#include <petscdmda.h>
#include <petscdmswarm.h>

#define PLYSHOCK_VERSION "0.1.0"

/* PETSc 3.18 returns plain 0; PETSC_SUCCESS arrived in 3.19 */
#if !PETSC_VERSION_GE(3, 19, 0)
  #define PETSC_SUCCESS 0
#endif

/* How a body becomes markers: the exact pieces of its (sub-)cells, or the
   points of a regular lattice in each cell that lie inside it (the fill of
   Uintah, Karamelo, NairnMPM), each with its lattice sub-cell's volume. */
typedef enum {
  PS_INSERT_EXACT   = 0,
  PS_INSERT_LATTICE = 1
} PSInsertion;

typedef enum {
  PS_BODY_LAMINATE = 0,
  PS_BODY_BOX      = 1,
  PS_BODY_SPHERE   = 2,
  PS_BODY_CYLINDER = 3
} PSBodyKind;

/* One body of a scene.  Filled by the Python front end (python/plyshock/core.py),
   validated there before it reaches C. */
typedef struct {
  PSBodyKind kind;
  PetscInt   material;         /* material id of a non-laminate body (plies carry their own) */
  PetscInt   priority;         /* the higher priority wins an overlap */
  PetscInt   subdivision;      /* sub-cells per cell and direction, >= 1 (exact insertion) */
  PSInsertion insertion;       /* exact (default) or lattice */
  PetscInt   points_per_cell;  /* lattice: points per cell and direction, >= 1 (n^dim per cell) */
  PetscReal  volume_tolerance; /* relative volume tolerance of curved bodies (-) */
  PetscReal  sliver_fraction;  /* pieces below this fraction of their sub-cell are merged (-) */
  PetscReal  velocity[3];      /* initial velocity (m/s) */
  /* laminate and box: an oriented box origin + [0,size_a] e_a (m); e[a] unit axes */
  PetscReal  origin[3];        /* m */
  PetscReal  e[3][3];          /* frame axes 1, 2, 3 as unit vectors in x, y, z */
  PetscReal  size[3];          /* extents along axes 1, 2, 3 (m); laminate: L1, L2, total thickness */
  PetscInt   nply;             /* laminate plies (0 for other bodies) */
  PetscReal *z;                /* nply + 1 ply interfaces along axis 3 from the origin (m) */
  PetscInt  *ply_material;     /* nply material ids */
  PetscReal *ply_axes;         /* nply x 9: material axes 1, 2, 3 of each ply (unit vectors) */
  /* sphere (a disk in 2D) and cylinder */
  PetscReal center[3];         /* sphere centre, cylinder base centre (m) */
  PetscReal axis[3];           /* cylinder unit axis */
  PetscReal radius;            /* m */
  PetscReal length;            /* cylinder length along axis (m) */
  /* representation */
  PetscInt  cellmat;           /* -1: markers; else `representation: cells`, the index of its material among the cell materials */
  PetscReal pressure;          /* initial pressure (Pa): sets the initial specific energy through the EOS at the initial density */
  PetscReal density;           /* a body in cells: its initial density (kg/m^3); 0: its material's */
  PetscReal plastic_strain;    /* initial equivalent plastic strain (-) */
} PSBody;

/* The scene: grid, materials, bodies.  Owned by the caller. */
typedef struct {
  PetscInt   dim;             /* 2 (plane strain, per metre of depth; or axisymmetric) or 3 */
  PetscReal  lower[3];        /* domain lower corner (m) */
  PetscReal  upper[3];        /* domain upper corner (m) */
  PetscInt   cells[3];        /* cells per direction */
  PetscInt   nmaterial;
  PetscReal *density;         /* kg/m^3, per material */
  PetscBool  anisotropic;     /* some material needs material axes on its markers */
  PetscBool  need_plastic;    /* some material has a strength model: plastic strain field */
  PetscBool  need_temperature;/* some material uses temperature (Johnson-Cook): temperature field */
  PetscInt   ndamage;         /* damage components per marker: 0 none, 1 Johnson-Cook failure, 4 ply failure (FT, FC, MT, MC) */
  PetscReal *T0;              /* initial temperature per material (K) */
  PetscBool  need_affine;     /* run.transfer apic: markers carry the affine velocity C_p */
  PetscInt   ncellmat;        /* materials of cell bodies (0: no Eulerian cells) */
  PetscInt  *cellmat;         /* their material ids, deck order */
  PetscInt   nbody;
  PSBody    *bodies;
  PetscBool  need_interface;  /* some laminate has cohesive ply interfaces: markers carry interface damage */
  PetscBool  axisymmetric;    /* 2D geometry: axisymmetric (x = r >= 0, y = z; masses and volumes of the full
                                 revolution) instead of plane strain */
} PSScene;

/* Counts of an insertion, per rank or reduced over ranks. */
typedef struct {
  PetscInt64 pieces;          /* non-empty (sub-cell, body, ply) pieces; lattice bodies: points inside */
  PetscInt64 markers;         /* markers made */
  PetscInt64 slivers_merged;  /* pieces below sliver_fraction merged into a neighbour */
  PetscInt64 slivers_kept;    /* slivers with no neighbour of the same ply in the cell */
} PSInsertStats;

/* Marker fields; registered only when a scene needs them. */
#define PS_FIELD_X        "x"        /* position (m), dim reals */
#define PS_FIELD_MASS     "mass"     /* m_p (kg; per metre of depth in 2D plane strain; the full revolution in axisymmetric) */
#define PS_FIELD_VOLUME   "volume"   /* V_p (m^3; m^2 in 2D plane strain; the full revolution's m^3 in axisymmetric) */
#define PS_FIELD_VELOCITY "v"        /* v_p (m/s), dim reals */
#define PS_FIELD_AXES     "axes"     /* material axes 1, 2, 3: 9 reals, anisotropic scenes only */
#define PS_FIELD_BODY     "body"     /* body id */
#define PS_FIELD_PLY      "ply"      /* ply id, -1 outside laminates; scenes with laminates only */
#define PS_FIELD_MATERIAL "material" /* material id */
#define PS_FIELD_ID       "id"       /* global marker id, unique for the marker's life (int64) */
/* solver state */
#define PS_FIELD_F        "F"        /* deformation gradient F_p, dim x dim (row major) */
#define PS_FIELD_V0       "volume0"  /* initial volume V0_p (m^3; m^2 in 2D plane strain; m^3 in axisymmetric) */
#define PS_FIELD_STRESS   "stress"   /* Cauchy stress without viscosity (Pa), symmetric: 3D xx,yy,zz,yz,xz,xy; 2D xx,yy,zz,xy */
#define PS_FIELD_SDEV     "sdev"     /* unrotated deviatoric stress R^T s R (Pa), same layout */
#define PS_FIELD_PRESSURE "pressure" /* p (Pa), compression positive */
#define PS_FIELD_Q        "q"        /* artificial viscosity pressure (Pa) */
#define PS_FIELD_ENERGY   "energy"   /* specific internal energy e (J/kg) */
#define PS_FIELD_EPS_P    "plastic_strain" /* equivalent plastic strain (-) */
#define PS_FIELD_TEMP     "temperature"    /* K */
#define PS_FIELD_DAMAGE   "damage"         /* damage (-), failed at 1: Johnson-Cook D, or a ply's d_ft, d_fc, d_mt, d_mc */
#define PS_FIELD_IDAMAGE  "interface_damage" /* damage of the cohesive ply interface next to the marker (-), open at 1;
                                                   laminates with interface: cohesive only (contact.c) */
#define PS_FIELD_AFFINE   "affine"         /* APIC affine velocity C_p (1/s), dim x dim (row major); run.transfer apic only */
#define PS_FIELD_SMAT     "stress_material" /* ply stress in material axes less the volumetric part, Voigt 11,22,33,23,13,12 (Pa); anisotropic scenes */
#define PS_PAD 1 /* grid nodes outside the domain on each side (shape functions reach one cell out) */

/* geometry (geom.c): no PETSc objects are made */
PETSC_EXTERN PetscErrorCode PSBodyBoundingBox(const PSScene *, PetscInt b, PetscReal lo[3], PetscReal hi[3]);
PETSC_EXTERN PetscReal      PSBodyVolume(const PSScene *, PetscInt b);
PETSC_EXTERN PetscErrorCode PSOverlapVolume(const PSScene *, PetscInt a, PetscInt b, PetscReal *vol);
PETSC_EXTERN PetscErrorCode PSBodyDomainVolume(const PSScene *, PetscInt b, PetscReal *vol);

/* insertion (insert.c) */
PETSC_EXTERN PetscErrorCode PSInitializePackage(void);
PETSC_EXTERN PetscErrorCode PSCountPieces(const PSScene *, const PetscInt cs[3], const PetscInt ce[3], PetscInt64 *n_body_ply);
PETSC_EXTERN PetscErrorCode PSInsertMarkers(const PSScene *, DM da, DM sw, PSInsertStats *);
PETSC_EXTERN PetscErrorCode PSCountSlabs(const PSScene *, PetscInt axis, PetscInt k0, PetscInt k1, PetscInt stride, PetscInt64 counts[]);

/* markers (markers.c) */
PETSC_EXTERN PetscErrorCode PSMarkersRegisterFields(const PSScene *, DM sw, PetscInt *bytes_per_marker);
PETSC_EXTERN PetscErrorCode PSMarkersBytes(const PSScene *, DM sw, PetscInt *bytes);
PETSC_EXTERN PetscErrorCode PSMarkersFieldList(const PSScene *, PetscInt *n, const char *names[], PetscInt bs[], PetscDataType types[]);
#define PS_MAX_FIELDS 32
PETSC_EXTERN PetscErrorCode PSCellOwnership(DM da, PetscInt cs[3], PetscInt ce[3]);
/* stored stress components: 3D xx,yy,zz,yz,xz,xy; 2D xx,yy,zz,xy (inline: the
   transfers' per-marker loops call it, and a call there spills every vector
   register) */
static inline PetscInt PSStressComponents(PetscInt dim)
{
  return dim == 3 ? 6 : 4;
}

/* output (io.c) */
PETSC_EXTERN PetscErrorCode PSWriteMarkers(const PSScene *, DM sw, const char filename[], PetscReal time, PetscInt nattr, const char *const attr_names[], const char *const attr_values[], const char *const body_names[], const char *const material_names[]);

#endif
