/* Validation of a body: shell closure and edge use, loop closure, edge ends at vertices,
 * degenerate faces, edges on their faces' surfaces. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/topo.h"

enum { MAX_KEPT = 1000 };

void cb_topo_report_init(cb_topo_report *r) { memset(r, 0, sizeof *r); }

void cb_topo_report_clear(cb_topo_report *r)
{
    for (int k = 0; k < r->n; k++)
        free(r->items[k]);
    free(r->items);
    cb_topo_report_init(r);
}

/* Appends a problem; beyond MAX_KEPT only counts it. Returns CB_ERR_NOMEM on failure. */
static cb_status problem(cb_topo_report *r, cb_error *err, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static cb_status problem(cb_topo_report *r, cb_error *err, const char *fmt, ...)
{
    if (r->n >= MAX_KEPT) {
        r->dropped++;
        return CB_OK;
    }
    if (r->n == r->cap) {
        int c = r->cap ? 2 * r->cap : 16;
        char **p = realloc(r->items, (size_t)c * sizeof *p);
        if (!p)
            return cb_error_set(err, CB_ERR_NOMEM, "validation report: out of memory");
        r->items = p;
        r->cap = c;
    }
    char buf[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    if (!(r->items[r->n] = malloc(strlen(buf) + 1)))
        return cb_error_set(err, CB_ERR_NOMEM, "validation report: out of memory");
    strcpy(r->items[r->n++], buf);
    return CB_OK;
}

static int coedge_start(const cb_topo_body *b, const cb_topo_coedge *c)
{
    return b->edges[c->edge].v[c->sense ? 0 : 1];
}

static int coedge_end(const cb_topo_body *b, const cb_topo_coedge *c)
{
    return b->edges[c->edge].v[c->sense ? 1 : 0];
}

static int shell_of(const cb_topo_body *b, int coedge)
{
    return b->faces[b->loops[b->coedges[coedge].loop].face].shell;
}

static double edge_tol(const cb_topo_body *b, int e, double tol)
{
    return fmax(tol, b->edges[e].tol);
}

/* Edge parameter ranges and curve ends against the vertices. */
static cb_status check_edges(cb_topo_report *r, const cb_topo_body *b, double tol, cb_error *err)
{
    cb_status st = CB_OK;
    for (int e = 0; e < b->n_edges && !st; e++) {
        const cb_topo_edge *ed = &b->edges[e];
        if (!(ed->t0 < ed->t1)) {
            st = problem(r, err, "edge %d: empty parameter range [%g, %g]", e, ed->t0, ed->t1);
            continue;
        }
        double p[2][3];
        const cb_topo_curve *c = &b->curves[ed->curve];
        cb_topo_curve_eval(p[ed->same_sense ? 0 : 1], c, ed->t0);
        cb_topo_curve_eval(p[ed->same_sense ? 1 : 0], c, ed->t1);
        for (int j = 0; j < 2 && !st; j++) {
            double d = cb_vec3_dist(p[j], b->vertices[ed->v[j]].p);
            r->max_edge_vertex = fmax(r->max_edge_vertex, d);
            if (d > edge_tol(b, e, tol))
                st = problem(r, err, "edge %d: curve %s is %.3g from vertex %d", e,
                             j ? "end" : "start", d, ed->v[j]);
        }
    }
    return st;
}

/* Every edge: the coedges using it, per shell. */
static cb_status check_edge_use(cb_topo_report *r, const cb_topo_body *b, cb_error *err)
{
    cb_status st = CB_OK;
    for (int e = 0; e < b->n_edges && !st; e++) {
        int first = b->edge_start[e], n = b->edge_start[e + 1] - first;
        if (n == 0)
            continue;
        const int *co = b->edge_coedges + first;
        int shell = shell_of(b, co[0]);
        for (int k = 1; k < n && !st; k++)
            if (shell_of(b, co[k]) != shell)
                st = problem(r, err, "edge %d: shared by shells %d and %d", e, shell,
                             shell_of(b, co[k]));
        if (st)
            break;
        int closed = b->shells[shell].closed;
        if (n > 2 || (closed && n == 1))
            st = problem(r, err, "edge %d: used by %d coedge%s in %s shell %d", e, n,
                         n == 1 ? "" : "s", closed ? "closed" : "open", shell);
        else if (n == 2 && b->coedges[co[0]].sense == b->coedges[co[1]].sense)
            st = problem(r, err, "edge %d: both coedges run %s it (faces %d and %d)", e,
                         b->coedges[co[0]].sense ? "along" : "against",
                         b->loops[b->coedges[co[0]].loop].face,
                         b->loops[b->coedges[co[1]].loop].face);
    }
    return st;
}

/* Length of an edge's curve by 16 chords. */
static double edge_length(const cb_topo_body *b, int e)
{
    const cb_topo_edge *ed = &b->edges[e];
    double prev[3], len = 0;
    for (int k = 0; k <= 16; k++) {
        double p[3];
        cb_topo_curve_eval(p, &b->curves[ed->curve], ed->t0 + (ed->t1 - ed->t0) * k / 16.0);
        if (k)
            len += cb_vec3_dist(p, prev);
        memcpy(prev, p, sizeof p);
    }
    return len;
}

/* Loops closed topologically and in 3D; faces bounded and not degenerate. */
static cb_status check_loops(cb_topo_report *r, const cb_topo_body *b, double tol, cb_error *err)
{
    cb_status st = CB_OK;
    for (int f = 0; f < b->n_faces && !st; f++) {
        const cb_topo_face *fc = &b->faces[f];
        if (fc->count == 0)
            st = problem(r, err, "face %d: no boundary loop", f);
        const cb_topo_surface *s = &b->surfaces[fc->surface];
        if (!st && s->kind == CB_SURFACE_NURBS) {
            cb_aabb box;
            cb_nurbs_surface_aabb(&box, s->nurbs);
            double diag[3] = {box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]};
            if (cb_vec3_norm(diag) <= tol)
                st = problem(r, err, "face %d: surface collapses to a point", f);
        }
        for (int l = fc->first; l < fc->first + fc->count && !st; l++) {
            const cb_topo_loop *lp = &b->loops[l];
            if (lp->count == 0) {
                st = problem(r, err, "face %d: loop %d has no coedges", f, l);
                continue;
            }
            double len = 0;
            for (int k = 0; k < lp->count && !st; k++) {
                const cb_topo_coedge *c = &b->coedges[lp->first + k];
                const cb_topo_coedge *n = &b->coedges[lp->first + (k + 1) % lp->count];
                len += edge_length(b, c->edge);
                if (coedge_end(b, c) != coedge_start(b, n)) {
                    st = problem(r, err,
                                 "face %d: loop %d is open: coedge %d ends at vertex %d, "
                                 "coedge %d starts at vertex %d",
                                 f, l, lp->first + k, coedge_end(b, c),
                                 lp->first + (k + 1) % lp->count, coedge_start(b, n));
                    continue;
                }
                double s0[3], e0[3], s1[3], e1[3];
                cb_topo_coedge_ends(s0, e0, b, lp->first + k);
                cb_topo_coedge_ends(s1, e1, b, lp->first + (k + 1) % lp->count);
                double gap = cb_vec3_dist(e0, s1);
                r->max_loop_gap = fmax(r->max_loop_gap, gap);
                if (gap > fmax(edge_tol(b, c->edge, tol), edge_tol(b, n->edge, tol)))
                    st = problem(r, err, "face %d: loop %d has a gap of %.3g after coedge %d", f, l,
                                 gap, lp->first + k);
            }
            if (!st && !(len > tol))
                st = problem(r, err, "face %d: loop %d is degenerate (length %.3g)", f, l, len);
        }
    }
    return st;
}

/* Samples of every edge against the surfaces of the faces using it. */
static cb_status check_on_surfaces(cb_topo_report *r, const cb_topo_body *b, double tol,
                                   int n_samples, cb_error *err)
{
    cb_topo_projector *pr = calloc((size_t)b->n_surfaces + 1, sizeof *pr);
    char *ready = calloc((size_t)b->n_surfaces + 1, 1);
    cb_status st = CB_OK;
    if (!pr || !ready)
        st = cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
    if (n_samples < 2)
        n_samples = 2;
    for (int f = 0; f < b->n_faces && !st; f++) {
        const cb_topo_face *fc = &b->faces[f];
        int s = fc->surface;
        if (!ready[s]) {
            if ((st = cb_topo_projector_init(&pr[s], &b->surfaces[s], err)))
                break;
            ready[s] = 1;
        }
        for (int l = fc->first; l < fc->first + fc->count && !st; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count && !st; c++) {
                int e = b->coedges[c].edge;
                const cb_topo_edge *ed = &b->edges[e];
                double worst = 0;
                for (int k = 0; k < n_samples; k++) {
                    double p[3];
                    cb_topo_curve_eval(p, &b->curves[ed->curve],
                                       ed->t0 + (ed->t1 - ed->t0) * k / (n_samples - 1));
                    worst = fmax(worst, cb_topo_projector_distance(&pr[s], p));
                }
                r->max_edge_surface = fmax(r->max_edge_surface, worst);
                if (worst > edge_tol(b, e, tol))
                    st = problem(r, err, "edge %d: %.3g off the %s surface of face %d", e, worst,
                                 cb_topo_surface_type_name(&b->surfaces[s]), f);
            }
    }
    for (int s = 0; pr && ready && s < b->n_surfaces; s++)
        if (ready[s])
            cb_topo_projector_clear(&pr[s]);
    free(pr);
    free(ready);
    return st;
}

cb_status cb_topo_validate(cb_topo_report *r, cb_topo_body *b, double tol, int n_samples,
                           cb_error *err)
{
    cb_error local;
    cb_status st = cb_topo_body_index(b, &local);
    if (st == CB_ERR_NOMEM)
        return cb_error_set(err, st, "%s", local.msg);
    if (st)
        return problem(r, err, "%s", local.msg);
    if (!(tol > 0))
        tol = b->tol > 0 ? b->tol : 1e-6;
    if ((st = check_edges(r, b, tol, err)) || (st = check_edge_use(r, b, err)) ||
        (st = check_loops(r, b, tol, err)) || (st = check_on_surfaces(r, b, tol, n_samples, err)))
        return st;
    return CB_OK;
}
