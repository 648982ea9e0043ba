/* Tessellation options and the shared edge samples. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/tess.h"
#include "brep/tess_internal.h"

void cb_tess_opts_init(cb_tess_opts *o)
{
    o->chord_tol = 0;
    o->angle_tol = 0;
    o->max_edge = 0;
}

cb_status cb_tess_opts_resolve(cb_tess_opts *out, const cb_tess_opts *o, const cb_topo_body *b,
                               cb_error *err)
{
    cb_tess_opts def;
    cb_tess_opts_init(&def);
    if (!o)
        o = &def;
    if (!isfinite(o->chord_tol))
        return cb_error_set(err, CB_ERR_INVALID, "tessellation: chord_tol %g is not finite",
                            o->chord_tol);
    if (!isfinite(o->angle_tol) || o->angle_tol > 0.5 * 3.14159265358979323846)
        return cb_error_set(err, CB_ERR_INVALID,
                            "tessellation: angle_tol %g outside (0, pi/2] radians", o->angle_tol);
    if (!isfinite(o->max_edge) || o->max_edge < 0)
        return cb_error_set(err, CB_ERR_INVALID,
                            "tessellation: max_edge %g is negative or not finite", o->max_edge);
    *out = *o;
    if (!(out->angle_tol > 0))
        out->angle_tol = CB_TESS_ANGLE;
    if (!(out->chord_tol > 0)) {
        cb_aabb box;
        cb_topo_body_edge_box(&box, b);
        double diag = 0;
        for (int i = 0; i < 3; i++)
            diag += (box.hi[i] - box.lo[i]) * (box.hi[i] - box.lo[i]);
        diag = sqrt(diag);
        if (!(diag > 0) || !isfinite(diag))
            return cb_error_set(err, CB_ERR_INVALID,
                                "tessellation: the body's edge box is empty or infinite, so "
                                "there is no default chord_tol: give one");
        out->chord_tol = CB_TESS_REL_CHORD * diag;
    }
    return CB_OK;
}

void cb_tess_edges_init(cb_tess_edges *es)
{
    memset(es, 0, sizeof *es);
}

void cb_tess_edges_clear(cb_tess_edges *es)
{
    free(es->xyz);
    free(es->start);
    free(es->ids);
    free(es->t);
    cb_tess_edges_init(es);
}

/* Distance from p to the line through a and b (to a when they coincide). */
static double line_distance(const double p[3], const double a[3], const double b[3])
{
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]}, c[3];
    double dd = cb_vec3_dot(d, d);
    if (!(dd > 0))
        return cb_vec3_norm(w);
    cb_vec3_cross(c, d, w);
    return cb_vec3_norm(c) / sqrt(dd);
}

/* A coedge of the edge being sampled: the faces will join consecutive samples by straight
 * segments in (u, v), whose image on the surface must stay near the chord too. */
typedef struct {
    const cb_topo_curve *pc;
    const cb_topo_inverter *inv;
    double t0, t1, s0, s1; /* pcurve parameter s0 at curve parameter t0, s1 at t1 */
} side_curve;

typedef struct {
    const cb_topo_curve *c;
    const cb_tess_opts *o;
    side_curve side[8]; /* of the edge and its twins (parallel_edges) */
    int n_sides;
    const cb_tess_zone *zones; /* of the faces using the edge */
    int n_zones;
} edge_job;

/* Largest distance between the surface image of the (u, v) midpoint of a piece of pcurve and
 * the midpoint of the 3D chord of that piece. (Pcurves need not share the edge's parameter, so
 * the piece is taken by the linear map of the parameter ranges, and its own ends are used.) */
static double side_deviation(const edge_job *j, double ta, double tb, double *min_cos)
{
    double worst = 0;
    *min_cos = 1;
    for (int k = 0; k < j->n_sides; k++) {
        const side_curve *sc = &j->side[k];
        double a[3], b[3], da[6][3], db[6][3], p[3], m[3], f = (sc->s1 - sc->s0) / (sc->t1 - sc->t0);
        cb_topo_pcurve_eval(a, sc->pc, sc->s0 + (ta - sc->t0) * f);
        cb_topo_pcurve_eval(b, sc->pc, sc->s0 + (tb - sc->t0) * f);
        cb_topo_inverter_eval_derivs(da, sc->inv, a[0], a[1]);
        cb_topo_inverter_eval_derivs(db, sc->inv, b[0], b[1]);
        cb_topo_inverter_eval(p, sc->inv, 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]));
        for (int i = 0; i < 3; i++)
            m[i] = 0.5 * (da[0][i] + db[0][i]);
        worst = fmax(worst, cb_vec3_dist(p, m));
        /* The surface normal turning along the piece: the faces' triangles on this side
         * could not follow it, as their boundary corners are these samples. Not at a pole or
         * apex, where one derivative vanishes against the other (to rounding, on a B-spline's
         * collapsed row: its normal there is noise, which halved a cone's seam down to the
         * chord tolerance towards the apex and left slivers there). */
        double na[3], nb[3];
        cb_vec3_cross(na, da[1], da[2]);
        cb_vec3_cross(nb, db[1], db[2]);
        double la = cb_vec3_norm(na), lb = cb_vec3_norm(nb);
        if (la > 1e-9 * (cb_vec3_dot(da[1], da[1]) + cb_vec3_dot(da[2], da[2])) &&
            lb > 1e-9 * (cb_vec3_dot(db[1], db[1]) + cb_vec3_dot(db[2], db[2])))
            *min_cos = fmin(*min_cos, cb_vec3_dot(na, nb) / (la * lb));
    }
    return worst;
}

/* Whether the piece [ta, tb] of the edge's curve must be halved. */
static int too_coarse(const edge_job *j, double ta, double tb)
{
    const cb_topo_curve *c = j->c;
    const cb_tess_opts *o = j->o;
    double da[3][3], db[3][3], p[3];
    cb_topo_curve_eval_derivs(da, c, ta);
    cb_topo_curve_eval_derivs(db, c, tb);
    if (o->max_edge > 0 && cb_vec3_dist(da[0], db[0]) > o->max_edge)
        return 1;
    double tol = o->chord_tol, lambda;
    for (int z = 0; z < j->n_zones; z++)
        if (j->zones[z].chord_tol < tol &&
            cb_seg3_nearest(&lambda, da[0], db[0], j->zones[z].c) <= j->zones[z].r)
            tol = j->zones[z].chord_tol;
    for (int k = 1; k <= 3; k++) {
        cb_topo_curve_eval(p, c, ta + (tb - ta) * k / 4);
        if (line_distance(p, da[0], db[0]) > tol)
            return 1;
    }
    double na = cb_vec3_norm(da[1]), nb = cb_vec3_norm(db[1]);
    if (na > 0 && nb > 0) {
        double cosang = cb_vec3_dot(da[1], db[1]) / (na * nb);
        if (cosang < cos(o->angle_tol))
            return 1;
    }
    double min_cos;
    return side_deviation(j, ta, tb, &min_cos) > tol ||
           (min_cos < cos(o->angle_tol) && cb_vec3_dist(da[0], db[0]) > 2 * o->chord_tol);
}

typedef struct {
    double *t;
    int n, cap;
} tlist;

static int tlist_push(tlist *l, double t)
{
    if (l->n == l->cap) {
        int c = l->cap ? 2 * l->cap : 64;
        double *nt = realloc(l->t, (size_t)c * sizeof(double));
        if (!nt)
            return 0;
        l->t = nt;
        l->cap = c;
    }
    l->t[l->n++] = t;
    return 1;
}

/* Appends the parameters after ta up to tb of the subdivision of [ta, tb], in order. */
static int subdivide(tlist *l, const edge_job *j, double ta, double tb, double min_dt, int depth)
{
    if (depth < 40 && tb - ta > min_dt && too_coarse(j, ta, tb)) {
        double tm = 0.5 * (ta + tb);
        return subdivide(l, j, ta, tm, min_dt, depth + 1) &&
               subdivide(l, j, tm, tb, min_dt, depth + 1);
    }
    return tlist_push(l, tb);
}

int cb_tess_cmp_int3(const void *a, const void *b)
{
    const int *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* Whether c and d are the same curve, number for number (two edges made from one curve: the
 * copies a Boolean gives the two pairs of faces that touch along one cut). */
static int same_curve(const cb_topo_curve *c, const cb_topo_curve *d)
{
    if (c->kind != d->kind)
        return 0;
    if (c->kind != CB_CURVE_NURBS)
        return memcmp(&c->frame, &d->frame, sizeof c->frame) == 0 && c->r1 == d->r1 &&
               c->r2 == d->r2;
    const cb_nurbs_curve_struct *a = c->nurbs, *b = d->nurbs;
    return a->deg == b->deg && a->n == b->n &&
           memcmp(a->knots, b->knots, (size_t)(a->n + a->deg + 1) * sizeof(double)) == 0 &&
           memcmp(a->cw, b->cw, (size_t)a->n * 4 * sizeof(double)) == 0;
}

/* parallel[e] = 1 when another edge joins the same two vertices as edge e (two solids touching
 * along a line, their union's shell touching itself there): sampled with their ends only, the
 * two would make one mesh edge of four triangles. twin[e]: the first edge joining them on the
 * same curve over the same range (e itself when none): where two faces of a body touch
 * along a curve that each pair of faces bounds by its own edge, both edges are sampled
 * alike, so that the meshes of the two pairs meet along the same chords instead of crossing
 * where the chords of one dip by their sagitta beside the other's samples. next[e]: the next
 * later edge with the same twin, -1 after the last. 0 when out of memory. */
static int parallel_edges(char **parallel, int **twin, int **next, const cb_topo_body *b)
{
    int *pairs = malloc((size_t)(b->n_edges + 1) * 3 * sizeof(int));
    char *par = calloc((size_t)b->n_edges + 1, 1);
    int *tw = malloc((size_t)(b->n_edges + 1) * sizeof(int));
    int *nx = malloc((size_t)(b->n_edges + 1) * sizeof(int));
    if (!pairs || !par || !tw || !nx) {
        free(pairs);
        free(par);
        free(tw);
        free(nx);
        return 0;
    }
    for (int e = 0; e < b->n_edges; e++) {
        int a = b->edges[e].v[0], c = b->edges[e].v[1];
        pairs[3 * e] = a < c ? a : c;
        pairs[3 * e + 1] = a < c ? c : a;
        pairs[3 * e + 2] = e;
        tw[e] = e;
        nx[e] = -1;
    }
    /* Sorted by vertex pair, then edge index: a run's first twin is its earliest. */
    qsort(pairs, (size_t)b->n_edges, 3 * sizeof(int), cb_tess_cmp_int3);
    for (int k = 1; k < b->n_edges; k++)
        if (pairs[3 * k] == pairs[3 * k - 3] && pairs[3 * k + 1] == pairs[3 * k - 2])
            par[pairs[3 * k + 2]] = par[pairs[3 * k - 1]] = 1;
    for (int k = 0; k < b->n_edges; k++) {
        const cb_topo_edge *E = &b->edges[pairs[3 * k + 2]];
        for (int i = k - 1; i >= 0 && pairs[3 * i] == pairs[3 * k] &&
                            pairs[3 * i + 1] == pairs[3 * k + 1];
             i--) {
            const cb_topo_edge *F = &b->edges[pairs[3 * i + 2]];
            if (F->t0 == E->t0 && F->t1 == E->t1 &&
                same_curve(&b->curves[F->curve], &b->curves[E->curve]))
                tw[pairs[3 * k + 2]] = tw[pairs[3 * i + 2]];
        }
    }
    /* Each group chained from its first edge in edge order. */
    int *last = pairs; /* reused: the group's last edge so far, by its first */
    for (int e = 0; e < b->n_edges; e++)
        if (tw[e] != e) {
            nx[last[tw[e]]] = e;
            last[tw[e]] = e;
        } else {
            last[e] = e;
        }
    free(pairs);
    *parallel = par;
    *twin = tw;
    *next = nx;
    return 1;
}

cb_status cb_tess_edges_sample(cb_tess_edges *es, const cb_topo_body *b, const cb_tess_opts *o,
                               cb_context *ctx, cb_error *err)
{
    return cb_tess_edges_sample_zoned(es, b, o, NULL, 0, ctx, err);
}

cb_status cb_tess_edges_sample_zoned(cb_tess_edges *es, const cb_topo_body *b,
                                     const cb_tess_opts *o, const cb_tess_zone *zones,
                                     int n_zones, cb_context *ctx, cb_error *err)
{
    cb_tess_edges_clear(es);
    es->n_edges = b->n_edges;
    es->start = malloc((size_t)(b->n_edges + 1) * sizeof(int));
    tlist all = {0};
    cb_topo_inverter *inv = NULL;
    char *parallel = NULL;
    int *twin = NULL, *next = NULL;
    int n_inv = 0;
    cb_status st;
    cb_tess_zone *mine = NULL; /* the zones of the edge being sampled */
    int cap_xyz = b->n_vertices + 16;
    es->xyz = malloc((size_t)cap_xyz * 3 * sizeof(double));
    if (!es->start || !es->xyz)
        goto nomem;
    for (int v = 0; v < b->n_vertices; v++)
        memcpy(es->xyz + 3 * v, b->vertices[v].p, sizeof(double[3]));
    es->n_points = b->n_vertices;
    int cap_ids = 0;
    if (!parallel_edges(&parallel, &twin, &next, b))
        goto nomem;
    inv = calloc((size_t)b->n_faces + 1, sizeof(cb_topo_inverter));
    mine = malloc(((size_t)n_zones + 1) * sizeof *mine);
    if (!inv || !mine)
        goto nomem;
    for (; n_inv < b->n_faces; n_inv++)
        if ((st = cb_topo_inverter_init(&inv[n_inv], &b->surfaces[b->faces[n_inv].surface],
                                        b->tol, err)))
            goto fail;
    for (int e = 0; e < b->n_edges; e++) {
        if (cb_context_cancelled(ctx)) {
            st = cb_error_set(err, CB_ERR_CANCELLED, "tessellation: cancelled");
            goto fail;
        }
        const cb_topo_edge *E = &b->edges[e];
        const cb_topo_curve *c = &b->curves[E->curve];
        es->start[e] = all.n;
        int first = all.n;
        double tol = fmax(E->tol, b->tol);
        if (!tlist_push(&all, E->t0))
            goto nomem;
        if (twin[e] != e) {
            /* Its twin's parameters (an earlier edge, sampled for both). */
            for (int k = es->start[twin[e]] + 1; k < es->start[twin[e] + 1]; k++)
                if (!tlist_push(&all, all.t[k]))
                    goto nomem;
        } else if (cb_topo_edge_length(b, e) <= tol) {
            if (!tlist_push(&all, E->t1))
                goto nomem;
        } else {
            /* The zones and coedges of e and of its twins (next). */
            edge_job j = {c, o, {{0}}, 0, mine, 0};
            for (int z = 0; z < n_zones; z++) {
                int in = 0;
                for (int f = e; f >= 0 && !in; f = next[f])
                    for (int k = b->edge_start[f]; k < b->edge_start[f + 1] && !in; k++)
                        in = b->loops[b->coedges[b->edge_coedges[k]].loop].face == zones[z].face;
                if (in)
                    mine[j.n_zones++] = zones[z];
            }
            for (int f = e; f >= 0; f = next[f])
                for (int k = b->edge_start[f]; k < b->edge_start[f + 1] && j.n_sides < 8; k++) {
                    int co = b->edge_coedges[k];
                    const cb_topo_coedge *C = &b->coedges[co];
                    if (C->pcurve < 0)
                        continue;
                    side_curve *sc = &j.side[j.n_sides++];
                    int fwd = (C->sense != 0) == (b->edges[f].same_sense != 0);
                    sc->pc = &b->pcurves[C->pcurve];
                    sc->inv = &inv[b->loops[C->loop].face];
                    sc->t0 = fwd ? E->t0 : E->t1;
                    sc->t1 = fwd ? E->t1 : E->t0;
                    cb_topo_coedge_pcurve_range(&sc->s0, &sc->s1, b, co, sc->inv,
                                                fmax(b->edges[f].tol, b->tol));
                }
            int pieces = E->v[0] == E->v[1] ? 3 : parallel[e] ? 2 : 1;
            double min_dt = 1e-9 * (E->t1 - E->t0);
            for (int k = 0; k < pieces; k++) {
                double ta = E->t0 + (E->t1 - E->t0) * k / pieces;
                double tb = k + 1 == pieces ? E->t1 : E->t0 + (E->t1 - E->t0) * (k + 1) / pieces;
                if (!subdivide(&all, &j, ta, tb, min_dt, 0))
                    goto nomem;
            }
        }
        int m = all.n - first;
        if (all.n > cap_ids) {
            cap_ids = 2 * all.n;
            int *ni = realloc(es->ids, (size_t)cap_ids * sizeof(int));
            if (!ni)
                goto nomem;
            es->ids = ni;
        }
        if (es->n_points + m > cap_xyz) {
            cap_xyz = 2 * (es->n_points + m);
            double *nx = realloc(es->xyz, (size_t)cap_xyz * 3 * sizeof(double));
            if (!nx)
                goto nomem;
            es->xyz = nx;
        }
        /* The curve runs from v[0] to v[1] when same_sense, else from v[1] to v[0]. */
        es->ids[first] = E->same_sense ? E->v[0] : E->v[1];
        es->ids[first + m - 1] = E->same_sense ? E->v[1] : E->v[0];
        for (int k = 1; k + 1 < m; k++) {
            cb_topo_curve_eval(es->xyz + 3 * es->n_points, c, all.t[first + k]);
            es->ids[first + k] = es->n_points++;
        }
        cb_context_progress(ctx, e + 1, 20.0 * (b->n_edges + 1), "tessellate");
    }
    es->start[b->n_edges] = all.n;
    es->t = all.t;
    all.t = NULL;
    st = CB_OK;
    goto done;
nomem:
    st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory sampling edges");
fail:
    cb_tess_edges_clear(es);
done:
    free(mine);
    free(parallel);
    free(twin);
    free(next);
    free(all.t);
    for (int f = 0; f < n_inv; f++)
        cb_topo_inverter_clear(&inv[f]);
    free(inv);
    return st;
}
