/* result.c — validation, volume and mesh checks of a Boolean result (cli/result.h). */
#include "cli/result.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "brep/mass.h"
#include "brep/mesh_check.h"
#include "brep/tess.h"

void cb_cli_result_check(cb_cli_result *r, cb_topo_body *res, cb_mesh_t mesh,
                         cb_context *ctx)
{
    memset(r, 0, sizeof *r);
    r->volume = r->area = r->mesh_volume = NAN;
    cb_error err;
    cb_error_clear(&err);
    r->faces = res->n_faces;
    r->solids = res->n_solids;
    cb_topo_report vr;
    cb_topo_report_init(&vr);
    cb_status st = cb_topo_validate(&vr, res, res->tol, 9, &err);
    r->valid = !st && vr.n == 0;
    if (!r->valid)
        snprintf(r->message, sizeof r->message, "result not valid: %s", st ? err.msg : vr.items[0]);
    cb_topo_report_clear(&vr);
    cb_mass_props m;
    st = cb_mass_body(&m, res, CB_MASS_REL_TOL, ctx, &err);
    if (!st) {
        r->volume = m.volume;
        r->area = m.area;
    } else if (r->valid) {
        r->valid = 0;
        snprintf(r->message, sizeof r->message, "volume: %s", err.msg);
    }
    if (res->n_faces == 0) {
        /* The empty solid (disjoint or touching operands): nothing to mesh, nothing wrong. */
        cb_mesh_clear(mesh);
        r->mesh_done = r->closed = r->manifold = 1;
        r->mesh_volume = 0;
        return;
    }
    if (ctx)
        cb_context_progress_reset(ctx);
    st = cb_tess_body(mesh, res, NULL, ctx, &err);
    cb_mesh_check_report cr;
    if (!st)
        st = cb_mesh_check(&cr, mesh, &err);
    if (!st) {
        r->mesh_done = 1;
        r->triangles = cr.triangles;
        r->closed = cr.closed;
        r->manifold = cr.edge_manifold && cr.vertex_manifold;
        r->self_intersections = cr.self_intersections;
        r->mesh_volume = cr.volume;
    } else if (r->valid) {
        r->valid = 0;
        snprintf(r->message, sizeof r->message, "mesh: %s", err.msg);
    }
    if (r->valid && r->mesh_done && r->solids >= 2 && r->closed && r->manifold &&
        r->self_intersections == 1) {
        r->touching = 1;
        snprintf(r->message, sizeof r->message,
                 "the result's %d solids touch each other along curves or at points (not a "
                 "manifold solid there); its mesh is reported self-intersecting where they do",
                 r->solids);
    }
}
