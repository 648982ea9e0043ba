/* B-rep assembly helpers for the Cardan-joint parts (models/cardan_internal.h). */
#include <math.h>
#include <stdlib.h>

#include "brep/geom.h"
#include "models/cardan_internal.h"

static const double pi = 3.14159265358979323846;

static void nomem(cb_build *bd)
{
    if (!bd->st)
        bd->st = cb_error_set(bd->err, CB_ERR_NOMEM, "out of memory");
}

static void to_world_dir(double d[3], const cb_frame *f, const double l[3])
{
    for (int i = 0; i < 3; i++)
        d[i] = l[0] * f->x[i] + l[1] * f->y[i] + l[2] * f->z[i];
}

/* The world frame of part-frame origin o, axis z and reference direction x. */
static void world_frame(cb_build *bd, cb_frame *g, const double o[3], const double z[3],
                        const double x[3])
{
    double wo[3], wz[3], wx[3];
    cb_frame_to_world(wo, &bd->f, o);
    to_world_dir(wz, &bd->f, z);
    to_world_dir(wx, &bd->f, x);
    if (!bd->st)
        bd->st = cb_frame_make(g, wo, wz, wx, bd->err);
}

cb_status cb_build_start(cb_build *bd, const cb_cardan_params *p, double size, cb_error *err)
{
    bd->err = err;
    bd->st = CB_OK;
    bd->as_nurbs = p->as_nurbs != 0;
    bd->tol = p->tol > 0 ? p->tol : CB_CARDAN_REL_TOL * size;
    cb_xform x;
    const double origin[3] = {0, 0, 0};
    if (p->pose.angle_deg != 0)
        cb_xform_rotation(&x, origin, p->pose.axis, p->pose.angle_deg * pi / 180);
    else
        cb_xform_identity(&x);
    for (int i = 0; i < 3; i++) {
        bd->f.o[i] = p->pose.translate[i];
        bd->f.x[i] = x.r[i][0];
        bd->f.y[i] = x.r[i][1];
        bd->f.z[i] = x.r[i][2];
    }
    if (!(bd->b = cb_topo_body_new()))
        return cb_error_set(err, CB_ERR_NOMEM, "out of memory");
    bd->b->length_unit_mm = 1;
    bd->b->tol = bd->tol;
    return CB_OK;
}

cb_status cb_build_finish(cb_topo_body **out, cb_build *bd, const char *what)
{
    cb_topo_body *b = bd->b;
    if (!bd->st) {
        int s = cb_topo_body_add_shell(b), so = cb_topo_body_add_solid(b);
        if (s < 0 || so < 0) {
            nomem(bd);
        } else {
            b->shells[s] = (cb_topo_shell){0, b->n_faces, 1, 0};
            b->solids[so] = (cb_topo_solid){0, 1};
        }
    }
    if (!bd->st)
        bd->st = cb_topo_body_index(b, bd->err);
    if (!bd->st)
        bd->st = cb_topo_compute_pcurves(b, bd->tol, bd->err);
    if (bd->st) {
        cb_error_prefix(bd->err, "%s: ", what);
        cb_topo_body_free(b);
        return bd->st;
    }
    *out = b;
    return CB_OK;
}

int cb_build_vertex(cb_build *bd, const double p[3])
{
    int v = cb_topo_body_add_vertex(bd->b);
    if (v < 0) {
        nomem(bd);
        return 0;
    }
    cb_frame_to_world(bd->b->vertices[v].p, &bd->f, p);
    return v;
}

static int edge(cb_build *bd, int curve, int v0, int v1, double t0, double t1)
{
    int e = cb_topo_body_add_edge(bd->b);
    if (e < 0) {
        nomem(bd);
        return 0;
    }
    cb_topo_edge *ed = &bd->b->edges[e];
    ed->curve = curve;
    ed->v[0] = v0;
    ed->v[1] = v1;
    ed->t0 = t0;
    ed->t1 = t1;
    ed->same_sense = 1;
    ed->tol = bd->tol;
    return e;
}

int cb_build_line(cb_build *bd, int v0, int v1)
{
    int c = cb_topo_body_add_curve(bd->b);
    if (c < 0) {
        nomem(bd);
        return 0;
    }
    const double *p = bd->b->vertices[v0].p, *q = bd->b->vertices[v1].p;
    double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    cb_topo_curve *cu = &bd->b->curves[c];
    cu->kind = CB_CURVE_LINE;
    cu->r1 = cb_vec3_norm(d);
    if (!bd->st)
        bd->st = cb_frame_make(&cu->frame, p, d, NULL, bd->err);
    return edge(bd, c, v0, v1, 0, 1);
}

int cb_build_circle(cb_build *bd, const double o[3], const double n[3], const double ref[3],
                    double r, int v)
{
    int c = cb_topo_body_add_curve(bd->b);
    if (c < 0) {
        nomem(bd);
        return 0;
    }
    cb_topo_curve *cu = &bd->b->curves[c];
    cu->kind = CB_CURVE_CIRCLE;
    cu->r1 = cu->r2 = r;
    world_frame(bd, &cu->frame, o, n, ref);
    return edge(bd, c, v, v, 0, 2 * pi);
}

static int face(cb_build *bd, int s, int same_sense)
{
    int f = cb_topo_body_add_face(bd->b);
    if (f < 0) {
        nomem(bd);
        return 0;
    }
    cb_topo_face *fa = &bd->b->faces[f];
    fa->surface = s;
    fa->same_sense = same_sense;
    fa->first = bd->b->n_loops;
    fa->shell = 0;
    return f;
}

void cb_build_loop(cb_build *bd, int n, const int (*es)[2])
{
    if (bd->st)
        return;
    int l = cb_topo_body_add_loop(bd->b);
    if (l < 0) {
        nomem(bd);
        return;
    }
    cb_topo_body *b = bd->b;
    int f = b->n_faces - 1;
    b->loops[l].first = b->n_coedges;
    b->loops[l].count = n;
    b->loops[l].face = f;
    b->loops[l].outer = b->faces[f].count == 0;
    b->faces[f].count++;
    for (int k = 0; k < n; k++) {
        int c = cb_topo_body_add_coedge(b);
        if (c < 0) {
            nomem(bd);
            return;
        }
        b->coedges[c].edge = es[k][0];
        b->coedges[c].sense = es[k][1];
        b->coedges[c].pcurve = -1;
        b->coedges[c].loop = l;
    }
}

static int add_surface(cb_build *bd)
{
    int s = cb_topo_body_add_surface(bd->b);
    if (s < 0)
        nomem(bd);
    return s < 0 ? 0 : s;
}

int cb_build_plane_face(cb_build *bd, const double o[3], const double n[3], const double x[3],
                        const double range[4])
{
    int s = add_surface(bd);
    cb_frame g;
    world_frame(bd, &g, o, n, x);
    if (bd->st)
        return 0;
    cb_topo_surface *su = &bd->b->surfaces[s];
    if (bd->as_nurbs) {
        /* Bilinear: the parameter is the plane's own (u, v). */
        const double ku[4] = {range[0], range[0], range[1], range[1]};
        const double kv[4] = {range[2], range[2], range[3], range[3]};
        double pts[4][3];
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++)
                for (int c = 0; c < 3; c++)
                    pts[2 * i + j][c] = g.o[c] + range[i] * g.x[c] + range[2 + j] * g.y[c];
        su->kind = CB_SURFACE_NURBS;
        bd->st = cb_nurbs_surface_make(su->nurbs, 1, 1, ku, 4, kv, 4, &pts[0][0], NULL, 2, 2,
                                       bd->err);
    } else {
        su->kind = CB_SURFACE_ANALYTIC;
        bd->st = cb_analytic_plane(&su->analytic, &g, bd->err);
    }
    return face(bd, s, 1);
}

int cb_build_polygon_face(cb_build *bd, const double o[3], const double n[3], const double x[3],
                          int n_pts, const double (*pts)[3])
{
    double y[3], range[4] = {HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
    cb_vec3_cross(y, n, x);
    for (int k = 0; k < n_pts; k++) {
        double d[3] = {pts[k][0] - o[0], pts[k][1] - o[1], pts[k][2] - o[2]};
        double u = cb_vec3_dot(d, x), v = cb_vec3_dot(d, y);
        range[0] = fmin(range[0], u);
        range[1] = fmax(range[1], u);
        range[2] = fmin(range[2], v);
        range[3] = fmax(range[3], v);
    }
    return cb_build_plane_face(bd, o, n, x, range);
}

void cb_build_tube_edges(cb_build *bd, cb_build_tube *t, const double o[3], const double dir[3],
                         const double ref[3], double r, double len)
{
    double p0[3], p1[3], o1[3];
    for (int i = 0; i < 3; i++) {
        t->o[i] = o[i];
        t->dir[i] = dir[i];
        t->ref[i] = ref[i];
        o1[i] = o[i] + len * dir[i];
        p0[i] = o[i] + r * ref[i];
        p1[i] = o1[i] + r * ref[i];
    }
    t->r = r;
    t->len = len;
    int v0 = cb_build_vertex(bd, p0), v1 = cb_build_vertex(bd, p1);
    t->c0 = cb_build_circle(bd, o, dir, ref, r, v0);
    t->c1 = cb_build_circle(bd, o1, dir, ref, r, v1);
    t->seam = bd->st ? 0 : cb_build_line(bd, v0, v1);
}

/* The cylinder about g's z axis over the first `quarters` quarter turns from g's x axis, as a
 * degree (2, 1) rational B-spline: quarter arcs with dyadic weights (w1^2 / (w0 w2) = 1/2
 * makes each a quarter circle), u in [0, quarters] counter-clockwise about the axis, v in
 * [0, len] along it. */
static void cylinder_nurbs(cb_build *bd, cb_nurbs_surface_t s, const cb_frame *g, double r,
                           double len, int quarters)
{
    static const double cx[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1};
    static const double cy[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
    static const double cw[9] = {1, 1, 2, 1, 1, 1, 2, 1, 1};
    const double k4[12] = {0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4}, k1[6] = {0, 0, 0, 1, 1, 1};
    const double kv[4] = {0, 0, len, len};
    const int n = 2 * quarters + 1;
    double pts[18][3], w[18];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 2; j++) {
            for (int c = 0; c < 3; c++)
                pts[2 * i + j][c] =
                    g->o[c] + r * cx[i] * g->x[c] + r * cy[i] * g->y[c] + j * len * g->z[c];
            w[2 * i + j] = cw[i];
        }
    bd->st = cb_nurbs_surface_make(s, 2, 1, quarters == 4 ? k4 : k1, n + 3, kv, 4, &pts[0][0], w,
                                   n, 2, bd->err);
}

/* A cylinder face about the axis through o along the unit dir, radius r, over [0, len] along
 * the axis, the angular range starting at ref (u = 0); same_sense as given. */
static void cylinder_face(cb_build *bd, const double o[3], const double dir[3],
                          const double ref[3], double r, double len, int quarters,
                          int same_sense)
{
    int s = add_surface(bd);
    cb_frame g;
    world_frame(bd, &g, o, dir, ref);
    if (bd->st)
        return;
    cb_topo_surface *su = &bd->b->surfaces[s];
    if (bd->as_nurbs) {
        su->kind = CB_SURFACE_NURBS;
        cylinder_nurbs(bd, su->nurbs, &g, r, len, quarters);
    } else {
        su->kind = CB_SURFACE_ANALYTIC;
        bd->st = cb_analytic_cylinder(&su->analytic, &g, r, bd->err);
    }
    face(bd, s, same_sense);
}

void cb_build_tube_face(cb_build *bd, const cb_build_tube *t, int outward)
{
    cylinder_face(bd, t->o, t->dir, t->ref, t->r, t->len, 4, outward);
    /* Counter-clockwise in (u, v) about the outward normal S_u x S_v; reversed for a bore. */
    const int out_loop[4][2] = {{t->c0, 1}, {t->seam, 1}, {t->c1, 0}, {t->seam, 0}};
    const int in_loop[4][2] = {{t->seam, 1}, {t->c1, 1}, {t->seam, 0}, {t->c0, 0}};
    cb_build_loop(bd, 4, outward ? out_loop : in_loop);
}

int cb_build_quarter_arc(cb_build *bd, const double o[3], const double n[3], const double ref[3],
                         double r, int v0, int v1)
{
    int c = cb_topo_body_add_curve(bd->b);
    if (c < 0) {
        nomem(bd);
        return 0;
    }
    cb_topo_curve *cu = &bd->b->curves[c];
    cu->kind = CB_CURVE_CIRCLE;
    cu->r1 = cu->r2 = r;
    world_frame(bd, &cu->frame, o, n, ref);
    return edge(bd, c, v0, v1, 0, 0.5 * pi);
}

void cb_build_fillet_face(cb_build *bd, const double o[3], const double dir[3],
                          const double ref[3], double r, double len)
{
    cylinder_face(bd, o, dir, ref, r, len, 1, 0);
}

void cb_build_cap_face(cb_build *bd, const cb_build_tube *t)
{
    double o1[3];
    for (int i = 0; i < 3; i++)
        o1[i] = t->o[i] + t->len * t->dir[i];
    const double range[4] = {-t->r, t->r, -t->r, t->r};
    cb_build_plane_face(bd, o1, t->dir, t->ref, range);
    const int l[1][2] = {{t->c1, 1}};
    cb_build_loop(bd, 1, l);
}

void cb_build_profile_ends(cb_build *bd, int n, const double (*pt)[2], double hw, const int *ef,
                           const int *ek, const int *fwd)
{
    enum { MAX = 16 };
    if (bd->st)
        return;
    if (n > MAX) {
        bd->st = cb_error_set(bd->err, CB_ERR_INVALID, "profile of %d points (at most %d)", n, MAX);
        return;
    }
    /* y = -hw runs against the profile, y = +hw along it. */
    double front[MAX][3], back[MAX][3];
    int lf[MAX][2], lk[MAX][2];
    for (int k = 0; k < n; k++) {
        front[k][0] = back[k][0] = pt[k][0];
        front[k][1] = -hw;
        back[k][1] = hw;
        front[k][2] = back[k][2] = pt[k][1];
        lf[k][0] = ef[n - 1 - k];
        lf[k][1] = !fwd[n - 1 - k];
        lk[k][0] = ek[k];
        lk[k][1] = fwd[k];
    }
    const double ny[3] = {0, -1, 0}, ydir[3] = {0, 1, 0}, xdir[3] = {1, 0, 0};
    cb_build_polygon_face(bd, front[0], ny, xdir, n, (const double(*)[3])front);
    cb_build_loop(bd, n, (const int(*)[2])lf);
    cb_build_polygon_face(bd, back[0], ydir, xdir, n, (const double(*)[3])back);
    cb_build_loop(bd, n, (const int(*)[2])lk);
}
