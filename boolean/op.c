/* op.c — union, intersection and difference of two closed B-reps (cb_bool_run): intersection,
 * cuts, faces split in their parameter domains, pieces classified and selected, result sewn. */
#define _POSIX_C_SOURCE 200809L
#include "boolean/op_internal.h"

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "boolean/arrange.h"
#include "boolean/cut_internal.h"
#include "brep/geom.h"
#include "brep/parallel.h"

const char *cb_bool_op_name(cb_bool_op op)
{
    switch (op) {
    case CB_BOOL_UNION:
        return "union";
    case CB_BOOL_INTERSECTION:
        return "intersection";
    case CB_BOOL_DIFFERENCE:
        return "difference";
    }
    return "?";
}

void cb_bool_opts_init(cb_bool_opts *o)
{
    memset(o, 0, sizeof *o);
}

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void _cb_bool_face_clear(op_face *f)
{
    for (int k = 0; k < f->n_srcs; k++)
        if (f->srcs[k].kind != OP_CUT)
            free(f->srcs[k].uv);
    free(f->srcs);
    for (int r = 0; r < f->n_regions; r++) {
        free(f->regions[r].loop_start);
        free(f->regions[r].pieces);
    }
    free(f->regions);
    memset(f, 0, sizeof *f);
}

static int push_src(op_face *of, int *cap, const op_src *s)
{
    if (of->n_srcs == *cap) {
        int c = *cap ? 2 * *cap : 16;
        op_src *q = realloc(of->srcs, (size_t)c * sizeof *q);
        if (!q)
            return -1;
        of->srcs = q;
        *cap = c;
    }
    of->srcs[of->n_srcs++] = *s;
    return 0;
}

/* The cuts a face is split along, in its (u, v) window (side: the face's side of the cuts),
 * with their boxes there. */
typedef struct {
    const cb_bool_cuts *cuts;
    const int *k; /* cut indices */
    int n;
    const double (*box)[4]; /* per listed cut: u0, u1, v0, v1 */
    int side;
} face_cuts;

/* Whether a point of one of the cuts lies within reach (in the scaled plane) of the chord of
 * segment g. */
static int cut_near(const cb_face_seg *g, const face_cuts *fc, const double scale[2],
                    double reach)
{
    double lo[2], hi[2];
    for (int d = 0; d < 2; d++) {
        lo[d] = fmin(g->p[d], g->q[d]) - reach / scale[d];
        hi[d] = fmax(g->p[d], g->q[d]) + reach / scale[d];
    }
    double ab[2] = {(g->q[0] - g->p[0]) * scale[0], (g->q[1] - g->p[1]) * scale[1]};
    double L2 = ab[0] * ab[0] + ab[1] * ab[1];
    for (int j = 0; j < fc->n; j++) {
        const double *bx = fc->box[j];
        if (bx[0] > hi[0] || bx[1] < lo[0] || bx[2] > hi[1] || bx[3] < lo[1])
            continue;
        const cb_bool_cut *c = fc->cuts->cut + fc->k[j];
        const double *uv = c->uv[fc->side];
        for (int i = 0; i < c->n; i++) {
            const double *x = uv + 2 * i;
            if (x[0] < lo[0] || x[0] > hi[0] || x[1] < lo[1] || x[1] > hi[1])
                continue;
            double ap[2] = {(x[0] - g->p[0]) * scale[0], (x[1] - g->p[1]) * scale[1]};
            double t = L2 > 0 ? fmin(1, fmax(0, (ab[0] * ap[0] + ab[1] * ap[1]) / L2)) : 0;
            if (hypot(ap[0] - t * ab[0], ap[1] - t * ab[1]) <= reach)
                return 1;
        }
    }
    return 0;
}

/* Into how many pieces segment g of the loop polygon is cut (see boundary_srcs). */
static int seg_pieces(const cb_face_seg *g, const face_cuts *fc, const double scale[2],
                      double dev_max, double snap)
{
    double dev = g->dev * fmax(scale[0], scale[1]); /* bounds it in the scaled plane */
    if (g->coedge < 0 || dev <= dev_max || !cut_near(g, fc, scale, dev + snap))
        return 1;
    return (int)fmin(4096, ceil(sqrt(dev / dev_max)));
}

/* The face's loop polygon (cb_face segments) as sources: one polyline per stretch of a coedge,
 * and one per join. Where a point of a cut may lie within snap of a segment's pcurve (within
 * its deviation bound plus snap of its chord, in the arrangement's scaled plane: a cut ending
 * on the loop, or running or touching along it), the segment is refined on the pcurve until
 * it lies within dev_max of it there (its deviation, a (u, v) distance, bounded by its
 * product with the larger scale), so that the arrangement joins the cut to the loop where
 * the exact loop passes, and only there. Elsewhere no polyline comes near the segment and the
 * polygon is left as it is: refining it would only bring the loop's own tangent corners
 * (two edges meeting at a zero angle) within snap of each other over a longer stretch. */
static cb_status boundary_srcs(op_face *of, int *cap, const cb_face *F, const face_cuts *fc,
                               const double scale[2], double dev_max, double snap,
                               cb_error *err)
{
    const cb_topo_body *b = F->b;
    int k = 0;
    while (k < F->n_segs) {
        const cb_face_seg *sg = F->segs + k;
        int end = k + 1;
        if (sg->coedge >= 0)
            while (end < F->n_segs && F->segs[end].coedge == sg->coedge &&
                   F->segs[end].p[0] == F->segs[end - 1].q[0] &&
                   F->segs[end].p[1] == F->segs[end - 1].q[1])
                end++;
        int n = 1;
        for (int j = k; j < end; j++)
            n += seg_pieces(F->segs + j, fc, scale, dev_max, snap);
        op_src s = {sg->coedge >= 0 ? OP_BOUNDARY : OP_JOIN, sg->coedge, 0,
                    malloc((size_t)n * 2 * sizeof(double))};
        if (!s.uv)
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        s.uv[0] = sg->p[0];
        s.uv[1] = sg->p[1];
        s.n = 1;
        for (int j = k; j < end; j++) {
            const cb_face_seg *g = F->segs + j;
            int m = seg_pieces(g, fc, scale, dev_max, snap);
            for (int i = 1; i < m; i++) {
                double q[3];
                cb_topo_pcurve_eval(q, b->pcurves + b->coedges[g->coedge].pcurve,
                                    g->s0 + (g->s1 - g->s0) * i / m);
                s.uv[2 * s.n] = q[0] + g->shift[0];
                s.uv[2 * s.n + 1] = q[1] + g->shift[1];
                s.n++;
            }
            s.uv[2 * s.n] = g->q[0];
            s.uv[2 * s.n + 1] = g->q[1];
            s.n++;
        }
        if (push_src(of, cap, &s)) {
            free(s.uv);
            return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
        }
        k = end;
    }
    return CB_OK;
}

/* Metric scale of the face's parameters: the largest |S_u|, |S_v| over a 5 x 5 grid of its
 * (u, v) box, so that a scaled (u, v) distance is never shorter than the 3D one. */
static void uv_scale(double scale[2], const cb_face *F)
{
    scale[0] = scale[1] = 0;
    for (int i = 0; i <= 4; i++)
        for (int j = 0; j <= 4; j++) {
            double d[6][3];
            double u = F->uv_box[0] + (F->uv_box[1] - F->uv_box[0]) * i / 4;
            double v = F->uv_box[2] + (F->uv_box[3] - F->uv_box[2]) * j / 4;
            cb_topo_inverter_eval_derivs(d, &F->inv, u, v);
            for (int k = 0; k < 2; k++)
                scale[k] = fmax(scale[k], sqrt(d[1 + k][0] * d[1 + k][0] +
                                               d[1 + k][1] * d[1 + k][1] +
                                               d[1 + k][2] * d[1 + k][2]));
        }
    for (int k = 0; k < 2; k++)
        if (!(scale[k] > 0))
            scale[k] = 1;
}

/* Cosine between the normals of two faces above which they count as coincident. */
#define COINCIDENT_COS 0.9

/* A piece lying on the other solid's boundary (coincident faces), its outward normal the same
 * as the other face's (same = 1) or opposite: one copy of the shared face is kept, A's, where
 * the result's boundary runs there — in union and intersection when the solids lie on the same
 * side, in A - B when they lie on opposite sides (then B is outside A there). */
static int keep_on_piece(cb_bool_op op, int side, int same)
{
    if (side != 0)
        return 0;
    return op == CB_BOOL_DIFFERENCE ? !same : same;
}

static int keep_piece(cb_bool_op op, int side, cb_bool_where w, int *flip)
{
    *flip = 0;
    switch (op) {
    case CB_BOOL_UNION:
        return w == CB_BOOL_OUT;
    case CB_BOOL_INTERSECTION:
        return w == CB_BOOL_IN;
    case CB_BOOL_DIFFERENCE:
        *flip = side == 1;
        return side == 0 ? w == CB_BOOL_OUT : w == CB_BOOL_IN;
    }
    return 0;
}

/* Whether both ends of segment i of cut c lie within near of one imprint (a cut with no
 * curve) on c's face of side `side`; *last: the imprint found for the previous segment, tried
 * first. */
static int seg_along_imprint(const cb_bool_cuts *cuts, const cb_bool_cut *c, int i, int side,
                             double near, int *last)
{
    for (int m = -1; m < cuts->n; m++) {
        int j = m < 0 ? *last : m;
        if (j < 0 || (m >= 0 && j == *last))
            continue;
        const cb_bool_cut *d = cuts->cut + j;
        if (d->curve >= 0 || d->face[side] != c->face[side])
            continue;
        double pos;
        if (cb_bool_cut_project(&pos, d, c->xyz + 3 * i, 0, d->n - 1) <= near &&
            cb_bool_cut_project(&pos, d, c->xyz + 3 * (i + 1), 0, d->n - 1) <= near) {
            *last = j;
            return 1;
        }
    }
    return 0;
}

/* Whether cut k says nothing new to face F (on side `side`): it runs along the face's
 * boundary (_cb_cut_along_boundary), or it is an intersection curve running along coincident faces'
 * imprints on F (both ends of every segment within that of one imprint's polyline: the imprint of
 * one edge may come as several cuts, split where the edge leaves the coincident face or at its
 * window's end, and the curve may run along several edges), which are sampled finer. Added anyway,
 * it would cross the line it runs along at every other sample, splitting the face's edge where its
 * neighbours do not (slivers as wide as the curve's chord error). */
static int redundant_cut(const cb_bool_cuts *cuts, int k, int side, const cb_face *F, double tol)
{
    const cb_bool_cut *c = cuts->cut + k;
    double near = CB_BOOL_SNAP * tol;
    if (_cb_cut_along_boundary(c, side, F, tol))
        return 1;
    if (c->curve < 0)
        return 0;
    int last = -1;
    for (int i = 0; i + 1 < c->n; i++)
        if (!seg_along_imprint(cuts, c, i, side, near, &last))
            return 0;
    return 1;
}

typedef struct {
    cb_bool_op op;
    const cb_bool_solid *solid[2];
    const cb_bool_cuts *cuts;
    double snap, tol;
} split_ctx;

/* The cycles of region r as loops of pieces: each arrangement piece on the source a face's
 * coedge gives where it has one (a cut running along the boundary is the boundary there),
 * positions along that source; reverse: every loop run backwards. */
static cb_status region_loops(op_region *reg, const cb_arr *arr, int r, const op_src *srcs,
                              int reverse, cb_error *err)
{
    const cb_arr_region *R = arr->region + r;
    int n_use = R->cycle[R->n_cycles] - R->cycle[0];
    reg->n_loops = R->n_cycles;
    reg->loop_start = malloc((size_t)(R->n_cycles + 1) * sizeof(int));
    reg->pieces = malloc((size_t)(n_use > 0 ? n_use : 1) * sizeof(op_piece));
    if (!reg->loop_start || !reg->pieces)
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    int m = 0;
    for (int k = 0; k < R->n_cycles; k++) {
        reg->loop_start[k] = m;
        int a = R->cycle[k], z = R->cycle[k + 1];
        for (int j = 0; j < z - a; j++) {
            const cb_arr_use *u = R->use + (reverse ? z - 1 - j : a + j);
            const cb_arr_piece *pc = arr->piece + u->piece;
            int pick = 0;
            for (int q = 0; q < pc->n_src; q++)
                if (srcs[pc->src[q]].kind == OP_BOUNDARY) {
                    pick = q;
                    break;
                }
            double start = u->dir > 0 ? pc->pos0[pick] : pc->pos1[pick];
            double end = u->dir > 0 ? pc->pos1[pick] : pc->pos0[pick];
            if (reverse) {
                double t = start;
                start = end;
                end = t;
            }
            op_piece *op = reg->pieces + m++;
            op->src = pc->src[pick];
            op->pos0 = fmin(start, end);
            op->pos1 = fmax(start, end);
            op->fwd = start < end;
        }
    }
    reg->loop_start[R->n_cycles] = m;
    return CB_OK;
}

/* Splits face `face` of side `side` along its cuts, classifies each region and keeps those the
 * operation selects, in of. */
static cb_status split_face(op_face *of, const split_ctx *sc, int side, int face,
                            cb_bool_stats *stats, cb_error *err)
{
    const cb_face *F = cb_bool_solid_face(sc->solid[side], face);
    of->side = side;
    of->face = face;
    int cap = 0;
    double scale[2];
    uv_scale(scale, F);
    /* The cuts it is split along (the loops go first, so that cuts ending on them are moved
     * onto them: cb_arr_build). */
    int *ks = malloc((size_t)(sc->cuts->n + 1) * sizeof *ks), nk = 0;
    double(*kbox)[4] = malloc((size_t)(sc->cuts->n + 1) * sizeof *kbox);
    if (!ks || !kbox) {
        free(ks);
        free(kbox);
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    }
    for (int k = 0; k < sc->cuts->n; k++) {
        const cb_bool_cut *c = sc->cuts->cut + k;
        if (c->face[side] != face || redundant_cut(sc->cuts, k, side, F, sc->tol))
            continue;
        double *bx = kbox[nk];
        bx[0] = bx[2] = HUGE_VAL;
        bx[1] = bx[3] = -HUGE_VAL;
        for (int i = 0; i < c->n; i++)
            for (int d = 0; d < 2; d++) {
                bx[2 * d] = fmin(bx[2 * d], c->uv[side][2 * i + d]);
                bx[2 * d + 1] = fmax(bx[2 * d + 1], c->uv[side][2 * i + d]);
            }
        ks[nk++] = k;
    }
    face_cuts fc = {sc->cuts, ks, nk, (const double(*)[4])kbox, side};
    cb_status st = boundary_srcs(of, &cap, F, &fc, scale, 0.125 * sc->snap, sc->snap, err);
    for (int j = 0; j < nk && !st; j++) {
        const cb_bool_cut *c = sc->cuts->cut + ks[j];
        op_src s = {OP_CUT, ks[j], c->n, c->uv[side]};
        if (push_src(of, &cap, &s))
            st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    }
    free(ks);
    free(kbox);
    if (st)
        return st;
    cb_arr_polyline *in = malloc((size_t)of->n_srcs * sizeof *in);
    if (!in)
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    for (int k = 0; k < of->n_srcs; k++) {
        in[k].n = of->srcs[k].n;
        in[k].uv = of->srcs[k].uv;
        in[k].id = k;
    }
    cb_arr arr;
    cb_arr_init(&arr);
    st = cb_arr_build(&arr, in, of->n_srcs, scale, sc->snap, err);
    free(in);
    if (st) {
        cb_error_prefix(err, "%s face %d: ", side ? "B" : "A", face);
        cb_arr_clear(&arr);
        return st;
    }
    const cb_topo_body *X = F->b;
    int n_reg = arr.n_regions;
    of->regions = calloc((size_t)(n_reg > 0 ? n_reg : 1), sizeof *of->regions);
    if (!of->regions) {
        cb_arr_clear(&arr);
        return cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    }
    for (int r = 0; r < n_reg && !st; r++) {
        double uv[2] = {arr.region[r].inner[0], arr.region[r].inner[1]};
        if (cb_face_classify_uv(F, uv[0], uv[1], 1e-3 * sc->tol) != CB_FACE_IN)
            continue; /* a hole of the face, or outside its loops */
        stats->pieces[side]++;
        double X3[3];
        cb_topo_inverter_eval(X3, &F->inv, uv[0], uv[1]);
        cb_bool_where w;
        st = cb_bool_solid_classify(&w, sc->solid[1 - side], X3, err);
        /* On the other solid: a coincident face, or only a curve where the solids touch (a
         * cut ending inside the region, which the inner point may lie on). Points around it,
         * half the region's clearance away, tell the two apart. */
        for (int k = 0; k < 8 && !st && w == CB_BOOL_ON; k++) {
            double a = k * 0.78539816339744831, h = 0.5 * arr.region[r].clearance;
            double q[2] = {arr.region[r].inner[0] + h * cos(a) / scale[0],
                           arr.region[r].inner[1] + h * sin(a) / scale[1]}, Y[3];
            if (!(h > 0) || cb_face_classify_uv(F, q[0], q[1], 1e-3 * sc->tol) != CB_FACE_IN)
                continue;
            cb_topo_inverter_eval(Y, &F->inv, q[0], q[1]);
            cb_bool_where wq;
            st = cb_bool_solid_classify(&wq, sc->solid[1 - side], Y, err);
            if (!st && wq != CB_BOOL_ON) {
                w = wq;
                uv[0] = q[0];
                uv[1] = q[1];
                memcpy(X3, Y, sizeof X3);
            }
        }
        if (st) {
            cb_error_prefix(err, "%s face %d: ", side ? "B" : "A", face);
            break;
        }
        int flip = 0, keep;
        if (w == CB_BOOL_ON) {
            double na[3], nb[3];
            int ok = cb_face_normal(na, F, uv[0], uv[1]) > 0 &&
                     cb_bool_solid_normal_at(nb, sc->solid[1 - side], X3);
            double c = ok ? cb_vec3_dot(na, nb) : 0;
            if (fabs(c) < COINCIDENT_COS) {
                st = cb_error_set(err, CB_ERR_UNSUPPORTED,
                                  "%s face %d: a piece touches the other solid at (%.6g, %.6g, "
                                  "%.6g) where their faces are not coincident",
                                  side ? "B" : "A", face, X3[0], X3[1], X3[2]);
                break;
            }
            keep = keep_on_piece(sc->op, side, c > 0);
        } else {
            keep = keep_piece(sc->op, side, w, &flip);
        }
        if (!keep)
            continue;
        op_region *reg = of->regions + of->n_regions;
        reg->side = side;
        reg->face = face;
        reg->flip = flip;
        reg->srcs = of->srcs;
        reg->n_srcs = of->n_srcs;
        /* Loops with the region to their left in (u, v); the face keeps the region on its left
         * seen from its normal, so a face turned against S_u x S_v runs them backwards. */
        int reverse = !(X->faces[face].same_sense ^ flip);
        st = region_loops(reg, &arr, r, of->srcs, reverse, err);
        if (st)
            break;
        of->n_regions++;
        stats->kept[side]++;
    }
    cb_arr_clear(&arr);
    return st;
}

/* The faces of A then B split in parallel: each writes only its own op_face, counters, status
 * and message, combined in face order afterwards, so the result does not depend on the number
 * of threads. */
typedef struct {
    const split_ctx *sc;
    op_face *faces;
    cb_bool_stats *part; /* per face: its pieces and kept regions */
    cb_status *st;
    cb_error *err;
    int n_a; /* A's faces come first */
    int n;
    cb_context *ctx;
    atomic_int done; /* faces finished, for progress */
} split_job;

static void split_body(void *v, size_t begin, size_t end)
{
    split_job *j = v;
    for (size_t i = begin; i < end; i++) {
        int k = (int)i, side = k >= j->n_a, face = side ? k - j->n_a : k;
        if (j->ctx && cb_context_cancelled(j->ctx))
            j->st[k] = cb_error_set(j->err + k, CB_ERR_CANCELLED, "bool: cancelled");
        else
            j->st[k] = split_face(j->faces + k, j->sc, side, face, j->part + k, j->err + k);
        if (j->ctx)
            cb_context_progress(j->ctx, 1 + 2.0 * (atomic_fetch_add(&j->done, 1) + 1) / j->n, 4,
                                "boolean");
    }
}

/* Splits every face (split_face) on the context's threads; the first failing face in order
 * gives the status and message. */
static cb_status split_faces(op_face *faces, const split_ctx *sc, int n_a, int n, int threads,
                             cb_context *ctx, cb_bool_stats *stats, cb_error *err)
{
    split_job j = {sc, faces, NULL, NULL, NULL, n_a, n, ctx, 0};
    j.part = calloc((size_t)n + 1, sizeof *j.part);
    j.st = calloc((size_t)n + 1, sizeof *j.st);
    j.err = calloc((size_t)n + 1, sizeof *j.err);
    cb_status st;
    if (!j.part || !j.st || !j.err)
        st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    else if ((st = cb_parallel_for((size_t)n, 1, threads, split_body, &j)))
        cb_error_set(err, st, "bool: splitting the faces in parallel failed: %s",
                     cb_status_name(st));
    for (int k = 0; k < n && !st; k++) {
        for (int s = 0; s < 2; s++) {
            stats->pieces[s] += j.part[k].pieces[s];
            stats->kept[s] += j.part[k].kept[s];
        }
        if (j.st[k]) {
            st = j.st[k];
            if (err)
                *err = j.err[k];
        }
    }
    free(j.part);
    free(j.st);
    free(j.err);
    return st;
}

cb_status cb_bool_run(cb_topo_body **out, cb_bool_stats *stats, cb_bool_op op,
                      const cb_topo_body *A, const cb_topo_body *B, const cb_bool_opts *opts,
                      cb_context *ctx, cb_error *err)
{
    *out = NULL;
    cb_bool_stats local;
    if (!stats)
        stats = &local;
    memset(stats, 0, sizeof *stats);
    if (op != CB_BOOL_UNION && op != CB_BOOL_INTERSECTION && op != CB_BOOL_DIFFERENCE)
        return cb_error_set(err, CB_ERR_INVALID, "bool: unknown operation %d", (int)op);
    const cb_topo_body *body[2] = {A, B};
    for (int s = 0; s < 2; s++) {
        const cb_topo_body *b = body[s];
        if (!b->edge_start)
            return cb_error_set(err, CB_ERR_INVALID,
                                "bool: operand %c has no incidence index (cb_topo_body_index)",
                                "AB"[s]);
        for (int c = 0; c < b->n_coedges; c++)
            if (b->coedges[c].pcurve < 0)
                return cb_error_set(err, CB_ERR_INVALID, "bool: operand %c: coedge %d has no pcurve",
                                    "AB"[s], c);
        for (int sh = 0; sh < b->n_shells; sh++)
            if (b->shells[sh].solid < 0)
                return cb_error_set(err, CB_ERR_INVALID,
                                    "bool: operand %c: shell %d is not a solid's (an open "
                                    "surface model has no inside)",
                                    "AB"[s], sh);
        for (int e = 0; e < b->n_edges; e++) {
            int uses = b->edge_start[e + 1] - b->edge_start[e];
            if (uses != 2)
                return cb_error_set(err, CB_ERR_INVALID,
                                    "bool: operand %c is not closed: edge %d is used by %d "
                                    "coedge%s",
                                    "AB"[s], e, uses, uses == 1 ? "" : "s");
        }
    }
    if (A->length_unit_mm != B->length_unit_mm)
        return cb_error_set(err, CB_ERR_UNSUPPORTED,
                            "bool: the operands use different length units (%g mm and %g mm); "
                            "scale one to the other's first",
                            A->length_unit_mm, B->length_unit_mm);
    cb_aabb ba, bb;
    cb_topo_body_edge_box(&ba, A);
    cb_topo_body_edge_box(&bb, B);
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double ext = fmax(ba.hi[k], bb.hi[k]) - fmin(ba.lo[k], bb.lo[k]);
        d2 += ext * ext;
    }
    double size = sqrt(d2);
    double tol = opts && opts->tol > 0 ? opts->tol : CB_BOOL_REL_TOL * size;
    double chord = opts && opts->chord > 0 ? opts->chord : CB_BOOL_REL_CHORD * size;
    int threads = ctx ? cb_context_threads(ctx) : 0;

    double t0 = wall();
    cb_ssi_opts so;
    cb_ssi_opts_default(&so);
    so.tol = tol;
    so.chord = chord;
    so.threads = threads;
    so.cancel = ctx;
    cb_ssi_result_t r;
    cb_ssi_result_init(r);
    cb_status st = cb_ssi_bodies(r, A, B, &so, err);
    stats->curves = (int)r->n_curves;
    stats->points = (int)r->n_points;
    stats->ssi_certified = (long)r->pairs_certified;
    stats->ssi_within_tolerance = (long)r->pairs_within_tolerance;
    stats->ssi_refused = (long)r->n_failed;
    stats->ssi_regions = (long)r->n_regions;
    stats->ssi_done = 1;
    if (!st && r->n_failed > 0) {
        const cb_ssi_failure *f = r->failed;
        st = cb_error_set(err, f->status ? f->status : CB_ERR_UNSUPPORTED,
                          "bool: %ld face pair%s could not be intersected with certainty; first: "
                          "A face %d, B face %d: %s",
                          (long)r->n_failed, r->n_failed == 1 ? "" : "s", f->face_a, f->face_b,
                          f->msg);
    }
    stats->time_ssi = wall() - t0;
    if (ctx)
        cb_context_progress(ctx, 1, 4, "boolean");
    if (st) {
        cb_ssi_result_clear(r);
        return st;
    }

    double t1 = wall();
    cb_bool_solid *S[2];
    cb_bool_cuts cuts;
    st = _cb_bool_solids_cuts(S, &cuts, r, A, B, tol, threads, err);
    cb_ssi_result_clear(r);
    stats->cuts = cuts.n;

    int n_faces = A->n_faces + B->n_faces;
    op_face *faces = calloc((size_t)n_faces, sizeof *faces);
    if (!st && !faces)
        st = cb_error_set(err, CB_ERR_NOMEM, "bool: out of memory");
    split_ctx sc = {op, {S[0], S[1]}, &cuts, CB_BOOL_SNAP * tol, tol};
    if (!st)
        st = split_faces(faces, &sc, A->n_faces, n_faces, threads, ctx, stats, err);
    stats->time_split = wall() - t1;

    double t2 = wall();
    if (!st) {
        char where[256] = "";
        st = _cb_bool_build(out, &stats->unmatched, where, sizeof where, faces, n_faces, A, B,
                            &cuts, tol, CB_BOOL_WELD * tol, err);
        if (!st && stats->unmatched) {
            st = cb_error_set(err, CB_ERR_NUMERIC,
                              "bool: %d edge%s of the result could not be sewn (the pieces do "
                              "not close up); %s",
                              stats->unmatched, stats->unmatched == 1 ? "" : "s", where);
            cb_topo_body_free(*out);
            *out = NULL;
        }
    }
    stats->time_build = wall() - t2;
    if (!st && ctx)
        cb_context_progress(ctx, 4, 4, "boolean");
    for (int k = 0; faces && k < n_faces; k++)
        _cb_bool_face_clear(faces + k);
    free(faces);
    cb_bool_cuts_clear(&cuts);
    cb_bool_solid_free(S[0]);
    cb_bool_solid_free(S[1]);
    return st;
}
