/* result.h — the checks every Boolean result gets in the CLI (colibri bool, colibri demo). */
#ifndef CB_CLI_RESULT_H
#define CB_CLI_RESULT_H

#include "brep/context.h"
#include "brep/mesh.h"
#include "brep/topo.h"

typedef struct {
    int valid;                          /* validator clean, volume and mesh computed */
    char message[CB_ERROR_MSG_LEN + 32]; /* why not valid ("" when valid) */
    double volume, area;                /* B-rep integration (NAN when it failed) */
    int solids, faces;
    int mesh_done;                      /* the fields below are set */
    int triangles, closed, manifold, self_intersections;
    double mesh_volume;
    int touching;                       /* the mesh crosses itself only because the result's
                                           solids touch (see cb_cli_result_check) */
} cb_cli_result;

/* Validates res at its tolerance, integrates its volume and area (CB_MASS_REL_TOL), tessellates
 * it into mesh (replacing its contents; default tolerances) and checks the mesh (closed,
 * manifold, self-intersections, volume); the first failure is r->message. The empty body (no
 * face) is valid with volume 0 and an empty mesh that passes every check. A valid result of
 * several solids whose closed, edge-manifold mesh CGAL reports self-intersecting is marked
 * touching, with a message saying so: its solids touch along curves or at points (a union of
 * operands that touch: not a manifold solid there, as the exact result is not); each solid's
 * own surface is not checked apart. */
void cb_cli_result_check(cb_cli_result *r, cb_topo_body *res, cb_mesh_t mesh,
                         cb_context *ctx);

#endif
