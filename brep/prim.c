/* Primitive solids as B-rep bodies (brep/prim.h). Each builder describes its shape in the
 * local coordinates of the placement frame; the helpers below map points, directions and
 * sub-frames to the world and append the entities. */
#include "brep/prim.h"

#include <math.h>
#include <stdlib.h>

#include "brep/geom.h"

static const double pi = 3.14159265358979323846;

typedef struct {
    cb_topo_body *b;
    cb_frame f;
    int as_nurbs;
    double tol;
    cb_error *err;
    cb_status st; /* first failure; later calls do nothing */
} builder;

static void to_world_dir(double d[3], const cb_frame *f, const double l[3])
{
    for (int i = 0; i < 3; i++)
        d[i] = l[0] * f->x[i] + l[1] * f->y[i] + l[2] * f->z[i];
}

static void nomem(builder *bd)
{
    if (!bd->st)
        bd->st = cb_error_set(bd->err, CB_ERR_NOMEM, "primitive: out of memory");
}

/* The world frame of local origin o, axis z and reference direction x. */
static void sub_frame(builder *bd, cb_frame *g, const double o[3], const double z[3],
                      const double x[3])
{
    double wo[3], wz[3], wx[3];
    cb_frame_to_world(wo, &bd->f, o);
    to_world_dir(wz, &bd->f, z);
    to_world_dir(wx, &bd->f, x);
    if (!bd->st)
        bd->st = cb_frame_make(g, wo, wz, wx, bd->err);
}

static int vertex(builder *bd, double x, double y, double z)
{
    int v = cb_topo_body_add_vertex(bd->b);
    if (v < 0) {
        nomem(bd);
        return 0;
    }
    double l[3] = {x, y, z};
    cb_frame_to_world(bd->b->vertices[v].p, &bd->f, l);
    return v;
}

static int edge(builder *bd, int curve, int v0, int v1, double t0, double t1)
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

static int line_edge(builder *bd, int v0, int v1)
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

/* The conic o + r1 cos t x + r2 sin t y (local o, x; y = z x x) from v0 to v1 over [t0, t1]. */
static int conic_edge(builder *bd, const double o[3], const double z[3], const double x[3],
                      double r1, double r2, int v0, int v1, double t0, double t1)
{
    int c = cb_topo_body_add_curve(bd->b);
    if (c < 0) {
        nomem(bd);
        return 0;
    }
    cb_topo_curve *cu = &bd->b->curves[c];
    cu->kind = r1 == r2 ? CB_CURVE_CIRCLE : CB_CURVE_ELLIPSE;
    cu->r1 = r1;
    cu->r2 = r2;
    sub_frame(bd, &cu->frame, o, z, x);
    return edge(bd, c, v0, v1, t0, t1);
}

/* An analytic surface in the sub-frame (o, z, x), written as a B-spline over
 * [u0, u1] x [v0, v1] when the builder asks for B-splines. */
static int surface(builder *bd, cb_analytic_kind kind, const double o[3], const double z[3],
                   const double x[3], const double prm[4], const double range[4])
{
    int s = cb_topo_body_add_surface(bd->b);
    if (s < 0) {
        nomem(bd);
        return 0;
    }
    cb_frame g;
    sub_frame(bd, &g, o, z, x);
    if (bd->st)
        return s;
    cb_analytic_surface a;
    cb_status st = CB_OK;
    switch (kind) {
    case CB_ANALYTIC_PLANE: st = cb_analytic_plane(&a, &g, bd->err); break;
    case CB_ANALYTIC_CYLINDER: st = cb_analytic_cylinder(&a, &g, prm[0], bd->err); break;
    case CB_ANALYTIC_CONE: st = cb_analytic_cone(&a, &g, prm[0], prm[1], bd->err); break;
    case CB_ANALYTIC_SPHERE: st = cb_analytic_sphere(&a, &g, prm[0], bd->err); break;
    case CB_ANALYTIC_TORUS: st = cb_analytic_torus(&a, &g, prm[0], prm[1], bd->err); break;
    case CB_ANALYTIC_ELLIPSOID:
        st = cb_analytic_ellipsoid(&a, &g, prm[0], prm[1], prm[2], bd->err);
        break;
    }
    if (st) {
        bd->st = st;
        return s;
    }
    cb_topo_surface *su = &bd->b->surfaces[s];
    if (bd->as_nurbs) {
        su->kind = CB_SURFACE_NURBS;
        bd->st =
            cb_analytic_to_nurbs(su->nurbs, &a, range[0], range[1], range[2], range[3], bd->err);
    } else {
        su->kind = CB_SURFACE_ANALYTIC;
        su->analytic = a;
    }
    return s;
}

static int face(builder *bd, int s, int same_sense)
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

/* One loop of face f (the face's last so far) from n (edge, sense) pairs in traversal order. */
static void loop(builder *bd, int f, int n, const int (*es)[2])
{
    int l = cb_topo_body_add_loop(bd->b);
    if (l < 0) {
        nomem(bd);
        return;
    }
    cb_topo_body *b = bd->b;
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

static cb_status start(builder *bd, const cb_frame *f, int as_nurbs, double tol, double size,
                       cb_error *err)
{
    bd->err = err;
    bd->st = CB_OK;
    bd->as_nurbs = as_nurbs;
    bd->tol = tol > 0 ? tol : CB_PRIM_REL_TOL * size;
    if (f) {
        const double *vs[4] = {f->o, f->x, f->y, f->z};
        for (int k = 0; k < 4; k++)
            for (int i = 0; i < 3; i++)
                if (!isfinite(vs[k][i]))
                    return cb_error_set(err, CB_ERR_INVALID, "primitive: frame is not finite");
        bd->f = *f;
    } else {
        bd->f = (cb_frame){{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    }
    if (!isfinite(tol))
        return cb_error_set(err, CB_ERR_INVALID, "primitive: tolerance %g is not finite", tol);
    if (!(bd->b = cb_topo_body_new()))
        return cb_error_set(err, CB_ERR_NOMEM, "primitive: out of memory");
    bd->b->length_unit_mm = 1;
    bd->b->tol = bd->tol;
    return CB_OK;
}

/* Closes the body: one shell of every face, one solid; index, pcurves. */
static cb_status finish(cb_topo_body **out, builder *bd, const char *what)
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

static cb_status positive(double x, const char *what, const char *name, cb_error *err)
{
    if (!(isfinite(x) && x > 0))
        return cb_error_set(err, CB_ERR_INVALID, "%s: %s %.17g must be finite and > 0", what, name,
                            x);
    return CB_OK;
}

cb_status cb_prim_box(cb_topo_body **out, const cb_frame *f, const double lo[3], const double hi[3],
                      int as_nurbs, double tol, cb_error *err)
{
    *out = NULL;
    double size = 0;
    for (int i = 0; i < 3; i++) {
        if (!(isfinite(lo[i]) && isfinite(hi[i]) && lo[i] < hi[i]))
            return cb_error_set(err, CB_ERR_INVALID,
                                "box: %c range [%.17g, %.17g] is empty or not finite", "xyz"[i],
                                lo[i], hi[i]);
        size = fmax(size, hi[i] - lo[i]);
    }
    builder bd;
    cb_status st = start(&bd, f, as_nurbs, tol, size, err);
    if (st)
        return st;
    /* Vertex k has coordinate i at hi when bit i of k is set. */
    int v[8], e[8][8];
    for (int k = 0; k < 8; k++) {
        v[k] = vertex(&bd, k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
        for (int j = 0; j < 8; j++)
            e[k][j] = -1;
    }
    for (int i = 0; i < 3; i++)
        for (int side = 0; side < 2; side++) {
            /* In-plane axes a, b with a x b the outward normal; corners counter-clockwise
             * about it. */
            int a = (i + 1) % 3, c = (i + 2) % 3;
            if (!side) {
                int t = a;
                a = c;
                c = t;
            }
            int corner[4], base = side << i;
            corner[0] = base;
            corner[1] = base | 1 << a;
            corner[2] = base | 1 << a | 1 << c;
            corner[3] = base | 1 << c;
            double o[3], n[3] = {0, 0, 0}, x[3] = {0, 0, 0}, range[4];
            for (int j = 0; j < 3; j++)
                o[j] = 0.5 * (lo[j] + hi[j]);
            o[i] = side ? hi[i] : lo[i];
            n[i] = side ? 1 : -1;
            x[a] = 1;
            range[0] = -0.5 * (hi[a] - lo[a]);
            range[1] = -range[0];
            range[2] = -0.5 * (hi[c] - lo[c]);
            range[3] = -range[2];
            int fa = face(&bd, surface(&bd, CB_ANALYTIC_PLANE, o, n, x, NULL, range), 1);
            int es[4][2];
            for (int k = 0; k < 4; k++) {
                int p = corner[k], q = corner[(k + 1) % 4];
                int lo_k = p < q ? p : q, hi_k = p < q ? q : p;
                if (e[lo_k][hi_k] < 0 && !bd.st)
                    e[lo_k][hi_k] = line_edge(&bd, v[lo_k], v[hi_k]);
                es[k][0] = e[lo_k][hi_k];
                es[k][1] = p == lo_k;
            }
            if (!bd.st)
                loop(&bd, fa, 4, (const int(*)[2])es);
        }
    return finish(out, &bd, "box");
}

/* Sphere and ellipsoid: one face, the seam meridian in y' = 0 from pole to pole. */
static cb_status spheroid(cb_topo_body **out, const cb_frame *f, cb_analytic_kind kind, double a,
                          double b, double c, int as_nurbs, double tol, const char *what,
                          cb_error *err)
{
    builder bd;
    cb_status st = start(&bd, f, as_nurbs, tol, 2 * fmax(a, fmax(b, c)), err);
    if (st)
        return st;
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0}, my[3] = {0, -1, 0};
    int s = vertex(&bd, 0, 0, -c), n = vertex(&bd, 0, 0, c);
    int mer = conic_edge(&bd, o, my, x, a, c, s, n, -0.5 * pi, 0.5 * pi);
    double prm[4] = {a, b, c, 0}, range[4] = {0, 2 * pi, -0.5 * pi, 0.5 * pi};
    int fa = face(&bd, surface(&bd, kind, o, z, x, prm, range), 1);
    const int l[2][2] = {{mer, 1}, {mer, 0}};
    if (!bd.st)
        loop(&bd, fa, 2, l);
    return finish(out, &bd, what);
}

cb_status cb_prim_sphere(cb_topo_body **out, const cb_frame *f, double radius, int as_nurbs,
                         double tol, cb_error *err)
{
    *out = NULL;
    cb_status st = positive(radius, "sphere", "radius", err);
    return st ? st
              : spheroid(out, f, CB_ANALYTIC_SPHERE, radius, radius, radius, as_nurbs, tol,
                         "sphere", err);
}

cb_status cb_prim_ellipsoid(cb_topo_body **out, const cb_frame *f, double a, double b, double c,
                            int as_nurbs, double tol, cb_error *err)
{
    *out = NULL;
    cb_status st = positive(a, "ellipsoid", "semi-axis a", err);
    if (!st)
        st = positive(b, "ellipsoid", "semi-axis b", err);
    if (!st)
        st = positive(c, "ellipsoid", "semi-axis c", err);
    return st ? st
              : spheroid(out, f, CB_ANALYTIC_ELLIPSOID, a, b, c, as_nurbs, tol, "ellipsoid", err);
}

/* Cylinder (r0 = r1) and cone frustum: a side face cut along the seam in y' = 0, x' > 0, and
 * a disc at each end of non-zero radius. */
static cb_status solid_of_revolution(cb_topo_body **out, const cb_frame *f, double r0, double r1,
                                     double h, int as_nurbs, double tol, const char *what,
                                     cb_error *err)
{
    builder bd;
    cb_status st = start(&bd, f, as_nurbs, tol, fmax(h, 2 * fmax(r0, r1)), err);
    if (st)
        return st;
    double o[3] = {0, 0, 0}, top[3] = {0, 0, h}, z[3] = {0, 0, 1}, mz[3] = {0, 0, -1},
           x[3] = {1, 0, 0};
    int a = vertex(&bd, r0, 0, 0), c = vertex(&bd, r1, 0, h);
    int bottom = -1, upper = -1;
    if (r0 > 0)
        bottom = conic_edge(&bd, o, z, x, r0, r0, a, a, 0, 2 * pi);
    if (r1 > 0)
        upper = conic_edge(&bd, top, z, x, r1, r1, c, c, 0, 2 * pi);
    int seam = bd.st ? 0 : line_edge(&bd, a, c);
    int side;
    if (r0 == r1) {
        double prm[4] = {r0, 0, 0, 0}, range[4] = {0, 2 * pi, 0, h};
        side = surface(&bd, CB_ANALYTIC_CYLINDER, o, z, x, prm, range);
    } else {
        /* Cone radii grow with v: the surface starts at the smaller end. */
        int up = r0 < r1;
        double rs = up ? r0 : r1, prm[4] = {rs, atan(fabs(r1 - r0) / h), 0, 0};
        double range[4] = {0, 2 * pi, 0, h};
        side = surface(&bd, CB_ANALYTIC_CONE, up ? o : top, up ? z : mz, x, prm, range);
    }
    int fs = face(&bd, side, 1);
    int es[4][2], n = 0;
    if (bottom >= 0) {
        es[n][0] = bottom;
        es[n++][1] = 1;
    }
    es[n][0] = seam;
    es[n++][1] = 1;
    if (upper >= 0) {
        es[n][0] = upper;
        es[n++][1] = 0;
    }
    es[n][0] = seam;
    es[n++][1] = 0;
    if (!bd.st)
        loop(&bd, fs, n, (const int(*)[2])es);
    double range0[4] = {-r0, r0, -r0, r0}, range1[4] = {-r1, r1, -r1, r1};
    if (bottom >= 0) {
        int fb = face(&bd, surface(&bd, CB_ANALYTIC_PLANE, o, z, x, NULL, range0), 0);
        const int l[1][2] = {{bottom, 0}};
        if (!bd.st)
            loop(&bd, fb, 1, l);
    }
    if (upper >= 0) {
        int ft = face(&bd, surface(&bd, CB_ANALYTIC_PLANE, top, z, x, NULL, range1), 1);
        const int l[1][2] = {{upper, 1}};
        if (!bd.st)
            loop(&bd, ft, 1, l);
    }
    return finish(out, &bd, what);
}

cb_status cb_prim_cylinder(cb_topo_body **out, const cb_frame *f, double radius, double height,
                           int as_nurbs, double tol, cb_error *err)
{
    *out = NULL;
    cb_status st = positive(radius, "cylinder", "radius", err);
    if (!st)
        st = positive(height, "cylinder", "height", err);
    return st ? st
              : solid_of_revolution(out, f, radius, radius, height, as_nurbs, tol, "cylinder", err);
}

cb_status cb_prim_cone(cb_topo_body **out, const cb_frame *f, double r0, double r1, double height,
                       int as_nurbs, double tol, cb_error *err)
{
    *out = NULL;
    if (!(isfinite(r0) && isfinite(r1) && r0 >= 0 && r1 >= 0))
        return cb_error_set(err, CB_ERR_INVALID,
                            "cone: radii %.17g and %.17g must be finite and >= 0", r0, r1);
    if (r0 == r1)
        return cb_error_set(err, CB_ERR_INVALID,
                            "cone: equal radii %.17g give a cylinder (cb_prim_cylinder)", r0);
    cb_status st = positive(height, "cone", "height", err);
    return st ? st : solid_of_revolution(out, f, r0, r1, height, as_nurbs, tol, "cone", err);
}

cb_status cb_prim_torus(cb_topo_body **out, const cb_frame *f, double major_radius,
                        double minor_radius, int as_nurbs, double tol, cb_error *err)
{
    *out = NULL;
    double R = major_radius, r = minor_radius;
    cb_status st = positive(R, "torus", "major radius", err);
    if (!st)
        st = positive(r, "torus", "minor radius", err);
    if (!st && !(r < R))
        st = cb_error_set(err, CB_ERR_INVALID,
                          "torus: minor radius %.17g must be below the major radius %.17g (a "
                          "horn or spindle torus intersects itself)",
                          r, R);
    if (st)
        return st;
    builder bd;
    if ((st = start(&bd, f, as_nurbs, tol, 2 * (R + r), err)))
        return st;
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0}, mx[3] = {-1, 0, 0},
           y[3] = {0, 1, 0}, my[3] = {0, -1, 0};
    double c0[3] = {R, 0, 0}, c1[3] = {-R, 0, 0};
    int p0 = vertex(&bd, R + r, 0, 0), p1 = vertex(&bd, -R - r, 0, 0);
    /* Meridians at u = 0 and u = pi, parameterised by the surface's v. */
    int m0 = conic_edge(&bd, c0, my, x, r, r, p0, p0, 0, 2 * pi);
    int m1 = conic_edge(&bd, c1, y, mx, r, r, p1, p1, 0, 2 * pi);
    int ea = conic_edge(&bd, o, z, x, R + r, R + r, p0, p1, 0, pi);
    int eb = conic_edge(&bd, o, z, x, R + r, R + r, p1, p0, pi, 2 * pi);
    double prm[4] = {R, r, 0, 0};
    double ra[4] = {0, pi, 0, 2 * pi}, rb[4] = {pi, 2 * pi, 0, 2 * pi};
    int fa = face(&bd, surface(&bd, CB_ANALYTIC_TORUS, o, z, x, prm, ra), 1);
    const int la[4][2] = {{ea, 1}, {m1, 1}, {ea, 0}, {m0, 0}};
    if (!bd.st)
        loop(&bd, fa, 4, la);
    int fb = face(&bd, surface(&bd, CB_ANALYTIC_TORUS, o, z, x, prm, rb), 1);
    const int lb[4][2] = {{eb, 1}, {m0, 1}, {eb, 0}, {m1, 0}};
    if (!bd.st)
        loop(&bd, fb, 4, lb);
    return finish(out, &bd, "torus");
}
