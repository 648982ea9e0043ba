/* result.c — validation, volume and mesh checks of a Boolean result (cli/result.h). */
#include "cli/result.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "brep/geom.h"
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
    /* The faces' integrated normals must close up (cb_mass_closure_bound at the body's
     * tolerance; measured on the committed corpus subset: at most 0.8% of the bound). */
    if (!st && r->valid) {
        double va = cb_vec3_norm(m.vector_area), bound = cb_mass_closure_bound(res, m.area, 0);
        if (!(va <= bound) || !(m.area >= 0)) {
            r->valid = 0;
            snprintf(r->message, sizeof r->message,
                     "volume: the faces' integrated normals do not close up (vector area "
                     "%.3g, the tolerance allows %.3g; area %.10g): a face integrated over "
                     "the wrong region, the volume %.10g not to be trusted",
                     va, bound, m.area, m.volume);
        }
    }
    if (res->n_faces == 0) {
        /* The empty solid (disjoint or touching operands): nothing to mesh, nothing wrong. */
        cb_mesh_clear(mesh);
        r->mesh_done = r->closed = r->manifold = r->mesh_ok = 1;
        r->mesh_volume = 0;
        return;
    }
    if (ctx)
        cb_context_progress_reset(ctx);
    st = cb_tess_body(mesh, res, NULL, ctx, &err);
    cb_mesh_check_report cr = {0};
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
    /* The exact result of operands that touch along a curve or at a point is no manifold
     * there, and its mesh meets itself: that is right only if no two triangles cross. */
    if (r->valid && r->mesh_done && r->closed && (!r->manifold || r->self_intersections == 1)) {
        cb_mesh_contacts c;
        st = cb_mesh_check_contacts(&c, mesh, res->tol > 0 ? res->tol : 1e-9, &err);
        if (!st && c.crossing == 0 && c.touching > 0) {
            char who[64];
            if (r->solids >= 2)
                snprintf(who, sizeof who, "the result's %d solids touch each other", r->solids);
            else
                snprintf(who, sizeof who, "the result touches itself");
            r->touching = 1;
            snprintf(r->message, sizeof r->message,
                     "%s along curves or at points (not a manifold solid there, as the exact "
                     "result is not): its mesh meets itself there, %d pairs of triangles "
                     "touching, none crossing",
                     who, c.touching);
        } else if (!st) {
            r->crossing = c.crossing;
        }
    }
    /* The B-rep's volume against its mesh's: the mesh lies within the chordal tolerance of the
     * faces, so the two differ by at most about that times the area. A larger difference
     * (a face integrated over the wrong side of its loops: the volume's sign turned) makes
     * the result invalid, not a number to trust. Twice the bound: the tolerance is met at
     * the triangles' sample points. The mesh's volume is its triangles' signed sum (CGAL's
     * is not defined for a closed mesh that touches itself, as a union of touching solids
     * does). */
    cb_tess_opts to, tr;
    cb_tess_opts_init(&to);
    if (r->valid && r->mesh_done && r->closed && isfinite(r->volume) &&
        cb_tess_opts_resolve(&tr, &to, res, &err) == CB_OK) {
        double mv = cb_mesh_volume(mesh), area = fmax(fabs(r->area), cb_mesh_area(mesh));
        double bound = 2 * tr.chord_tol * area + 1e-9 * fabs(mv);
        if (!(fabs(r->volume - mv) <= bound)) {
            r->valid = 0;
            snprintf(r->message, sizeof r->message,
                     "volume: the B-rep's volume %.10g and its mesh's %.10g differ by more "
                     "than the mesh's chordal error allows (%.3g)",
                     r->volume, mv, bound);
        }
    }
    /* A mesh that is open, or meets itself where the result does not only touch itself, is
     * no picture of a solid. */
    r->mesh_ok = r->mesh_done && r->closed &&
                 ((r->manifold && r->self_intersections == 0) || r->touching);
    if (r->valid && !r->mesh_ok) {
        if (!r->closed)
            snprintf(r->message, sizeof r->message,
                     "mesh not closed: %d edges of one triangle, %d of three or more",
                     cr.boundary_edges, cr.nonmanifold_edges);
        else if (r->crossing)
            snprintf(r->message, sizeof r->message,
                     "mesh crosses itself: %d pairs of triangles", r->crossing);
        else
            snprintf(r->message, sizeof r->message,
                     "mesh meets itself (%d edges of three or more triangles, %d vertices of "
                     "several fans, CGAL self-intersection %d) and the contacts were not "
                     "proved touching",
                     cr.nonmanifold_edges, cr.nonmanifold_vertices, cr.self_intersections);
    }
}
