/* colibri.h — the public interface of Colibri: solid Booleans on B-rep models with B-spline
 * faces. One include gives every module header; each documents its own functions.
 *
 *   brep/status.h    cb_status (every fallible call returns one) and cb_error (its message)
 *   brep/context.h   cb_context: thread count, progress callback, cancel flag
 *   brep/nurbs.h     B-spline curves and surfaces      brep/analytic.h  planes, quadrics, tori
 *   brep/topo.h      B-rep bodies (cb_topo_body_new / cb_topo_body_free), validation
 *   brep/prim.h      box, sphere, ellipsoid, cylinder, cone, torus as B-reps
 *   brep/face.h      a trimmed face as a query object (inside/outside, rays, distance)
 *   brep/mass.h      volume, area, centroid of a B-rep   brep/tess.h  watertight tessellation
 *   brep/mesh.h      triangle meshes (cb_mesh_init / cb_mesh_clear), mesh_check.h: CGAL checks
 *   ssi/ssi.h        surface/surface intersection      io/step.h, io/step_write.h: STEP files
 *   boolean/bool.h   broad phase and point-in-solid classification (the Booleans' first stages)
 *   io/mesh.h        STL / OBJ / PLY / OFF             io/bpt.h: Bezier patch files
 *   models/models.h  the shipped model generators
 *
 * Conventions: names are cb_<module>_<verb>; handles come in _new/_free pairs and value types
 * in _init/_clear pairs; the caller owns what it passes in and frees what it gets back; every
 * tolerance is an explicit parameter whose default the header states. Nothing exits or aborts.
 * Compile with the flags of `pkg-config --cflags colibri` (or find_package(colibri) in CMake). */
#ifndef COLIBRI_H
#define COLIBRI_H

/* The arithmetic libraries' headers carry their own C++ guards (and C++ overloads that may not
 * sit inside extern "C"): included first, they are skipped when the module headers name them. */
#include <arb.h>
#include <flint/flint.h>
#include <flint/fmpq.h>
#include <flint/fmpz.h>
#include <flint/fmpz_mat.h>
#include <flint/fmpz_mpoly.h>
#include <flint/fmpz_poly.h>
#include <flint/nmod_mat.h>
#include <flint/nmod_vec.h>

#ifdef __cplusplus
extern "C" {
#endif

#include "brep/status.h"
#include "brep/context.h"
#include "brep/geom.h"
#include "brep/nurbs.h"
#include "brep/analytic.h"
#include "brep/bbox.h"
#include "brep/topo.h"
#include "brep/prim.h"
#include "brep/face.h"
#include "brep/mass.h"
#include "brep/mesh.h"
#include "brep/mesh_check.h"
#include "brep/tess.h"
#include "ssi/ssi.h"
#include "boolean/bool.h"
#include "io/step.h"
#include "io/step_write.h"
#include "io/mesh.h"
#include "io/bpt.h"
#include "models/models.h"

/* The library's version, "MAJOR.MINOR.PATCH". */
const char *cb_version(void);

#ifdef __cplusplus
}
#endif

#endif
