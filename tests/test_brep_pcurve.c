/* Pcurves (brep/topo_pcurve.c), their validation and the orientation of closed shells
 * (brep/topo_orient.c): the shipped models with pcurves computed from scratch and compared
 * with the files' own, flipped bodies, and bodies built by hand (a cylinder with its seam, a
 * sphere with its poles, a plate with a circular hole). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brep/mass.h"
#include "brep/tess.h"
#include "brep/topo.h"
#include "check.h"
#include "io/step.h"

static const double PI = 3.14159265358979323846;

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int face_surface(const cb_topo_body *b, int c)
{
    return b->faces[b->loops[b->coedges[c].loop].face].surface;
}

/* Largest |S(pc(t)) - C(t)| over 33 parameters of every coedge (the convention: the pcurve
 * shares the edge's parameter), and the largest distance of the same edge points from the
 * surface, which bounds what any pcurve can reach. */
static void pcurve_deviation(double *dev, double *gap, const cb_topo_body *b)
{
    *dev = *gap = 0;
    for (int c = 0; c < b->n_coedges; c++) {
        const cb_topo_coedge *co = &b->coedges[c];
        const cb_topo_edge *e = &b->edges[co->edge];
        cb_topo_inverter inv;
        cb_error err;
        if (cb_topo_inverter_init(&inv, &b->surfaces[face_surface(b, c)], b->tol, &err)) {
            CHECK(0, "inverter: %s", err.msg);
            continue;
        }
        for (int k = 0; k <= 32; k++) {
            double t = e->t0 + (e->t1 - e->t0) * k / 32, w[3], p[3], q[3], uv[2];
            cb_topo_curve_eval(w, &b->pcurves[co->pcurve], t);
            cb_topo_inverter_eval(q, &inv, w[0], w[1]);
            cb_topo_curve_eval(p, &b->curves[e->curve], t);
            *dev = fmax(*dev, cb_vec3_dist(p, q));
            *gap = fmax(*gap, cb_topo_inverter_invert(uv, &inv, p, w));
        }
        cb_topo_inverter_clear(&inv);
    }
}

/* Every face's same_sense toggled: the normals all turn inward. */
/* Turns the body inside out: each face's sense and the direction of its loops reversed
 * (cb_topo_shell_reverse), so the loops still run round the same region. */
static void flip_faces(cb_topo_body *b)
{
    for (int k = 0; k < b->n_shells; k++)
        cb_topo_shell_reverse(b, k);
    cb_error err;
    cb_status st = cb_topo_body_index(b, &err);
    CHECK(st == CB_OK, "index after reversal: %s", err.msg);
}

static int reports(const cb_topo_report *r, const char *what)
{
    for (int k = 0; k < r->n; k++)
        if (strstr(r->items[k], what))
            return 1;
    return 0;
}

/* Computed pcurves against the file's, in (u, v): 17 points of each computed pcurve, moved by
 * the whole periods that bring its start onto the file pcurve's start, projected onto the file
 * pcurve. (Files lift single pcurves freely, e.g. a sphere's latitude by 2 pi, so the shift is
 * per coedge; the seam sides of the computed pcurves are checked on the bodies built by hand.)
 * Coedges whose file pcurve misses its own edge (linkrods has some) are counted, not
 * compared. */
static void compare_with_file(double *worst, int *skipped, const cb_topo_body *b,
                              const int *file_pc, double tol)
{
    *worst = 0;
    *skipped = 0;
    for (int c = 0; c < b->n_coedges; c++) {
        const cb_topo_coedge *co = &b->coedges[c];
        const cb_topo_edge *e = &b->edges[co->edge];
        if (file_pc[c] < 0)
            continue;
        cb_topo_inverter inv;
        cb_error err;
        if (cb_topo_inverter_init(&inv, &b->surfaces[face_surface(b, c)], tol, &err))
            continue;
        cb_topo_body tmp = *b;
        cb_topo_coedge alt = *co;
        alt.pcurve = file_pc[c];
        tmp.coedges = &alt - c; /* only index c is read */
        double s0, s1;
        double gap = cb_topo_coedge_pcurve_range(&s0, &s1, &tmp, c, &inv, tol);
        const cb_topo_curve *fp = &b->pcurves[file_pc[c]], *mp = &b->pcurves[co->pcurve];
        if (gap > tol) {
            (*skipped)++;
            cb_topo_inverter_clear(&inv);
            continue;
        }
        int forward = co->sense == e->same_sense;
        double fs[3], ms[3], shift[2] = {0, 0};
        cb_topo_pcurve_eval(fs, fp, s0);
        cb_topo_curve_eval(ms, mp, forward ? e->t0 : e->t1);
        for (int i = 0; i < 2; i++)
            if (inv.lift[i] > 0)
                shift[i] = inv.lift[i] * round((fs[i] - ms[i]) / inv.lift[i]);
        double lo = -HUGE_VAL, hi = HUGE_VAL;
        if (fp->kind == CB_CURVE_NURBS)
            cb_nurbs_curve_domain(fp->nurbs, &lo, &hi);
        for (int k = 0; k <= 16; k++) {
            double w[3], q[3], s;
            cb_topo_curve_eval(w, mp, e->t0 + (e->t1 - e->t0) * k / 16);
            w[0] += shift[0];
            w[1] += shift[1];
            w[2] = 0;
            cb_topo_curve_project(&s, fp, w, lo, hi);
            cb_topo_curve_eval(q, fp, s);
            *worst = fmax(*worst, hypot(q[0] - w[0], q[1] - w[1]));
        }
        cb_topo_inverter_clear(&inv);
    }
}

typedef struct {
    const char *file;
    double tol;    /* validation tolerance; 0: the file's own */
    double uv_tol; /* agreement with the file's pcurves in (u, v) */
} model_case;

static void test_model(const model_case *m)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/%s", shared_dir(), m->file);
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_step_read(&b, path, &err);
    CHECK(st == CB_OK && b, "%s: %s", m->file, err.msg);
    if (!b)
        return;
    double tol = m->tol > 0 ? m->tol : b->tol;
    int *file_pc = malloc((size_t)b->n_coedges * sizeof *file_pc), with_file = 0;
    for (int c = 0; c < b->n_coedges; c++) {
        file_pc[c] = b->coedges[c].pcurve;
        with_file += file_pc[c] >= 0;
        b->coedges[c].pcurve = -1;
    }
    double t0 = now();
    st = cb_topo_compute_pcurves(b, b->tol, &err);
    double t1 = now();
    CHECK(st == CB_OK, "%s: compute: %s", m->file, err.msg);
    int kinds[4] = {0, 0, 0, 0};
    for (int c = 0; c < b->n_coedges; c++) {
        CHECK(b->coedges[c].pcurve >= 0, "%s: coedge %d has no pcurve", m->file, c);
        if (b->coedges[c].pcurve >= 0)
            kinds[b->pcurves[b->coedges[c].pcurve].kind]++;
    }
    if (st) {
        free(file_pc);
        cb_topo_body_free(b);
        return;
    }
    double dev, gap;
    pcurve_deviation(&dev, &gap, b);
    /* The fit meets the foot points within b->tol; the edge itself lies up to gap off. */
    CHECK(dev <= gap + b->tol * 1.01, "%s: pcurves %g off their edges (edges %g off the surfaces)",
          m->file, dev, gap);
    cb_topo_report r;
    cb_topo_report_init(&r);
    st = cb_topo_validate(&r, b, tol, 9, &err);
    CHECK(st == CB_OK && r.n == 0, "%s: %d problems, first: %s", m->file, r.n,
          r.n ? r.items[0] : err.msg);
    cb_topo_report_clear(&r);
    double vol = 0;
    st = cb_topo_shell_volume(&vol, b, 0, 64, tol, &err);
    CHECK(st == CB_OK && vol > 0, "%s: shell volume %g (%s)", m->file, vol, st ? err.msg : "");
    double file_uv = 0;
    int skipped = 0;
    if (with_file) {
        compare_with_file(&file_uv, &skipped, b, file_pc, tol);
        CHECK(file_uv <= m->uv_tol, "%s: computed pcurves %g from the file's in (u, v)", m->file,
              file_uv);
    }
    flip_faces(b);
    cb_topo_report_init(&r);
    cb_topo_validate(&r, b, tol, 9, &err);
    CHECK(reports(&r, "shell 0: inward oriented"), "%s flipped: %d problems, first: %s",
          m->file, r.n, r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    printf("%-20s pcurves in %6.1f ms (line %d, circle %d, ellipse %d, bspline %d): max "
           "|S(pc(t)) - C(t)| %.3g (edges off surfaces %.3g); volume %.6g; ",
           m->file, 1e3 * (t1 - t0), kinds[0], kinds[1], kinds[2], kinds[3], dev, gap, vol);
    if (with_file)
        printf("vs file pcurves %.3g in (u, v), %d file pcurves missing their edges\n", file_uv,
               skipped);
    else
        printf("no file pcurves\n");
    free(file_pc);
    cb_topo_body_free(b);
}

static void test_models(void)
{
    static const model_case cases[] = {
        /* The file has no pcurves: the reader computed them, and computing again must agree. */
        {"trj5_k1-al-214.stp", 0, 1e-9},
        /* Edges up to 4.1e-4 off their surfaces; see tests/test_io_step.c. Its B-spline
         * surfaces nearly collapse along a boundary, where u barely moves the point (0.1 in u
         * for 0.014 in 3D), so (u, v) agreement is loose there. */
        {"linkrods.step", 5e-4, 0.05},
        /* Pcurves fitted to 2e-5 (the file's tolerance) on spheres of radius ~20. */
        {"ujoint_fork.step", 0, 1e-4},
        {"ujoint_cross.step", 0, 1e-6},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++)
        test_model(&cases[k]);
}

/* ---------------------------------------------------------------- bodies by hand ----------- */

static int vertex(cb_topo_body *b, double x, double y, double z)
{
    int v = cb_topo_body_add_vertex(b);
    b->vertices[v].p[0] = x;
    b->vertices[v].p[1] = y;
    b->vertices[v].p[2] = z;
    return v;
}

static void frame(cb_frame *f, const double o[3], const double z[3], const double x[3])
{
    cb_error err;
    CHECK(cb_frame_make(f, o, z, x, &err) == CB_OK, "frame: %s", err.msg);
}

static int edge(cb_topo_body *b, int curve, int v0, int v1, double t0, double t1)
{
    int e = cb_topo_body_add_edge(b);
    cb_topo_edge *ed = &b->edges[e];
    ed->curve = curve;
    ed->v[0] = v0;
    ed->v[1] = v1;
    ed->t0 = t0;
    ed->t1 = t1;
    ed->same_sense = 1;
    ed->tol = 1e-9;
    return e;
}

static int line_edge(cb_topo_body *b, int v0, int v1)
{
    int c = cb_topo_body_add_curve(b);
    const double *p = b->vertices[v0].p, *q = b->vertices[v1].p;
    double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double len = cb_vec3_norm(d);
    b->curves[c].kind = CB_CURVE_LINE;
    frame(&b->curves[c].frame, p, d, NULL);
    b->curves[c].r1 = len;
    return edge(b, c, v0, v1, 0, 1);
}

static int circle_edge(cb_topo_body *b, const double o[3], const double z[3], const double x[3],
                       double r, int v0, int v1, double t0, double t1)
{
    int c = cb_topo_body_add_curve(b);
    b->curves[c].kind = CB_CURVE_CIRCLE;
    frame(&b->curves[c].frame, o, z, x);
    b->curves[c].r1 = b->curves[c].r2 = r; /* a circle is the ellipse with r1 = r2 */
    return edge(b, c, v0, v1, t0, t1);
}

/* Starts face f on surface s; then loops with loop(). */
static int face(cb_topo_body *b, int s, int same_sense)
{
    int f = cb_topo_body_add_face(b);
    b->faces[f].surface = s;
    b->faces[f].same_sense = same_sense;
    b->faces[f].first = b->n_loops;
    b->faces[f].shell = 0;
    return f;
}

/* A loop of face f from n (edge, sense) pairs. */
static void loop(cb_topo_body *b, int f, int n, const int (*es)[2])
{
    int l = cb_topo_body_add_loop(b);
    b->loops[l].first = b->n_coedges;
    b->loops[l].count = n;
    b->loops[l].face = f;
    b->loops[l].outer = b->faces[f].count == 0;
    for (int k = 0; k < n; k++) {
        int c = cb_topo_body_add_coedge(b);
        b->coedges[c].edge = es[k][0];
        b->coedges[c].sense = es[k][1];
        b->coedges[c].pcurve = -1;
        b->coedges[c].loop = l;
    }
    b->faces[f].count++;
}

static void finish(cb_topo_body *b, int closed)
{
    int s = cb_topo_body_add_shell(b);
    b->shells[s].first = 0;
    b->shells[s].count = b->n_faces;
    b->shells[s].closed = closed;
    b->shells[s].solid = closed ? 0 : -1;
    if (closed) {
        int so = cb_topo_body_add_solid(b);
        b->solids[so].first = 0;
        b->solids[so].count = 1;
    }
    b->tol = 1e-9;
    cb_error err;
    CHECK(cb_topo_body_index(b, &err) == CB_OK, "index: %s", err.msg);
}

static int analytic_surface(cb_topo_body *b, cb_analytic_kind kind, const double o[3], double r)
{
    int s = cb_topo_body_add_surface(b);
    cb_frame f;
    double z[3] = {0, 0, 1};
    frame(&f, o, z, NULL);
    cb_error err;
    cb_status st = CB_OK;
    b->surfaces[s].kind = CB_SURFACE_ANALYTIC;
    switch (kind) {
    case CB_ANALYTIC_PLANE: st = cb_analytic_plane(&b->surfaces[s].analytic, &f, &err); break;
    case CB_ANALYTIC_CYLINDER:
        st = cb_analytic_cylinder(&b->surfaces[s].analytic, &f, r, &err);
        break;
    case CB_ANALYTIC_CONE:
        st = cb_analytic_cone(&b->surfaces[s].analytic, &f, r, PI / 4, &err);
        break;
    default: st = cb_analytic_sphere(&b->surfaces[s].analytic, &f, r, &err); break;
    }
    CHECK(st == CB_OK, "surface: %s", err.msg);
    return s;
}

/* (u, v) of coedge c at its start (end = 0) or end. */
static void coedge_uv(double uv[3], const cb_topo_body *b, int c, int end)
{
    const cb_topo_coedge *co = &b->coedges[c];
    const cb_topo_edge *e = &b->edges[co->edge];
    int at_t1 = (co->sense == e->same_sense) == end;
    cb_topo_curve_eval(uv, &b->pcurves[co->pcurve], at_t1 ? e->t1 : e->t0);
}

/* Computes the pcurves, validates, checks the volume, then the flipped body. */
static void check_solid(cb_topo_body *b, const char *what, double volume)
{
    cb_error err;
    cb_status st = cb_topo_compute_pcurves(b, 1e-9, &err);
    CHECK(st == CB_OK, "%s: %s", what, err.msg);
    if (st)
        return;
    double dev, gap;
    pcurve_deviation(&dev, &gap, b);
    CHECK(dev < 1e-9, "%s: pcurves %g off their edges", what, dev);
    cb_topo_report r;
    cb_topo_report_init(&r);
    st = cb_topo_validate(&r, b, 0, 9, &err);
    CHECK(st == CB_OK && r.n == 0, "%s: %d problems, first: %s", what, r.n,
          r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    double vol = 0;
    st = cb_topo_shell_volume(&vol, b, 0, 64, 1e-9, &err);
    CHECK(st == CB_OK && fabs(vol - volume) < 0.02 * volume, "%s: volume %g, expected %g", what,
          vol, volume);
    printf("%-20s max |S(pc(t)) - C(t)| %.3g, volume %.6g (exact %.6g)\n", what, dev, vol, volume);
    flip_faces(b);
    cb_topo_report_init(&r);
    cb_topo_validate(&r, b, 0, 9, &err);
    CHECK(r.n == 1 && reports(&r, "shell 0: inward oriented"), "%s flipped: %d problems: %s",
          what, r.n, r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    flip_faces(b); /* back as built, for the callers' checks of its coedges */
}

/* A solid of revolution about z between heights h[0] < h[1]: a side face on a cylinder or cone
 * (radius 1 at z = 0, a cone's semi-angle 45 degrees; the face's normal S_u x S_v outward)
 * bounded by the circles of radii r[0], r[1] at those heights, counter-clockwise about z over
 * [t0, t0 + 2 pi] from their vertices at angle t0, and by the seam line between the vertices,
 * used twice (coedges 0..3: bottom, seam up, top back, seam down); and two discs. Returns the
 * side face's surface. */
static int revolved_solid(cb_topo_body *b, cb_analytic_kind kind, const double h[2],
                          const double r[2], double t0)
{
    double o[3] = {0, 0, 0}, lo[3] = {0, 0, h[0]}, hi[3] = {0, 0, h[1]}, z[3] = {0, 0, 1},
           x[3] = {1, 0, 0};
    int a = vertex(b, r[0] * cos(t0), r[0] * sin(t0), h[0]);
    int c = vertex(b, r[1] * cos(t0), r[1] * sin(t0), h[1]);
    int bottom = circle_edge(b, lo, z, x, r[0], a, a, t0, t0 + 2 * PI);
    int upper = circle_edge(b, hi, z, x, r[1], c, c, t0, t0 + 2 * PI);
    int seam = line_edge(b, a, c);
    int side = analytic_surface(b, kind, o, 1);
    int f = face(b, side, 1);
    const int side_loop[4][2] = {{bottom, 1}, {seam, 1}, {upper, 0}, {seam, 0}};
    loop(b, f, 4, side_loop);
    f = face(b, analytic_surface(b, CB_ANALYTIC_PLANE, lo, 0), 0);
    const int bl[1][2] = {{bottom, 0}}, tl[1][2] = {{upper, 1}};
    loop(b, f, 1, bl);
    f = face(b, analytic_surface(b, CB_ANALYTIC_PLANE, hi, 0), 1);
    loop(b, f, 1, tl);
    finish(b, 1);
    return side;
}

/* Radius 1, height 2: side face with the seam line used twice, two discs. */
static void test_cylinder(void)
{
    cb_topo_body *b = cb_topo_body_new();
    const double h[2] = {0, 2}, r[2] = {1, 1};
    revolved_solid(b, CB_ANALYTIC_CYLINDER, h, r, 0);
    check_solid(b, "cylinder", 2 * PI);
    /* check_solid leaves the body as built: the seam's two coedges must be on the two sides,
     * u = 2 pi going up after the bottom circle, u = 0 coming down. */
    double s1[3], s3[3];
    coedge_uv(s1, b, 1, 0);
    coedge_uv(s3, b, 3, 0);
    CHECK(fabs(s1[0] - 2 * PI) < 1e-12 && fabs(s3[0]) < 1e-12 && fabs(s1[1]) < 1e-12 &&
              fabs(s3[1] - 2) < 1e-12,
          "cylinder seam sides: up at (%g, %g), down from (%g, %g)", s1[0], s1[1], s3[0], s3[1]);
    CHECK(b->pcurves[b->coedges[0].pcurve].kind == CB_CURVE_LINE &&
              b->pcurves[b->coedges[4].pcurve].kind == CB_CURVE_CIRCLE,
          "cylinder: circle on the side not a line or disc rim not a circle");
    cb_topo_body_free(b);
}

/* A frustum on the far nappe of the cone (r + v tan a) (cos u, sin u) + v z (r = 1, a = 45
 * degrees): its side face between v = -4 and v = -2, where r + v tan a runs from -3 to -1, so
 * each point lies across the axis from the generator of its angle u (screw.step's face 6 lies
 * so). The inversion finds every point of that nappe, the pcurves come out at v in [-4, -2], and
 * the frustum's volume, 26 pi / 3, holds. (The feet were taken on the near generator: the seam's
 * pcurve collapsed to the apex, 10.6 from its edge in screw.step.) */
static void test_cone_far_nappe(void)
{
    cb_topo_body *b = cb_topo_body_new();
    const double h[2] = {-4, -2}, r[2] = {3, 1};
    int side = revolved_solid(b, CB_ANALYTIC_CONE, h, r, PI);
    cb_topo_inverter inv;
    cb_error err;
    cb_status st = cb_topo_inverter_init(&inv, &b->surfaces[side], 1e-9, &err);
    CHECK(st == CB_OK, "cone: %s", err.msg);
    if (st) {
        cb_topo_body_free(b);
        return;
    }
    double worst = 0;
    for (int i = 0; i < 16; i++) {
        double uv[2], q[3], want[2] = {0.3 + 0.37 * i, -4 + 0.125 * i};
        cb_topo_inverter_eval(q, &inv, want[0], want[1]);
        worst = fmax(worst, cb_topo_inverter_invert(uv, &inv, q, NULL) +
                                fabs(uv[1] - want[1]));
    }
    CHECK(worst < 1e-12, "cone far nappe: inversion off by %g", worst);
    cb_topo_inverter_clear(&inv);
    check_solid(b, "cone far nappe", 26 * PI / 3);
    double v_lo = HUGE_VAL, v_hi = -HUGE_VAL;
    for (int k = 0; k < 4; k++)
        for (int end = 0; end < 2; end++) {
            double uv[3];
            coedge_uv(uv, b, k, end);
            v_lo = fmin(v_lo, uv[1]);
            v_hi = fmax(v_hi, uv[1]);
        }
    CHECK(fabs(v_lo + 4) < 1e-12 && fabs(v_hi + 2) < 1e-12,
          "cone far nappe: side face's pcurves over v in [%g, %g], not [-4, -2]", v_lo, v_hi);
    cb_topo_body_free(b);
}

/* The cylinder of test_cylinder with its circles' parameters running over [2 pi, 4 pi] and the
 * side face's pcurves of them given as B-spline lines u = s over [0, 2 pi] (as
 * trj2_io1-ec-214.stp writes a hole): the pcurves do not follow the edges' parameters, so each
 * coedge's part is found by projection, and each closed edge takes its pcurve whole, the way
 * round its coedge runs: the upper circle, used against its direction, from u = 2 pi to 0. The
 * volume is the cylinder's. (Both ends of the pcurve are one point on the surface, and the two
 * projections could not tell them apart: here both circles came out empty and the volume a third
 * of the cylinder's; in trj2_io1-ec-214.stp a circle ran the wrong way, its loop wound twice
 * round the surface, and the volume was refused.) */
static void test_closed_edge_period_pcurve(void)
{
    cb_topo_body *b = cb_topo_body_new();
    const double h[2] = {0, 2}, radii[2] = {1, 1};
    int side = revolved_solid(b, CB_ANALYTIC_CYLINDER, h, radii, 2 * PI);
    cb_error err;
    CHECK(cb_topo_compute_pcurves(b, 1e-9, &err) == CB_OK, "period pcurve: %s", err.msg);
    for (int k = 0; k < 3; k += 2) {
        int p = cb_topo_body_add_pcurve(b);
        double knots[4] = {0, 0, 2 * PI, 2 * PI}, pts[6] = {0, k, 0, 2 * PI, k, 0};
        b->pcurves[p].kind = CB_CURVE_NURBS;
        CHECK(cb_nurbs_curve_make(b->pcurves[p].nurbs, 1, knots, 4, pts, NULL, 2, &err) == CB_OK,
              "period pcurve: %s", err.msg);
        b->coedges[k].pcurve = p;
    }
    cb_topo_inverter inv;
    cb_status st = cb_topo_inverter_init(&inv, &b->surfaces[side], 1e-9, &err);
    CHECK(st == CB_OK, "inverter: %s", err.msg);
    if (st) {
        cb_topo_body_free(b);
        return;
    }
    double r[2][2];
    for (int k = 0; k < 2; k++)
        cb_topo_coedge_pcurve_range(&r[k][0], &r[k][1], b, 2 * k, &inv, 1e-9);
    cb_topo_inverter_clear(&inv);
    CHECK(r[0][0] == 0 && r[0][1] == 2 * PI && r[1][0] == 2 * PI && r[1][1] == 0,
          "period pcurve: bottom circle over [%g, %g], upper over [%g, %g]", r[0][0], r[0][1],
          r[1][0], r[1][1]);
    cb_mass_props m;
    st = cb_mass_shell(&m, b, 0, 0, NULL, &err);
    CHECK(st == CB_OK && fabs(m.volume - 2 * PI) < 1e-9, "period pcurve: volume %.15g: %s",
          st ? 0.0 : m.volume, st ? err.msg : "");
    cb_topo_body_free(b);
}

/* Unit sphere: one face bounded by the meridian u = 0 from pole to pole, used twice. */
static void test_sphere(void)
{
    cb_topo_body *b = cb_topo_body_new();
    double o[3] = {0, 0, 0}, axis[3] = {0, -1, 0}, x[3] = {1, 0, 0};
    int s = vertex(b, 0, 0, -1), n = vertex(b, 0, 0, 1);
    int mer = circle_edge(b, o, axis, x, 1, s, n, 1.5 * PI, 2.5 * PI);
    int f = face(b, analytic_surface(b, CB_ANALYTIC_SPHERE, o, 1), 1);
    const int l[2][2] = {{mer, 1}, {mer, 0}};
    loop(b, f, 2, l);
    finish(b, 1);
    check_solid(b, "sphere", 4 * PI / 3);
    double a[3], z[3], c[3];
    coedge_uv(a, b, 0, 0);
    coedge_uv(z, b, 0, 1);
    coedge_uv(c, b, 1, 0);
    CHECK(fabs(a[0] - z[0]) < 1e-12 && fabs(a[1] + PI / 2) < 1e-12 && fabs(z[1] - PI / 2) < 1e-12,
          "sphere: meridian from (%g, %g) to (%g, %g)", a[0], a[1], z[0], z[1]);
    CHECK(fabs(fabs(c[0] - a[0]) - 2 * PI) < 1e-12, "sphere: seam uses at u = %g and %g", a[0],
          c[0]);
    cb_topo_body_free(b);
}

/* A hemisphere cap as an open shell, closed at the north pole by a degenerate edge: the pole's
 * pcurve must run along v = pi/2 between the seam's two sides. */
static void test_pole_edge(void)
{
    cb_topo_body *b = cb_topo_body_new();
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, axis[3] = {0, -1, 0}, x[3] = {1, 0, 0};
    int e = vertex(b, 1, 0, 0), n = vertex(b, 0, 0, 1);
    int equator = circle_edge(b, o, z, x, 1, e, e, 0, 2 * PI);
    int mer = circle_edge(b, o, axis, x, 1, e, n, 0, 0.5 * PI);
    int c = cb_topo_body_add_curve(b);
    double pole[6] = {0, 0, 1, 0, 0, 1}, knots[4] = {0, 0, 1, 1};
    cb_error err;
    b->curves[c].kind = CB_CURVE_NURBS;
    CHECK(cb_nurbs_curve_make(b->curves[c].nurbs, 1, knots, 4, pole, NULL, 2, &err) == CB_OK,
          "pole curve: %s", err.msg);
    int degenerate = edge(b, c, n, n, 0, 1);
    int f = face(b, analytic_surface(b, CB_ANALYTIC_SPHERE, o, 1), 1);
    const int l[4][2] = {{equator, 1}, {mer, 1}, {degenerate, 1}, {mer, 0}};
    loop(b, f, 4, l);
    finish(b, 0);
    cb_status st = cb_topo_compute_pcurves(b, 1e-9, &err);
    CHECK(st == CB_OK, "cap: %s", err.msg);
    if (st) {
        cb_topo_body_free(b);
        return;
    }
    double a[3], w[3];
    coedge_uv(a, b, 2, 0);
    coedge_uv(w, b, 2, 1);
    CHECK(fabs(a[1] - PI / 2) < 1e-12 && fabs(w[1] - PI / 2) < 1e-12 &&
              fabs(fabs(a[0] - w[0]) - 2 * PI) < 1e-12,
          "cap: pole pcurve from (%g, %g) to (%g, %g)", a[0], a[1], w[0], w[1]);
    cb_topo_report r;
    cb_topo_report_init(&r);
    st = cb_topo_validate(&r, b, 0, 9, &err);
    CHECK(st == CB_OK && r.n == 0, "cap: %d problems, first: %s", r.n, r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    /* Meshed: the loop runs along the pole line by the degenerate edge, whose ends both lie
     * on it. */
    cb_tess_face_mesh fm;
    memset(&fm, 0, sizeof fm);
    cb_tess_edges es;
    cb_tess_edges_init(&es);
    cb_tess_opts to;
    st = cb_tess_opts_resolve(&to, NULL, b, &err);
    if (!st)
        st = cb_tess_edges_sample(&es, b, &to, NULL, &err);
    if (!st)
        st = cb_tess_face(&fm, b, f, &es, &to, NULL, &err);
    CHECK(st == CB_OK && fm.n_tris > 0, "cap: mesh: %s", st ? err.msg : "no triangles");
    cb_tess_face_mesh_clear(&fm);
    cb_tess_edges_clear(&es);
    cb_topo_body_free(b);
}

/* Square plate [-2, 2]^2 with a hole of radius 1: lines and an exact circle in (u, v). */
static void test_plate(void)
{
    cb_topo_body *b = cb_topo_body_new();
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    int v[4] = {vertex(b, -2, -2, 0), vertex(b, 2, -2, 0), vertex(b, 2, 2, 0),
                vertex(b, -2, 2, 0)};
    int h = vertex(b, 1, 0, 0), e[4];
    for (int k = 0; k < 4; k++)
        e[k] = line_edge(b, v[k], v[(k + 1) % 4]);
    int hole = circle_edge(b, o, z, x, 1, h, h, 0, 2 * PI);
    int f = face(b, analytic_surface(b, CB_ANALYTIC_PLANE, o, 0), 1);
    const int outer[4][2] = {{e[0], 1}, {e[1], 1}, {e[2], 1}, {e[3], 1}}, inner[1][2] = {{hole, 0}};
    loop(b, f, 4, outer);
    loop(b, f, 1, inner);
    finish(b, 0);
    cb_error err;
    cb_status st = cb_topo_compute_pcurves(b, 1e-9, &err);
    CHECK(st == CB_OK, "plate: %s", err.msg);
    if (st) {
        cb_topo_body_free(b);
        return;
    }
    double dev, gap;
    pcurve_deviation(&dev, &gap, b);
    CHECK(dev < 1e-14, "plate: pcurves %g off their edges", dev);
    for (int c = 0; c < 5; c++)
        CHECK(b->pcurves[b->coedges[c].pcurve].kind == (c < 4 ? CB_CURVE_LINE : CB_CURVE_CIRCLE),
              "plate: coedge %d pcurve is a %s", c,
              cb_curve_kind_name(b->pcurves[b->coedges[c].pcurve].kind));
    cb_topo_report r;
    cb_topo_report_init(&r);
    CHECK(cb_topo_validate(&r, b, 0, 9, &err) == CB_OK && r.n == 0, "plate: %d problems: %s",
          r.n, r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    /* A pcurve moved off its edge is reported. */
    cb_topo_curve *pc = &b->pcurves[b->coedges[4].pcurve];
    pc->frame.o[0] += 0.25;
    cb_topo_report_init(&r);
    cb_topo_validate(&r, b, 0, 9, &err);
    CHECK(reports(&r, "coedge 4: pcurve"), "plate, moved hole pcurve: %d problems: %s", r.n,
          r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    pc->frame.o[0] -= 0.25;
    cb_topo_body_free(b);
}

/* A wall along a staircase polyline (degree 1 along it, every inner knot a crease) and 0.1
 * high: the nearest samples of a point on one step just before a corner all lie on the
 * corner's column, where the derivatives are the next step's, which runs across the first:
 * Newton from there cannot move along the step. The inversion starts again on both sides of
 * the crease and finds the point. */
static void test_crease(void)
{
    enum { N = 21 };
    double pts[2 * N * 3], ku[4] = {0, 0, 1, 1}, kv[N + 2];
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < N; j++) {
            double *q = pts + 3 * (i * N + j);
            q[0] = (j + 1) / 2; /* steps alternately along y and x */
            q[1] = j / 2;
            q[2] = 0.1 * i;
        }
    kv[0] = 0;
    for (int j = 0; j < N; j++)
        kv[j + 1] = j;
    kv[N + 1] = N - 1;
    cb_topo_surface S;
    cb_topo_surface_init(&S);
    S.kind = CB_SURFACE_NURBS;
    cb_error err;
    cb_topo_inverter inv;
    cb_status st = cb_nurbs_surface_make(S.nurbs, 1, 1, ku, 4, kv, N + 2, pts, NULL, 2, N, &err);
    if (!st)
        st = cb_topo_inverter_init(&inv, &S, 1e-9, &err);
    CHECK(st == CB_OK, "crease: %s", err.msg);
    if (!st) {
        int bad = 0;
        for (int j = 1; j + 1 < N; j++) {
            /* on step j - 1 .. j, a twentieth before its end at the corner j */
            double w[2] = {0.5, j - 0.05}, p[3], uv[2];
            cb_topo_inverter_eval(p, &inv, w[0], w[1]);
            double d = cb_topo_inverter_invert(uv, &inv, p, NULL);
            if (!(d < 1e-12 && fabs(uv[1] - w[1]) < 1e-9)) {
                if (!bad)
                    CHECK(0, "crease: point at v = %g inverted to v = %g, %g off", w[1], uv[1], d);
                bad++;
            }
        }
        CHECK(bad == 0, "crease: %d of %d points not found", bad, N - 2);
        cb_topo_inverter_clear(&inv);
    }
    cb_topo_surface_clear(&S);
}

/* An edge passing over the concave crease of a V-shaped trough off the surface: a branch of
 * the hyperbola z = sqrt(y^2 + h^2) (a rational quadratic), h above the crease where it
 * crosses it, within h of the trough z = |y| everywhere. Its feet jump from one sheet to the
 * other where it crosses the crease's bisector, so no pcurve follows them within the fitting
 * tolerance; one within the edge's tolerance does (a Boolean's cut curve along an edge of a
 * face lying on another: trj5_k1-al-214 against its copy turned 30 degrees about z). */
static void test_concave_crease(void)
{
    const double h = 1e-4, a = 0.5, Z = sqrt(a * a + h * h), etol = 2e-4;
    double pts[2 * 3 * 3], ku[4] = {0, 0, 1, 1}, kv[5] = {0, 0, 1, 2, 2};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 3; j++) {
            double *q = pts + 3 * (i * 3 + j);
            q[0] = 2.0 * i;
            q[1] = j - 1.0;
            q[2] = fabs(j - 1.0);
        }
    cb_topo_body *b = cb_topo_body_new();
    int s = cb_topo_body_add_surface(b);
    b->surfaces[s].kind = CB_SURFACE_NURBS;
    cb_error err;
    cb_status st = cb_nurbs_surface_make(b->surfaces[s].nurbs, 1, 1, ku, 4, kv, 5, pts, NULL, 2,
                                         3, &err);
    CHECK(st == CB_OK, "concave crease: %s", err.msg);
    if (st) {
        cb_topo_body_free(b);
        return;
    }
    int A = vertex(b, 0.5, -a, Z), B = vertex(b, 1.5, a, Z), D = vertex(b, 1.5, 0, 0),
        E = vertex(b, 1.5, -a, a);
    /* The hyperbola: ends on the trough, the tangents' meeting point, weight Z / h. */
    double cp[9] = {0.5, -a, Z, 1, 0, h * h / Z, 1.5, a, Z}, w[3] = {1, Z / h, 1};
    double kn[6] = {0, 0, 0, 1, 1, 1};
    int cv = cb_topo_body_add_curve(b);
    b->curves[cv].kind = CB_CURVE_NURBS;
    st = cb_nurbs_curve_make(b->curves[cv].nurbs, 2, kn, 6, cp, w, 3, &err);
    CHECK(st == CB_OK, "concave crease: %s", err.msg);
    int eh = edge(b, cv, A, B, 0, 1);
    b->edges[eh].tol = etol;
    int f = face(b, s, 1);
    loop(b, f, 4,
         (const int[][2]){{eh, 1}, {line_edge(b, B, D), 1}, {line_edge(b, D, E), 1},
                          {line_edge(b, E, A), 1}});
    finish(b, 0);
    b->tol = 1e-6;
    st = cb_topo_compute_pcurves(b, b->tol, &err);
    CHECK(st == CB_OK, "concave crease: pcurves: %s", err.msg);
    if (!st) {
        cb_topo_inverter inv;
        CHECK(cb_topo_inverter_init(&inv, &b->surfaces[s], b->tol, &err) == CB_OK, "%s",
              err.msg);
        double worst = 0;
        for (int k = 0; k <= 1000; k++) {
            double t = k / 1000.0, q[3], p[3], uv[3];
            cb_topo_curve_eval(uv, &b->pcurves[b->coedges[0].pcurve], t);
            cb_topo_inverter_eval(q, &inv, uv[0], uv[1]);
            cb_topo_curve_eval(p, &b->curves[cv], t);
            worst = fmax(worst, cb_vec3_dist(p, q));
        }
        /* within the edge's tolerance, and no better than the curve's distance h / sqrt 2 */
        CHECK(worst <= etol && worst >= 0.5 * h, "concave crease: pcurve %.3g off its edge",
              worst);
        cb_topo_inverter_clear(&inv);
    }
    cb_topo_body_free(b);
}

int main(void)
{
    double t0 = now();
    test_plate();
    test_crease();
    test_concave_crease();
    test_cylinder();
    test_cone_far_nappe();
    test_closed_edge_period_pcurve();
    test_sphere();
    test_pole_edge();
    test_models();
    printf("pcurve tests: %.2f s\n", now() - t0);
    return check_report("brep_pcurve");
}
