/* Validation of a body: shell closure and edge use, loop closure, edge ends at vertices,
 * degenerate loops and faces (no length, no area), edges on their faces' surfaces, pcurves on
 * their edges and loops closed in (u, v), outward orientation of closed shells. */
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

/* Loops closed topologically and in 3D; faces bounded and not degenerate. */
static cb_status check_loops(cb_topo_report *r, const cb_topo_body *b, double tol, char *bad,
                             cb_error *err)
{
    cb_status st = CB_OK;
    for (int f = 0; f < b->n_faces && !st; f++) {
        int before = r->n + r->dropped;
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
                len += cb_topo_edge_length(b, c->edge);
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
        bad[f] = r->n + r->dropped > before;
    }
    return st;
}

/* Samples of every edge against the surfaces of the faces using it: the smaller of the
 * projector's distance and the point inversion's (cb_topo_inverter), both distances to a
 * point of the surface. The inversion follows a closed B-spline surface's parameter across
 * its seam, where the projector's search, clamped to the domain, stalls (0.27 off for an edge
 * on a B-spline torus' seam); the projector's closed forms round less far from the origin
 * (a plane at 1e12: 1.7e-4 against 4.8e-4). */
static cb_status check_on_surfaces(cb_topo_report *r, const cb_topo_body *b, double tol,
                                   int n_samples, cb_error *err)
{
    cb_topo_inverter *inv = calloc((size_t)b->n_surfaces + 1, sizeof *inv);
    char *ready = calloc((size_t)b->n_surfaces + 1, 1);
    cb_status st = CB_OK;
    if (!inv || !ready)
        st = cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
    if (n_samples < 2)
        n_samples = 2;
    for (int f = 0; f < b->n_faces && !st; f++) {
        const cb_topo_face *fc = &b->faces[f];
        int s = fc->surface;
        if (!ready[s]) {
            if ((st = cb_topo_inverter_init(&inv[s], &b->surfaces[s], b->tol, err)))
                break;
            ready[s] = 1;
        }
        for (int l = fc->first; l < fc->first + fc->count && !st; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count && !st; c++) {
                int e = b->coedges[c].edge;
                const cb_topo_edge *ed = &b->edges[e];
                double worst = 0;
                for (int k = 0; k < n_samples; k++) {
                    double p[3], uv[2];
                    cb_topo_curve_eval(p, &b->curves[ed->curve],
                                       ed->t0 + (ed->t1 - ed->t0) * k / (n_samples - 1));
                    worst = fmax(worst, fmin(cb_topo_projector_distance(&inv[s].pr, p),
                                             cb_topo_inverter_invert(uv, &inv[s], p, NULL)));
                }
                r->max_edge_surface = fmax(r->max_edge_surface, worst);
                if (worst > edge_tol(b, e, tol))
                    st = problem(r, err, "edge %d: %.3g off the %s surface of face %d", e, worst,
                                 cb_topo_surface_type_name(&b->surfaces[s]), f);
            }
    }
    for (int s = 0; inv && ready && s < b->n_surfaces; s++)
        if (ready[s])
            cb_topo_inverter_clear(&inv[s]);
    free(inv);
    free(ready);
    return st;
}

/* Pcurve of coedge c against its edge over the part it uses (range written to s), in 3D:
 * parameter by parameter for pcurves of the edge's parameterisation, else the distance to the
 * edge curve. */
double cb_topo_coedge_pcurve_error(double range[2], const cb_topo_body *b, int c,
                                   const cb_topo_inverter *inv, double tol, int n_samples)
{
    const cb_topo_coedge *co = &b->coedges[c];
    const cb_topo_edge *ed = &b->edges[co->edge];
    const cb_topo_curve *pc = &b->pcurves[co->pcurve], *cv = &b->curves[ed->curve];
    double etol = edge_tol(b, co->edge, tol);
    double worst = cb_topo_coedge_pcurve_range(&range[0], &range[1], b, c, inv, etol);
    if (worst > etol)
        return worst;
    if (n_samples < 2)
        n_samples = 2;
    int forward = co->sense == ed->same_sense;
    for (int k = 0; k < n_samples; k++) {
        double x = (double)k / (n_samples - 1), w[3], p[3], q[3];
        cb_topo_pcurve_eval(w, pc, range[0] + (range[1] - range[0]) * x);
        cb_topo_inverter_eval(p, inv, w[0], w[1]);
        cb_topo_curve_eval(q, cv, forward ? ed->t0 + (ed->t1 - ed->t0) * x
                                          : ed->t1 - (ed->t1 - ed->t0) * x);
        double d = cb_vec3_dist(p, q);
        /* The parameterisations may differ (a file's pcurve need not share the edge's
         * parameter): what counts is the distance to the edge itself. */
        if (d > etol)
            d = fmin(d, cb_topo_edge_distance(b, co->edge, p));
        worst = fmax(worst, d);
    }
    return worst;
}

static cb_status check_pcurve(cb_topo_report *r, const cb_topo_body *b, int c,
                              const cb_topo_inverter *inv, double tol, int n_samples,
                              double s[2], cb_error *err)
{
    const cb_topo_coedge *co = &b->coedges[c];
    double etol = edge_tol(b, co->edge, tol);
    double gap = cb_topo_coedge_pcurve_range(&s[0], &s[1], b, c, inv, etol);
    int f = b->loops[co->loop].face;
    if (gap > etol)
        return problem(r, err, "coedge %d: pcurve ends %.3g from its edge's ends on face %d", c,
                       gap, f);
    double worst = cb_topo_coedge_pcurve_error(s, b, c, inv, tol, n_samples);
    if (worst > etol)
        return problem(r, err, "coedge %d: pcurve %.3g off its edge %d on face %d", c, worst,
                       co->edge, f);
    return CB_OK;
}

/* ---------------------------------------------------------------- face area ---------------- */

/* A face whose loops close and have length can still enclose nothing: its loop folded back on
 * itself along a line (a triangle of three collinear points). Tessellation then fails on it, so
 * validation measures the area the loops enclose: the integral of |S_u x S_v| over the face's
 * domain in (u, v), by the columns cb_topo_shell_volume integrates its flux over (brep/topo.h;
 * the polygons and the columns are built as in brep/topo_orient.c). A sphere bounded by its
 * seam and poles, a cone by a circle and its apex, enclose area there like any other face. */

enum {
    AREA_SAMPLES = 16, /* polygon points per curved pcurve */
    AREA_COLUMNS = 32
};

/* The loops of one face sampled in (u, v): loop l is pts[start[l] .. start[l + 1]) and closes
 * from its last point to its first moved by wrap[l] periods. */
typedef struct {
    double *pts;
    int n, cap;
    int *start, (*wrap)[2];
    int n_loops;
} uv_polygons;

static void uv_polygons_clear(uv_polygons *pg)
{
    free(pg->pts);
    free(pg->start);
    free(pg->wrap);
    memset(pg, 0, sizeof *pg);
}

static cb_status uv_push(uv_polygons *pg, const double w[3], const int k[2],
                         const cb_topo_inverter *inv, cb_error *err)
{
    if (pg->n == pg->cap) {
        int c = pg->cap ? 2 * pg->cap : 64;
        double *p = realloc(pg->pts, (size_t)c * 2 * sizeof *p);
        if (!p)
            return cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
        pg->pts = p;
        pg->cap = c;
    }
    pg->pts[2 * pg->n] = w[0] + k[0] * inv->lift[0];
    pg->pts[2 * pg->n + 1] = w[1] + k[1] * inv->lift[1];
    pg->n++;
    return CB_OK;
}

/* Whole periods k[i] that move b nearest a; none when a -> b already closes on the surface (the
 * same point, or a pole line). */
static void lift_between(int k[2], const cb_topo_inverter *inv, const double a[2],
                         const double b[2], double tol)
{
    k[0] = k[1] = 0;
    if (cb_topo_inverter_spread(inv, a, b) <= tol)
        return;
    for (int i = 0; i < 2; i++)
        if (inv->lift[i] > 0)
            k[i] = (int)round((a[i] - b[i]) / inv->lift[i]);
}

/* The pcurves of face f's loops over the parts their coedges use (range, from the pcurve
 * check), each lifted to continue the previous one. */
static cb_status face_uv_polygons(uv_polygons *pg, const cb_topo_body *b, int f,
                                  const cb_topo_inverter *inv, const double (*range)[2],
                                  double tol, cb_error *err)
{
    const cb_topo_face *fc = &b->faces[f];
    pg->start = malloc(((size_t)fc->count + 1) * sizeof *pg->start);
    pg->wrap = malloc(((size_t)fc->count + 1) * sizeof *pg->wrap);
    if (!pg->start || !pg->wrap)
        return cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
    cb_status st = CB_OK;
    for (int l = fc->first; l < fc->first + fc->count && !st; l++) {
        const cb_topo_loop *lp = &b->loops[l];
        int first = pg->n;
        double prev[2] = {0, 0};
        pg->start[pg->n_loops] = first;
        for (int c = lp->first; c < lp->first + lp->count && !st; c++) {
            const cb_topo_curve *pc = &b->pcurves[b->coedges[c].pcurve];
            double s0 = range[c][0], s1 = range[c][1], w[3];
            int m = pc->kind == CB_CURVE_LINE ? 1 : AREA_SAMPLES, k[2] = {0, 0};
            cb_topo_pcurve_eval(w, pc, s0);
            if (c > lp->first)
                lift_between(k, inv, prev, w, tol);
            for (int j = 0; j < m && !st; j++) {
                cb_topo_pcurve_eval(w, pc, s0 + (s1 - s0) * j / m);
                st = uv_push(pg, w, k, inv, err);
            }
            /* The end too: the next pcurve may start elsewhere on a pole line. */
            cb_topo_pcurve_eval(w, pc, s1);
            if (!st)
                st = uv_push(pg, w, k, inv, err);
            prev[0] = pg->pts[2 * (pg->n - 1)];
            prev[1] = pg->pts[2 * (pg->n - 1) + 1];
        }
        if (st)
            break;
        lift_between(pg->wrap[pg->n_loops], inv, pg->pts + 2 * (pg->n - 1), pg->pts + 2 * first,
                     tol);
        pg->n_loops++;
    }
    pg->start[pg->n_loops] = pg->n;
    return st;
}

static void uv_point(double p[2], const uv_polygons *pg, const cb_topo_inverter *inv, int l, int k)
{
    if (k < pg->start[l + 1]) {
        p[0] = pg->pts[2 * k];
        p[1] = pg->pts[2 * k + 1];
        return;
    }
    int f = pg->start[l];
    p[0] = pg->pts[2 * f] + pg->wrap[l][0] * inv->lift[0];
    p[1] = pg->pts[2 * f + 1] + pg->wrap[l][1] * inv->lift[1];
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* The area of face f, integrated column by column until it exceeds enough (*area is then the
 * part summed so far). *measured is 0 where the columns cannot bound the face: loops around
 * both periods of a doubly periodic surface, or a column crossed an odd number of times with no
 * pole to close it at. Columns are visited from the middle out of order, so a face of any
 * real area stops after one or two. */
static cb_status face_area(double *area, int *measured, const cb_topo_body *b, int f,
                           const cb_topo_inverter *inv, const double (*range)[2], double tol,
                           double enough, cb_error *err)
{
    uv_polygons pg;
    memset(&pg, 0, sizeof pg);
    double *cut = NULL;
    *area = 0;
    *measured = 0;
    cb_status st = face_uv_polygons(&pg, b, f, inv, range, tol, err);
    if (st || pg.n < 2)
        goto done;
    int wraps[2] = {0, 0}, any[2] = {0, 0};
    for (int l = 0; l < pg.n_loops; l++)
        for (int i = 0; i < 2; i++) {
            wraps[i] += pg.wrap[l][i];
            any[i] |= pg.wrap[l][i] != 0;
        }
    if (any[0] && any[1])
        goto done;
    /* Columns across a, intervals along bb. */
    int a = any[1] ? 1 : 0, bb = 1 - a;
    double Pa = inv->period[a], Pb = inv->period[bb];
    if (Pb > 0)
        for (int l = 1; l < pg.n_loops; l++) {
            double sh = Pb * round((pg.pts[2 * pg.start[0] + bb] - pg.pts[2 * pg.start[l] + bb]) /
                                   Pb);
            for (int k = pg.start[l]; k < pg.start[l + 1]; k++)
                pg.pts[2 * k + bb] += sh;
        }
    double lo_a = HUGE_VAL, hi_a = -HUGE_VAL, lo_b = HUGE_VAL, hi_b = -HUGE_VAL;
    for (int k = 0; k < pg.n; k++) {
        lo_a = fmin(lo_a, pg.pts[2 * k + a]);
        hi_a = fmax(hi_a, pg.pts[2 * k + a]);
        lo_b = fmin(lo_b, pg.pts[2 * k + bb]);
        hi_b = fmax(hi_b, pg.pts[2 * k + bb]);
    }
    if (Pa > 0)
        hi_a = fmin(hi_a, lo_a + Pa);
    /* A column crossed an odd number of times is closed at the pole the loops keep to their
     * left (left of +a: +b for a = u, -b for a = v). */
    int up = (wraps[a] > 0) == (b->faces[f].same_sense != 0);
    if (a == 1)
        up = !up;
    double edge_b = up ? inv->box[2 * bb + 1] : inv->box[2 * bb];
    int cap = 16;
    if (!(cut = malloc((size_t)cap * sizeof *cut))) {
        st = cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
        goto done;
    }
    static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834},
                        gw[3] = {0.5555555555555556, 0.8888888888888888, 0.5555555555555556};
    double width = (hi_a - lo_a) / AREA_COLUMNS, piece = (hi_b - lo_b) / 8;
    *measured = 1;
    /* 13 is prime to AREA_COLUMNS: every column once, the middle one first. */
    for (int it = 0; it < AREA_COLUMNS && width > 0 && *area <= enough; it++) {
        int col = (AREA_COLUMNS / 2 + 13 * it) % AREA_COLUMNS;
        double x = lo_a + (col + 0.5) * width;
        int m = 0;
        for (int l = 0; l < pg.n_loops && !st; l++)
            for (int k = pg.start[l]; k < pg.start[l + 1] && !st; k++) {
                double p[2], q[2];
                uv_point(p, &pg, inv, l, k);
                uv_point(q, &pg, inv, l, k + 1);
                int k0 = 0, k1 = 0;
                if (Pa > 0) {
                    k0 = (int)floor((fmin(p[a], q[a]) - x) / Pa);
                    k1 = (int)ceil((fmax(p[a], q[a]) - x) / Pa);
                }
                for (int j = k0; j <= k1; j++) {
                    double X = x + j * Pa;
                    if ((p[a] <= X) == (q[a] <= X))
                        continue;
                    if (m + 1 >= cap) { /* room for a pole bound too */
                        double *nc = realloc(cut, (size_t)(2 * cap) * sizeof *nc);
                        if (!nc) {
                            st = cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
                            break;
                        }
                        cut = nc;
                        cap *= 2;
                    }
                    cut[m++] = p[bb] + (X - p[a]) / (q[a] - p[a]) * (q[bb] - p[bb]);
                }
            }
        if (st)
            break;
        if (m == 0)
            continue;
        qsort(cut, (size_t)m, sizeof *cut, cmp_double);
        int k = 0;
        double from = 0;
        if (m % 2) {
            if (!isfinite(edge_b)) {
                *measured = 0;
                break;
            }
            if (up) {
                cut[m++] = edge_b;
            } else {
                from = edge_b;
                k = -1;
            }
        }
        for (; k + 1 < m; k += 2) {
            double lo = k < 0 ? from : cut[k], hi = cut[k + 1];
            int np = piece > 0 ? (int)ceil((hi - lo) / piece) : 1;
            if (np < 1)
                np = 1;
            double h = (hi - lo) / np;
            for (int i = 0; i < np; i++)
                for (int g = 0; g < 3; g++) {
                    double y = lo + h * (i + 0.5 + 0.5 * gx[g]), uv[2], d[6][3], n[3];
                    uv[a] = x;
                    uv[bb] = y;
                    cb_topo_inverter_eval_derivs(d, inv, uv[0], uv[1]);
                    cb_vec3_cross(n, d[1], d[2]);
                    *area += width * 0.5 * h * gw[g] * cb_vec3_norm(n);
                }
        }
    }
done:
    free(cut);
    uv_polygons_clear(&pg);
    return st;
}

/* Face f (its coedges all with pcurves, range their parts) is degenerate when the area it
 * encloses is at most tol times the length of its loops: its mean width, 2 area / length, is
 * at most 2 tol, which the tolerance cannot tell from a line. (Against tol^2 alone, a loop
 * folded onto a curve would pass on the rounding of the file's coordinates.) */
static cb_status check_face_area(cb_topo_report *r, const cb_topo_body *b, int f,
                                 const cb_topo_inverter *inv, const double (*range)[2],
                                 double tol, cb_error *err)
{
    const cb_topo_face *fc = &b->faces[f];
    double len = 0, area;
    for (int l = fc->first; l < fc->first + fc->count; l++)
        for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++)
            len += cb_topo_edge_length(b, b->coedges[c].edge);
    int measured;
    cb_status st = face_area(&area, &measured, b, f, inv, range, tol, tol * len, err);
    if (st || !measured || area > tol * len)
        return st;
    return problem(r, err,
                   "face %d: degenerate, its loops span no area (area %.3g, loops of length %.3g)",
                   f, area, len);
}

/* Pcurves on their edges; loops whose coedges all have pcurves closed in (u, v); faces
 * whose coedges all have pcurves, and whose loops were found sound, enclose area. */
static cb_status check_pcurves(cb_topo_report *r, const cb_topo_body *b, double tol,
                               int n_samples, const char *bad, cb_error *err)
{
    cb_status st = CB_OK;
    double(*range)[2] = malloc(((size_t)b->n_coedges + 1) * sizeof *range);
    if (!range)
        return cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
    if (n_samples < 2)
        n_samples = 2;
    for (int f = 0; f < b->n_faces && !st; f++) {
        const cb_topo_face *fc = &b->faces[f];
        int with = 0, without = 0, before = r->n + r->dropped;
        for (int l = fc->first; l < fc->first + fc->count; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
                with += b->coedges[c].pcurve >= 0;
                without += b->coedges[c].pcurve < 0;
            }
        if (!with)
            continue;
        cb_topo_inverter inv;
        if ((st = cb_topo_inverter_init(&inv, &b->surfaces[fc->surface], tol, err)))
            break;
        for (int l = fc->first; l < fc->first + fc->count && !st; l++) {
            const cb_topo_loop *lp = &b->loops[l];
            int all = 1, bad = r->n;
            for (int c = lp->first; c < lp->first + lp->count && !st; c++) {
                if (b->coedges[c].pcurve < 0)
                    all = 0;
                else
                    st = check_pcurve(r, b, c, &inv, tol, n_samples, range[c], err);
            }
            if (st || !all || r->n > bad)
                continue;
            for (int k = 0; k < lp->count && !st; k++) {
                int c = lp->first + k, n = lp->first + (k + 1) % lp->count;
                double a[3], z[3];
                cb_topo_pcurve_eval(a, &b->pcurves[b->coedges[c].pcurve], range[c][1]);
                cb_topo_pcurve_eval(z, &b->pcurves[b->coedges[n].pcurve], range[n][0]);
                double moved[2] = {z[0], z[1]};
                for (int i = 0; i < 2; i++)
                    if (inv.lift[i] > 0)
                        moved[i] += inv.lift[i] * round((a[i] - z[i]) / inv.lift[i]);
                double tl = fmax(edge_tol(b, b->coedges[c].edge, tol),
                                 edge_tol(b, b->coedges[n].edge, tol));
                if (cb_topo_inverter_spread(&inv, a, z) > tl &&
                    cb_topo_inverter_spread(&inv, a, moved) > tl)
                    st = problem(r, err,
                                 "face %d: loop %d open in (u, v) after coedge %d: (%.6g, %.6g) "
                                 "to (%.6g, %.6g)",
                                 f, l, c, a[0], a[1], z[0], z[1]);
            }
        }
        if (!st && !without && !bad[f] && r->n + r->dropped == before)
            st = check_face_area(r, b, f, &inv, (const double(*)[2])range, tol, err);
        cb_topo_inverter_clear(&inv);
    }
    free(range);
    return st;
}

/* Closed shells with pcurves throughout: outward, by the sign of their enclosed volume. */
static cb_status check_orientation(cb_topo_report *r, const cb_topo_body *b, double tol,
                                   cb_error *err)
{
    cb_status st = CB_OK;
    for (int k = 0; k < b->n_shells && !st; k++) {
        const cb_topo_shell *sh = &b->shells[k];
        int all = sh->closed;
        for (int f = sh->first; f < sh->first + sh->count && all; f++)
            for (int l = b->faces[f].first; l < b->faces[f].first + b->faces[f].count; l++)
                for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++)
                    all &= b->coedges[c].pcurve >= 0;
        if (!all)
            continue;
        double vol;
        cb_error local;
        cb_status vs = cb_topo_shell_volume(&vol, b, k, 64, tol, &local);
        if (vs == CB_ERR_NOMEM)
            return cb_error_set(err, vs, "%s", local.msg);
        /* A void's faces face into its cavity, away from the material: its own signed volume
         * is negative. */
        int void_shell = sh->solid >= 0 && b->solids[sh->solid].first != k;
        if (vs)
            st = problem(r, err, "shell %d: orientation not decided: %s", k, local.msg);
        else if (!void_shell && vol < 0)
            st = problem(r, err, "shell %d: inward oriented (signed volume %.3g)", k, vol);
        else if (void_shell && vol > 0)
            st = problem(r, err, "shell %d: void facing out of its cavity (signed volume %.3g)",
                         k, vol);
    }
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
    /* Faces whose loops are reported already (open, degenerate) are not measured for area. */
    char *bad = calloc((size_t)b->n_faces + 1, 1);
    if (!bad)
        return cb_error_set(err, CB_ERR_NOMEM, "validation: out of memory");
    if (!(st = check_edges(r, b, tol, err)) && !(st = check_edge_use(r, b, err)) &&
        !(st = check_loops(r, b, tol, bad, err)) &&
        !(st = check_on_surfaces(r, b, tol, n_samples, err)) &&
        !(st = check_pcurves(r, b, tol, n_samples, bad, err)))
        st = check_orientation(r, b, tol, err);
    free(bad);
    return st;
}
