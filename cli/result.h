/* result.h — the checks every Boolean result gets in the CLI (colibri bool, colibri demo). */
#ifndef CB_CLI_RESULT_H
#define CB_CLI_RESULT_H

#include "brep/context.h"
#include "brep/mesh.h"
#include "brep/topo.h"

typedef struct {
    int valid;                          /* validator clean, volume and mesh computed */
    int mesh_ok;                        /* the mesh closed, manifold and free of
                                           self-intersections, or touching */
    char message[CB_ERROR_MSG_LEN + 32]; /* why not valid, else why the mesh is not ok
                                            ("" when both hold) */
    double volume, area;                /* B-rep integration (NAN when it failed) */
    int solids, faces;
    int mesh_done;                      /* the fields below are set */
    int triangles, closed, manifold, self_intersections;
    double mesh_volume;
    int touching;                       /* the mesh meets itself only where the result
                                           touches itself (see cb_cli_result_check) */
    int crossing;                       /* pairs of triangles found crossing where the mesh
                                           meets itself (0: not looked for, or none) */
} cb_cli_result;

/* Validates res at its tolerance, integrates its volume and area (CB_MASS_REL_TOL; the area
 * must be positive and the faces' vector area within twice the tolerance times the edges'
 * length of zero, else the volume is not trusted and the result is not valid), tessellates
 * it into mesh (replacing its contents; default tolerances) and checks the mesh (closed,
 * manifold, self-intersections, volume, and the B-rep's volume within twice the chordal
 * tolerance times the area of the mesh's); the first failure is r->message. The empty body (no
 * face) is valid with volume 0 and an empty mesh that passes every check. A valid result
 * whose closed mesh meets itself (vertices where triangles form several fans, or CGAL's
 * self-intersections) with every pair of triangles that meet touching, none crossing
 * (cb_mesh_check_contacts within the result's tolerance), is marked touching, with a message
 * saying so: it touches itself, or its solids touch each other, along curves or at points (a
 * union of operands that touch: not a manifold solid there, as the exact result is not). A
 * mesh that is open, or meets itself otherwise, is not ok (r->mesh_ok = 0, the reason in
 * r->message; crossing triangle pairs counted in r->crossing): a result to report as failed. */
void cb_cli_result_check(cb_cli_result *r, cb_topo_body *res, cb_mesh_t mesh,
                         cb_context *ctx);

#endif
