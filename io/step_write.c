/* STEP AP214 writer for B-rep bodies. */
#include "io/step_write.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A growing text buffer for one entity's parameters. */
typedef struct {
    char *s;
    size_t len, cap;
    int failed; /* out of memory: the text is incomplete */
} strbuf;

static void sb_printf(strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void sb_printf(strbuf *b, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        size_t room = b->cap - b->len;
        int n = vsnprintf(b->s ? b->s + b->len : NULL, room, fmt, ap);
        va_end(ap);
        if (n < 0) {
            b->failed = 1;
            return;
        }
        if ((size_t)n < room) {
            b->len += (size_t)n;
            return;
        }
        size_t cap = 2 * b->cap + (size_t)n + 256;
        char *s = realloc(b->s, cap);
        if (!s) {
            b->failed = 1;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
}

/* A Part 21 REAL: 17 significant digits (the double comes back unchanged) and the decimal
 * point the grammar requires ("1." and "1.E-07", never "1" or "1E-07"). */
static void sb_real(strbuf *b, double x)
{
    char t[48];
    snprintf(t, sizeof t, "%.17G", x);
    if (!strchr(t, '.')) {
        char *e = strchr(t, 'E');
        if (e) {
            memmove(e + 1, e, strlen(e) + 1);
            *e = '.';
        } else {
            strcat(t, ".");
        }
    }
    sb_printf(b, "%s", t);
}

typedef struct {
    FILE *f;
    const cb_topo_body *b;
    long next;                   /* next entity number */
    long *curve_id, *surface_id; /* entity written for body curve / surface k, 0 if not yet */
    long *vertex_id, *edge_id;
    long context2d; /* the parameter space context of the pcurves, 0 if not yet */
    int dim;        /* coordinates written per point: 3, or 2 while writing a pcurve */
    strbuf text;
    int failed;
} writer;

/* Writes "#n=<text>;" and returns n; the text buffer is emptied for the next entity. */
static long emit_text(writer *w)
{
    long id = w->next++;
    if (w->text.failed || fprintf(w->f, "#%ld=%.*s;\n", id, (int)w->text.len, w->text.s) < 0)
        w->failed = 1;
    w->text.len = 0;
    w->text.failed = 0;
    return id;
}

static long emit(writer *w, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static long emit(writer *w, const char *fmt, ...)
{
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= sizeof line)
        w->failed = 1;
    sb_printf(&w->text, "%s", line);
    return emit_text(w);
}

static long write_triple(writer *w, const char *entity, const double v[3])
{
    sb_printf(&w->text, "%s('',(", entity);
    for (int k = 0; k < w->dim; k++) {
        sb_real(&w->text, v[k]);
        sb_printf(&w->text, k < w->dim - 1 ? "," : "))");
    }
    return emit_text(w);
}

static long write_point(writer *w, const double p[3])
{
    return write_triple(w, "CARTESIAN_POINT", p);
}

static long write_direction(writer *w, const double d[3])
{
    return write_triple(w, "DIRECTION", d);
}

static long write_axis2(writer *w, const cb_frame *f)
{
    long p = write_point(w, f->o), z = write_direction(w, f->z), x = write_direction(w, f->x);
    return emit(w, "AXIS2_PLACEMENT_3D('',#%ld,#%ld,#%ld)", p, z, x);
}

static long write_vector(writer *w, const double dir[3])
{
    double u[3] = {dir[0], dir[1], dir[2]};
    double len = cb_vec3_normalize(u);
    long d = write_direction(w, u);
    sb_printf(&w->text, "VECTOR('',#%ld,", d);
    sb_real(&w->text, len);
    sb_printf(&w->text, ")");
    return emit_text(w);
}

/* "(m1,m2,...)": the multiplicities of the distinct values of a knot vector. */
static void sb_mults(strbuf *t, const double *U, int count)
{
    sb_printf(t, "(");
    for (int k = 0; k < count;) {
        int m = 1;
        while (k + m < count && U[k + m] == U[k])
            m++;
        sb_printf(t, "%s%d", k ? "," : "", m);
        k += m;
    }
    sb_printf(t, ")");
}

/* "(k1,k2,...)": the distinct values of a knot vector. */
static void sb_knot_values(strbuf *t, const double *U, int count)
{
    sb_printf(t, "(");
    for (int k = 0; k < count; k++) {
        if (k && U[k] == U[k - 1])
            continue;
        if (k)
            sb_printf(t, ",");
        sb_real(t, U[k]);
    }
    sb_printf(t, ")");
}

static int is_rational(const double *cw, long n)
{
    for (long i = 0; i < n; i++)
        if (cw[4 * i + 3] != 1.0)
            return 1;
    return 0;
}

/* Cartesian points of n homogeneous points, ids into ids[]. */
static int write_control_points(writer *w, long *ids, const double *cw, long n)
{
    for (long i = 0; i < n; i++) {
        const double *p = cw + 4 * i;
        double e[3] = {p[0] / p[3], p[1] / p[3], p[2] / p[3]};
        ids[i] = write_point(w, e);
    }
    return 0;
}

static long write_bspline_curve(writer *w, const cb_nurbs_curve_t c)
{
    long *ids = malloc((size_t)c->n * sizeof *ids);
    if (!ids) {
        w->failed = 1;
        return 0;
    }
    write_control_points(w, ids, c->cw, c->n);
    int rational = is_rational(c->cw, c->n);
    strbuf *t = &w->text;
    if (rational)
        sb_printf(t, "(BOUNDED_CURVE() B_SPLINE_CURVE(%d,(", c->deg);
    else
        sb_printf(t, "B_SPLINE_CURVE_WITH_KNOTS('',%d,(", c->deg);
    for (int i = 0; i < c->n; i++)
        sb_printf(t, "%s#%ld", i ? "," : "", ids[i]);
    sb_printf(t, rational ? "),.UNSPECIFIED.,.F.,.F.) B_SPLINE_CURVE_WITH_KNOTS("
                          : "),.UNSPECIFIED.,.F.,.F.,");
    sb_mults(t, c->knots, c->n + c->deg + 1);
    sb_printf(t, ",");
    sb_knot_values(t, c->knots, c->n + c->deg + 1);
    sb_printf(t, ",.UNSPECIFIED.)");
    if (rational) {
        sb_printf(t, " CURVE() GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE((");
        for (int i = 0; i < c->n; i++) {
            if (i)
                sb_printf(t, ",");
            sb_real(t, c->cw[4 * i + 3]);
        }
        sb_printf(t, ")) REPRESENTATION_ITEM(''))");
    }
    free(ids);
    return emit_text(w);
}

static long write_bspline_surface(writer *w, const cb_nurbs_surface_t s)
{
    long n = (long)s->n_u * s->n_v;
    long *ids = malloc((size_t)n * sizeof *ids);
    if (!ids) {
        w->failed = 1;
        return 0;
    }
    write_control_points(w, ids, s->cw, n);
    int rational = is_rational(s->cw, n);
    strbuf *t = &w->text;
    if (rational)
        sb_printf(t, "(BOUNDED_SURFACE() B_SPLINE_SURFACE(%d,%d,(", s->deg_u, s->deg_v);
    else
        sb_printf(t, "B_SPLINE_SURFACE_WITH_KNOTS('',%d,%d,(", s->deg_u, s->deg_v);
    for (int i = 0; i < s->n_u; i++) {
        sb_printf(t, "%s(", i ? "," : "");
        for (int j = 0; j < s->n_v; j++)
            sb_printf(t, "%s#%ld", j ? "," : "", ids[(long)i * s->n_v + j]);
        sb_printf(t, ")");
    }
    sb_printf(t, rational ? "),.UNSPECIFIED.,.F.,.F.,.F.) B_SPLINE_SURFACE_WITH_KNOTS("
                          : "),.UNSPECIFIED.,.F.,.F.,.F.,");
    /* STEP lists u multiplicities, v multiplicities, u knots, v knots. */
    int ku = s->n_u + s->deg_u + 1, kv = s->n_v + s->deg_v + 1;
    sb_mults(t, s->knots_u, ku);
    sb_printf(t, ",");
    sb_mults(t, s->knots_v, kv);
    sb_printf(t, ",");
    sb_knot_values(t, s->knots_u, ku);
    sb_printf(t, ",");
    sb_knot_values(t, s->knots_v, kv);
    sb_printf(t, ",.UNSPECIFIED.)");
    if (rational) {
        sb_printf(t, " GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE((");
        for (int i = 0; i < s->n_u; i++) {
            sb_printf(t, "%s(", i ? "," : "");
            for (int j = 0; j < s->n_v; j++) {
                if (j)
                    sb_printf(t, ",");
                sb_real(t, cb_nurbs_surface_cw(s, i, j)[3]);
            }
            sb_printf(t, ")");
        }
        sb_printf(t, ")) REPRESENTATION_ITEM('') SURFACE())");
    }
    free(ids);
    return emit_text(w);
}

static long write_curve(writer *w, const cb_topo_curve *c)
{
    switch (c->kind) {
    case CB_CURVE_LINE: {
        double dir[3];
        for (int k = 0; k < 3; k++)
            dir[k] = c->r1 * c->frame.z[k];
        long p = write_point(w, c->frame.o), v = write_vector(w, dir);
        return emit(w, "LINE('',#%ld,#%ld)", p, v);
    }
    case CB_CURVE_CIRCLE: {
        long ax = write_axis2(w, &c->frame);
        sb_printf(&w->text, "CIRCLE('',#%ld,", ax);
        sb_real(&w->text, c->r1);
        sb_printf(&w->text, ")");
        return emit_text(w);
    }
    case CB_CURVE_ELLIPSE: {
        long ax = write_axis2(w, &c->frame);
        sb_printf(&w->text, "ELLIPSE('',#%ld,", ax);
        sb_real(&w->text, c->r1);
        sb_printf(&w->text, ",");
        sb_real(&w->text, c->r2);
        sb_printf(&w->text, ")");
        return emit_text(w);
    }
    case CB_CURVE_NURBS:
        return write_bspline_curve(w, c->nurbs);
    }
    w->failed = 1;
    return 0;
}

static long write_analytic(writer *w, const cb_analytic_surface *a)
{
    static const char *const names[] = {
        [CB_ANALYTIC_PLANE] = "PLANE",         [CB_ANALYTIC_CYLINDER] = "CYLINDRICAL_SURFACE",
        [CB_ANALYTIC_CONE] = "CONICAL_SURFACE", [CB_ANALYTIC_SPHERE] = "SPHERICAL_SURFACE",
        [CB_ANALYTIC_TORUS] = "TOROIDAL_SURFACE"};
    if (a->kind == CB_ANALYTIC_ELLIPSOID) {
        cb_nurbs_surface_t n;
        cb_nurbs_surface_init(n);
        long id = 0;
        const double pi = 3.14159265358979323846;
        if (cb_analytic_to_nurbs(n, a, 0.0, 2.0 * pi, -pi / 2, pi / 2, NULL) == CB_OK)
            id = write_bspline_surface(w, n);
        else
            w->failed = 1;
        cb_nurbs_surface_clear(n);
        return id;
    }
    long ax = write_axis2(w, &a->frame);
    sb_printf(&w->text, "%s('',#%ld", names[a->kind], ax);
    double params[2];
    int np = 0;
    switch (a->kind) {
    case CB_ANALYTIC_CYLINDER:
    case CB_ANALYTIC_SPHERE: params[np++] = a->r1; break;
    case CB_ANALYTIC_CONE: params[np++] = a->r1; params[np++] = a->angle; break;
    case CB_ANALYTIC_TORUS: params[np++] = a->r1; params[np++] = a->r2; break;
    default: break;
    }
    for (int k = 0; k < np; k++) {
        sb_printf(&w->text, ",");
        sb_real(&w->text, params[k]);
    }
    sb_printf(&w->text, ")");
    return emit_text(w);
}

static long write_surface(writer *w, const cb_topo_surface *s)
{
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC: return write_analytic(w, &s->analytic);
    case CB_SURFACE_NURBS: return write_bspline_surface(w, s->nurbs);
    case CB_SURFACE_REVOLUTION: {
        long prof = write_curve(w, &s->profile);
        long p = write_point(w, s->frame.o), d = write_direction(w, s->frame.z);
        long ax = emit(w, "AXIS1_PLACEMENT('',#%ld,#%ld)", p, d);
        return emit(w, "SURFACE_OF_REVOLUTION('',#%ld,#%ld)", prof, ax);
    }
    case CB_SURFACE_EXTRUSION: {
        long prof = write_curve(w, &s->profile), v = write_vector(w, s->dir);
        return emit(w, "SURFACE_OF_LINEAR_EXTRUSION('',#%ld,#%ld)", prof, v);
    }
    }
    w->failed = 1;
    return 0;
}

static long body_curve(writer *w, int k)
{
    if (!w->curve_id[k])
        w->curve_id[k] = write_curve(w, &w->b->curves[k]);
    return w->curve_id[k];
}

static long body_surface(writer *w, int k)
{
    if (!w->surface_id[k])
        w->surface_id[k] = write_surface(w, &w->b->surfaces[k]);
    return w->surface_id[k];
}

static long body_vertex(writer *w, int k)
{
    if (!w->vertex_id[k]) {
        long p = write_point(w, w->b->vertices[k].p);
        w->vertex_id[k] = emit(w, "VERTEX_POINT('',#%ld)", p);
    }
    return w->vertex_id[k];
}

/* PCURVE('', surface, DEFINITIONAL_REPRESENTATION('', (the 2D curve moved by sh and
 * reparameterised by t -> t - dt), 2D context)). */
static long write_pcurve(writer *w, long surface, const cb_topo_curve *pc, const double sh[2],
                         double dt)
{
    if (!w->context2d)
        w->context2d = emit(w, "(GEOMETRIC_REPRESENTATION_CONTEXT(2) "
                               "PARAMETRIC_REPRESENTATION_CONTEXT() "
                               "REPRESENTATION_CONTEXT('2D SPACE',''))");
    cb_topo_curve moved = *pc;
    cb_nurbs_curve_init(moved.nurbs);
    if (pc->kind == CB_CURVE_NURBS) {
        if (cb_nurbs_curve_set(moved.nurbs, pc->nurbs, NULL)) {
            w->failed = 1;
            return 0;
        }
        for (int k = 0; k < moved.nurbs->n; k++)
            for (int i = 0; i < 2; i++)
                moved.nurbs->cw[4 * k + i] += sh[i] * moved.nurbs->cw[4 * k + 3];
        for (int k = 0; k < moved.nurbs->n + moved.nurbs->deg + 1; k++)
            moved.nurbs->knots[k] += dt;
    } else {
        for (int i = 0; i < 2; i++)
            moved.frame.o[i] += sh[i] - dt * moved.r1 * moved.frame.z[i];
    }
    w->dim = 2;
    long c = write_curve(w, &moved);
    w->dim = 3;
    cb_topo_curve_clear(&moved);
    long rep = emit(w, "DEFINITIONAL_REPRESENTATION('',(#%ld),#%ld)", c, w->context2d);
    return emit(w, "PCURVE('',#%ld,#%ld)", surface, rep);
}

/* The coedges of face fi on edge k when there are two (a seam) and both carry a pcurve that
 * can be written as the face's surface is (lines and B-splines in (u, v); not on an
 * ellipsoid, written as a B-spline of another parameterisation): 1 and their indices. */
static int seam_coedges(const writer *w, int k, int fi, int co[2])
{
    const cb_topo_body *b = w->b;
    const cb_topo_face *f = &b->faces[fi];
    const cb_topo_surface *s = &b->surfaces[f->surface];
    if (s->kind == CB_SURFACE_ANALYTIC && s->analytic.kind == CB_ANALYTIC_ELLIPSOID)
        return 0;
    int n = 0;
    for (int l = f->first; l < f->first + f->count; l++)
        for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++)
            if (b->coedges[c].edge == k) {
                if (n == 2)
                    return 0;
                co[n++] = c;
            }
    for (int j = 0; j < n; j++) {
        int p = b->coedges[co[j]].pcurve;
        if (p < 0 || (b->pcurves[p].kind != CB_CURVE_LINE && b->pcurves[p].kind != CB_CURVE_NURBS))
            return 0;
    }
    return n == 2;
}

/* The shift by whole periods that puts the two pcurves of seam coedges co on the two ends of
 * the surface's domain across the seam: pcurves may lie a period or more away (all of a
 * face's lifted alike, which Colibri reads alike), and the reader computes the others of the
 * face in the domain itself. */
static void seam_lift(double sh[2], writer *w, int s, const int co[2])
{
    const cb_topo_body *b = w->b;
    sh[0] = sh[1] = 0;
    cb_topo_inverter inv;
    if (cb_topo_inverter_init(&inv, &b->surfaces[s], b->tol > 0 ? b->tol : 1e-9, NULL))
        return;
    const cb_topo_edge *e = &b->edges[b->coedges[co[0]].edge];
    double m[2][3];
    for (int j = 0; j < 2; j++)
        cb_topo_curve_eval(m[j], &b->pcurves[b->coedges[co[j]].pcurve], 0.5 * (e->t0 + e->t1));
    int across = fabs(m[1][0] - m[0][0]) > fabs(m[1][1] - m[0][1]) ? 0 : 1;
    double P = inv.period[across];
    if (P > 0)
        sh[across] = P * round((inv.box[2 * across] - fmin(m[0][across], m[1][across])) / P);
    cb_topo_inverter_clear(&inv);
}

/* Edge k, first met in face fi. A seam edge of fi (used twice by it) carries its two pcurves,
 * in the order of its coedges in the face, as a SEAM_CURVE: without them a reader must place
 * each use on a side of the seam by itself, and Open CASCADE and Colibri both placed them
 * wrongly in a sphere cut by a plane through both pieces of its seam (a Boolean's result), so
 * reading back the sphere minus a cap gave the cap. Other edges carry their 3D curve alone. */
static long body_edge(writer *w, int k, int fi)
{
    if (!w->edge_id[k]) {
        const cb_topo_edge *e = &w->b->edges[k];
        long v0 = body_vertex(w, e->v[0]), v1 = body_vertex(w, e->v[1]);
        long c = body_curve(w, e->curve);
        int co[2];
        if (seam_coedges(w, k, fi, co)) {
            int s = w->b->faces[fi].surface;
            long surf = body_surface(w, s), pc[2];
            double sh[2], dt = 0;
            seam_lift(sh, w, s, co);
            const cb_topo_curve *cu = &w->b->curves[e->curve];
            if (cu->kind == CB_CURVE_CIRCLE || cu->kind == CB_CURVE_ELLIPSE) {
                /* A reader puts the conic's range where its start vertex projects, in
                 * [0, 2 pi): the pcurves follow that parameter. */
                double ta;
                cb_topo_curve_project(&ta, cu, w->b->vertices[e->v[e->same_sense ? 0 : 1]].p, 0,
                                      0);
                dt = 6.283185307179586 * round((ta - e->t0) / 6.283185307179586);
            }
            for (int j = 0; j < 2; j++)
                pc[j] = write_pcurve(w, surf, &w->b->pcurves[w->b->coedges[co[j]].pcurve], sh,
                                     dt);
            c = emit(w, "SEAM_CURVE('',#%ld,(#%ld,#%ld),.PCURVE_S1.)", c, pc[0], pc[1]);
        }
        w->edge_id[k] =
            emit(w, "EDGE_CURVE('',#%ld,#%ld,#%ld,%s)", v0, v1, c, e->same_sense ? ".T." : ".F.");
    }
    return w->edge_id[k];
}

/* Writes an entity whose parameters end in a list of the ids, e.g. "EDGE_LOOP('',(#1,#2))". */
static long emit_list(writer *w, const char *head, const long *ids, int n, const char *tail)
{
    sb_printf(&w->text, "%s(", head);
    for (int k = 0; k < n; k++)
        sb_printf(&w->text, "%s#%ld", k ? "," : "", ids[k]);
    sb_printf(&w->text, ")%s", tail);
    return emit_text(w);
}

static long write_face(writer *w, int fi)
{
    const cb_topo_body *b = w->b;
    const cb_topo_face *f = &b->faces[fi];
    long *bounds = malloc((size_t)(f->count ? f->count : 1) * sizeof *bounds);
    if (!bounds) {
        w->failed = 1;
        return 0;
    }
    for (int l = 0; l < f->count; l++) {
        const cb_topo_loop *lp = &b->loops[f->first + l];
        long *oe = malloc((size_t)(lp->count ? lp->count : 1) * sizeof *oe);
        if (!oe) {
            w->failed = 1;
            break;
        }
        for (int c = 0; c < lp->count; c++) {
            const cb_topo_coedge *ce = &b->coedges[lp->first + c];
            long e = body_edge(w, ce->edge, fi);
            oe[c] = emit(w, "ORIENTED_EDGE('',*,*,#%ld,%s)", e, ce->sense ? ".T." : ".F.");
        }
        long loop = emit_list(w, "EDGE_LOOP('',", oe, lp->count, ")");
        free(oe);
        bounds[l] = emit(w, "%s('',#%ld,.T.)", lp->outer ? "FACE_OUTER_BOUND" : "FACE_BOUND",
                         loop);
    }
    long surf = body_surface(w, f->surface);
    char tail[32];
    snprintf(tail, sizeof tail, ",#%ld,%s)", surf, f->same_sense ? ".T." : ".F.");
    long id = emit_list(w, "ADVANCED_FACE('',", bounds, f->count, tail);
    free(bounds);
    return id;
}

static long write_shell(writer *w, int si, const char *entity)
{
    const cb_topo_shell *sh = &w->b->shells[si];
    long *faces = malloc((size_t)(sh->count ? sh->count : 1) * sizeof *faces);
    if (!faces) {
        w->failed = 1;
        return 0;
    }
    for (int k = 0; k < sh->count; k++)
        faces[k] = write_face(w, sh->first + k);
    char head[64];
    snprintf(head, sizeof head, "%s('',", entity);
    long id = emit_list(w, head, faces, sh->count, ")");
    free(faces);
    return id;
}

static long write_solid(writer *w, int si)
{
    const cb_topo_solid *so = &w->b->solids[si];
    long outer = write_shell(w, so->first, "CLOSED_SHELL");
    if (so->count == 1)
        return emit(w, "MANIFOLD_SOLID_BREP('',#%ld)", outer);
    /* The reader already turned void faces to face out of the material, so the voids keep
     * that orientation (.T.). */
    long *voids = malloc((size_t)(so->count - 1) * sizeof *voids);
    if (!voids) {
        w->failed = 1;
        return 0;
    }
    for (int k = 1; k < so->count; k++) {
        long sh = write_shell(w, so->first + k, "CLOSED_SHELL");
        voids[k - 1] = emit(w, "ORIENTED_CLOSED_SHELL('',*,#%ld,.T.)", sh);
    }
    char head[64];
    snprintf(head, sizeof head, "BREP_WITH_VOIDS('',#%ld,", outer);
    long id = emit_list(w, head, voids, so->count - 1, ")");
    free(voids);
    return id;
}

/* The length unit: SI with a prefix where the body's unit is one, else conversion-based. */
static long write_length_unit(writer *w, double mm)
{
    static const struct {
        double mm;
        const char *prefix;
    } si[] = {{1.0, ".MILLI."}, {10.0, ".CENTI."}, {1000.0, "$"}, {1e-3, ".MICRO."}};
    for (size_t k = 0; k < sizeof si / sizeof *si; k++)
        if (mm == si[k].mm)
            return emit(w, "(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(%s,.METRE.))", si[k].prefix);
    long milli = emit(w, "(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.))");
    sb_printf(&w->text, "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(");
    sb_real(&w->text, mm);
    sb_printf(&w->text, "),#%ld)", milli);
    long measure = emit_text(w);
    long dim = emit(w, "DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)");
    return emit(w, "(CONVERSION_BASED_UNIT('UNIT',#%ld) LENGTH_UNIT() NAMED_UNIT(#%ld))",
                measure, dim);
}

/* Refuses what would give a wrong or unreadable file, before anything is written. */
static cb_status check_body(const cb_topo_body *b, cb_error *err)
{
    int free_shells = 0;
    for (int k = 0; k < b->n_shells; k++)
        free_shells += b->shells[k].solid < 0;
    if (b->n_solids > 0 && free_shells > 0)
        return cb_error_set(err, CB_ERR_UNSUPPORTED,
                            "STEP write: %d solids and %d shells outside solids in one body",
                            b->n_solids, free_shells);
    if (b->n_faces == 0)
        return cb_error_set(err, CB_ERR_INVALID, "STEP write: the body has no faces");
    for (int k = 0; k < b->n_vertices; k++)
        for (int i = 0; i < 3; i++)
            if (!isfinite(b->vertices[k].p[i]))
                return cb_error_set(err, CB_ERR_INVALID, "STEP write: vertex %d is not finite",
                                    k);
    for (int k = 0; k < b->n_surfaces; k++)
        if (b->surfaces[k].kind == CB_SURFACE_NURBS &&
            cb_nurbs_surface_validate(b->surfaces[k].nurbs, err))
            return cb_error_prefix(err, "STEP write: surface %d: ", k);
    for (int k = 0; k < b->n_curves; k++)
        if (b->curves[k].kind == CB_CURVE_NURBS && cb_nurbs_curve_validate(b->curves[k].nurbs, err))
            return cb_error_prefix(err, "STEP write: curve %d: ", k);
    return CB_OK;
}

static void write_header(FILE *f, const char *name)
{
    fprintf(f, "ISO-10303-21;\nHEADER;\n"
               "FILE_DESCRIPTION(('Colibri B-rep'),'2;1');\n"
               "FILE_NAME('%s','',(''),(''),'Colibri','Colibri','');\n"
               "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\n"
               "ENDSEC;\nDATA;\n",
            name);
}

/* Product structure and representation context; returns the context id, and the id of the
 * product definition shape in *pds. */
static long write_product(writer *w, const char *name, long *pds)
{
    long app = emit(w, "APPLICATION_CONTEXT('automotive_design')");
    emit(w, "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,"
            "#%ld)", app);
    long pctx = emit(w, "PRODUCT_CONTEXT('',#%ld,'mechanical')", app);
    long prod = emit(w, "PRODUCT('%s','%s','',(#%ld))", name, name, pctx);
    emit(w, "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#%ld))", prod);
    long form = emit(w, "PRODUCT_DEFINITION_FORMATION('','',#%ld)", prod);
    long dctx = emit(w, "PRODUCT_DEFINITION_CONTEXT('part definition',#%ld,'design')", app);
    long def = emit(w, "PRODUCT_DEFINITION('design','',#%ld,#%ld)", form, dctx);
    *pds = emit(w, "PRODUCT_DEFINITION_SHAPE('','',#%ld)", def);

    long len = write_length_unit(w, w->b->length_unit_mm);
    long ang = emit(w, "(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.))");
    long sr = emit(w, "(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT())");
    if (!(w->b->tol > 0))
        return emit(w, "(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT("
                       "(#%ld,#%ld,#%ld)) REPRESENTATION_CONTEXT('',''))", len, ang, sr);
    sb_printf(&w->text, "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(");
    sb_real(&w->text, w->b->tol);
    sb_printf(&w->text, "),#%ld,'distance_accuracy_value','confusion accuracy')", len);
    long unc = emit_text(w);
    return emit(w, "(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT("
                   "(#%ld)) GLOBAL_UNIT_ASSIGNED_CONTEXT((#%ld,#%ld,#%ld)) "
                   "REPRESENTATION_CONTEXT('',''))", unc, len, ang, sr);
}

/* Product names go inside a Part 21 string: keep printable ASCII without quotes or
 * backslashes, so no escaping is needed. */
static void clean_name(char *out, size_t size, const char *name)
{
    size_t k = 0;
    for (; name[k] && k + 1 < size; k++) {
        unsigned char c = (unsigned char)name[k];
        out[k] = (c >= 32 && c < 127 && c != '\'' && c != '\\') ? (char)c : '_';
    }
    out[k] = '\0';
}

cb_status cb_step_write(const cb_topo_body *b, const char *path, const char *name,
                        cb_error *err)
{
    cb_status st = check_body(b, err);
    if (st)
        return st;
    char pname[128];
    clean_name(pname, sizeof pname, name ? name : "colibri");
    writer w = {.b = b, .next = 1, .dim = 3};
    w.curve_id = calloc((size_t)b->n_curves + 1, sizeof(long));
    w.surface_id = calloc((size_t)b->n_surfaces + 1, sizeof(long));
    w.vertex_id = calloc((size_t)b->n_vertices + 1, sizeof(long));
    w.edge_id = calloc((size_t)b->n_edges + 1, sizeof(long));
    if (!w.curve_id || !w.surface_id || !w.vertex_id || !w.edge_id) {
        st = cb_error_set(err, CB_ERR_NOMEM, "STEP write: no memory");
        goto done;
    }
    if (!(w.f = fopen(path, "w"))) {
        st = cb_error_set(err, CB_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
        goto done;
    }
    write_header(w.f, pname);
    long pds, ctx = write_product(&w, pname, &pds);
    long origin_p = write_point(&w, (double[3]){0, 0, 0});
    long origin_z = write_direction(&w, (double[3]){0, 0, 1});
    long origin_x = write_direction(&w, (double[3]){1, 0, 0});
    long origin = emit(&w, "AXIS2_PLACEMENT_3D('',#%ld,#%ld,#%ld)", origin_p, origin_z, origin_x);
    int n_items = b->n_solids ? b->n_solids : 1;
    long *items = malloc((size_t)(n_items + 1) * sizeof *items);
    if (!items) {
        w.failed = 1;
    } else {
        items[0] = origin;
        const char *rep = "ADVANCED_BREP_SHAPE_REPRESENTATION('',";
        if (b->n_solids) {
            for (int k = 0; k < b->n_solids; k++)
                items[k + 1] = write_solid(&w, k);
        } else {
            long *shells = malloc((size_t)b->n_shells * sizeof *shells);
            if (!shells) {
                w.failed = 1;
            } else {
                for (int k = 0; k < b->n_shells; k++)
                    shells[k] = write_shell(&w, k, b->shells[k].closed ? "CLOSED_SHELL"
                                                                       : "OPEN_SHELL");
                items[1] = emit_list(&w, "SHELL_BASED_SURFACE_MODEL('',", shells, b->n_shells,
                                     ")");
                free(shells);
            }
            rep = "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',";
        }
        char tail[32];
        snprintf(tail, sizeof tail, ",#%ld)", ctx);
        long shape = emit_list(&w, rep, items, n_items + 1, tail);
        emit(&w, "SHAPE_DEFINITION_REPRESENTATION(#%ld,#%ld)", pds, shape);
        free(items);
    }
    if (fprintf(w.f, "ENDSEC;\nEND-ISO-10303-21;\n") < 0)
        w.failed = 1;
    if (fclose(w.f) != 0)
        w.failed = 1;
    if (w.failed) {
        remove(path);
        st = cb_error_set(err, CB_ERR_IO, "%s: write failed", path);
    }
done:
    free(w.text.s);
    free(w.curve_id);
    free(w.surface_id);
    free(w.vertex_id);
    free(w.edge_id);
    return st;
}
