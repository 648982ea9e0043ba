/* STEP reader (io/step_*.c): the shipped models, synthetic cubes (units, voids, assembly
 * placement, unclamped B-spline edges) and malformed files of every class. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brep/mass.h"
#include "brep/mesh_check.h"
#include "brep/tess.h"
#include "brep/topo.h"
#include "check.h"
#include "io/step.h"
#include "io/step_write.h"

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

static const char *source_dir(void)
{
    const char *d = getenv("COLIBRI_SOURCE");
    return d ? d : ".";
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---------------------------------------------------------------- shipped models ----------- */

typedef struct {
    const char *file;
    double max_edge_tol; /* reference for the largest edge tolerance after reading (Open
                            CASCADE's figure), or 0: no edge raised */
    int faces;
    const char *types[4];
    int counts[4];
} model_case;

static int type_count(const cb_topo_body *b, const char *type)
{
    const char *names[8];
    int counts[8], n = cb_topo_body_surface_types(names, counts, b);
    for (int k = 0; k < n; k++)
        if (!strcmp(names[k], type))
            return counts[k];
    return 0;
}

static void test_model(const model_case *m)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/%s", shared_dir(), m->file);
    cb_topo_body *b = NULL;
    cb_error err;
    cb_error_clear(&err);
    cb_step_stats ts;
    double t0 = now();
    cb_status st = cb_step_read_opt(&b, path, NULL, &ts, &err);
    double t1 = now();
    CHECK(st == CB_OK && b, "%s: %s", m->file, err.msg);
    if (!b)
        return;
    CHECK(b->n_solids == 1 && b->n_shells == 1 && b->shells[0].closed,
          "%s: %d solids, %d shells, not one closed solid", m->file, b->n_solids, b->n_shells);
    CHECK(b->n_faces == m->faces, "%s: %d faces, %d expected", m->file, b->n_faces, m->faces);
    int typed = 0;
    for (int k = 0; k < 4 && m->types[k]; k++) {
        int got = type_count(b, m->types[k]);
        typed += got;
        CHECK(got == m->counts[k], "%s: %d %s faces, %d expected", m->file, got, m->types[k],
              m->counts[k]);
    }
    CHECK(typed == b->n_faces, "%s: faces of unexpected surface types", m->file);
    /* Every edge used twice, with opposite senses, and on both its faces. */
    for (int e = 0; e < b->n_edges; e++) {
        int faces[4], nf = cb_topo_edge_faces(faces, 4, b, e);
        int uses = b->edge_start[e + 1] - b->edge_start[e];
        CHECK(uses == 2 && (nf == 2 || nf == 1), "%s: edge %d has %d uses on %d faces", m->file, e,
              uses, nf);
    }
    cb_topo_report r;
    cb_topo_report_init(&r);
    double t2 = now();
    st = cb_topo_validate(&r, b, 0, 9, &err);
    double t3 = now();
    CHECK(st == CB_OK, "%s: validation failed to run: %s", m->file, err.msg);
    CHECK(r.n == 0, "%s: %d problems at the file's tolerance, first: %s", m->file, r.n,
          r.n ? r.items[0] : "");
    /* Topology and vertices meet the file's own tolerance; edges meet their surfaces within
     * their own tolerances. */
    CHECK(r.max_loop_gap <= b->tol && r.max_edge_vertex <= b->tol,
          "%s: loop gap %g, edge-vertex %g above the file tolerance %g", m->file, r.max_loop_gap,
          r.max_edge_vertex, b->tol);
    CHECK(r.max_edge_surface <= ts.max_edge_tol, "%s: edges %g off their surfaces", m->file,
          r.max_edge_surface);
    /* Edge tolerances: raised only where the file's is not met, never beyond the cap, and the
     * largest within 10% of Open CASCADE's. */
    int raised = 0;
    double largest = 0;
    for (int e = 0; e < b->n_edges; e++) {
        raised += b->edges[e].tol > b->tol;
        largest = fmax(largest, b->edges[e].tol);
        CHECK(b->edges[e].tol >= b->tol && b->edges[e].tol <= fmax(ts.edge_tol_cap, b->tol),
              "%s: edge %d tol %g outside [%g, %g]", m->file, e, b->edges[e].tol, b->tol,
              ts.edge_tol_cap);
    }
    CHECK(raised == ts.edges_tol_raised && largest == ts.max_edge_tol && ts.edges_over_cap == 0,
          "%s: stats say %d raised (%d over the cap), largest %g; the body %d, %g", m->file,
          ts.edges_tol_raised, ts.edges_over_cap, ts.max_edge_tol, raised, largest);
    if (m->max_edge_tol > 0)
        CHECK(raised > 0 && fabs(largest - m->max_edge_tol) <= 0.1 * m->max_edge_tol,
              "%s: %d edges raised, largest tol %g, %g expected within 10%%", m->file, raised,
              largest, m->max_edge_tol);
    else
        CHECK(raised == 0 && largest == b->tol, "%s: %d edges raised, largest tol %g", m->file,
              raised, largest);
    cb_aabb box;
    cb_topo_body_edge_box(&box, b);
    double diag[3] = {box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]};
    CHECK(fabs(ts.edge_tol_cap - CB_STEP_MAX_EDGE_TOL_REL * cb_vec3_norm(diag)) <=
              1e-12 * ts.edge_tol_cap,
          "%s: cap %g", m->file, ts.edge_tol_cap);
    /* A raised tolerance covers its edge between the samples too: 257 samples. (Only where
     * tolerances were raised: on trj5's degree-1 surfaces the projector's Newton search stalls
     * at some creases and reports points of an edge far from a face they lie on.) */
    if (raised) {
        cb_topo_report_clear(&r);
        cb_topo_report_init(&r);
        st = cb_topo_validate(&r, b, 0, 257, &err);
        CHECK(st == CB_OK && r.n == 0, "%s: %d problems at 257 samples, first: %s", m->file,
              r.n, r.n ? r.items[0] : err.msg);
    }
    printf("%-20s parse %6.1f ms, validate %6.1f ms: %d faces, %d edges, %d vertices, "
           "%d pcurves; unit %g mm, tol %g; max edge-surface %.3g, loop gap %.3g, "
           "edge-vertex %.3g; %d edge tolerances raised, largest %.4g (cap %.3g)\n",
           m->file, 1e3 * (t1 - t0), 1e3 * (t3 - t2), b->n_faces, b->n_edges, b->n_vertices,
           b->n_pcurves, b->length_unit_mm, b->tol, r.max_edge_surface, r.max_loop_gap,
           r.max_edge_vertex, raised, largest, ts.edge_tol_cap);
    cb_topo_report_clear(&r);
    cb_topo_body_free(b);
}

static void test_models(void)
{
    static const model_case cases[] = {
        /* Its edges lie up to 1.03e-4 off their faces, within the 2e-4 the file declares. */
        {"trj5_k1-al-214.stp", 0, 39, {"bspline"}, {39}},
        /* Its B-spline edges are approximations lying up to 4.14e-4 (model size 5.6) off the
         * surfaces, twenty times the 2e-5 the file declares; Open CASCADE's reader sets the
         * largest edge tolerance to 4.13e-4. */
        {"linkrods.step", 4.13e-4, 37, {"bspline", "torus", "cylinder", "plane"}, {18, 9, 4, 6}},
        {"ujoint_fork.step", 0, 17, {"plane", "cylinder", "sphere"}, {7, 7, 3}},
        {"ujoint_cross.step", 0, 8, {"plane", "cylinder"}, {4, 4}},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++)
        test_model(&cases[k]);
}

/* The linkrods pcurves are rational B-splines with unclamped knots (1,2,2,2,2,1), which the
 * reader clamps by knot insertion: the clamped curves must still be the circles they were.
 * Each pcurve of a planar face, mapped through the plane, must lie on its edge's 3D curve (the
 * pcurve's parameter is not the circle's angle, so points are compared to the curve, not
 * parameter by parameter). */
static void test_clamped_pcurves(void)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/linkrods.step", shared_dir());
    cb_topo_body *b = NULL;
    cb_error err;
    if (cb_step_read(&b, path, &err)) {
        CHECK(0, "linkrods: %s", err.msg);
        return;
    }
    int checked = 0;
    double worst = 0;
    for (int c = 0; c < b->n_coedges; c++) {
        const cb_topo_coedge *co = &b->coedges[c];
        const cb_topo_surface *s = &b->surfaces[b->faces[b->loops[co->loop].face].surface];
        const cb_topo_curve *pc = co->pcurve >= 0 ? &b->pcurves[co->pcurve] : NULL;
        if (!pc || pc->kind != CB_CURVE_NURBS || s->kind != CB_SURFACE_ANALYTIC ||
            s->analytic.kind != CB_ANALYTIC_PLANE)
            continue;
        const cb_topo_edge *e = &b->edges[co->edge];
        const cb_topo_curve *cv = &b->curves[e->curve];
        double a, z;
        cb_nurbs_curve_domain(pc->nurbs, &a, &z);
        CHECK(pc->nurbs->knots[0] == a && pc->nurbs->knots[pc->nurbs->n + pc->nurbs->deg] == z,
              "linkrods pcurve %d not clamped", co->pcurve);
        for (int k = 0; k <= 16; k++) {
            double uv[3], p[3], t;
            cb_topo_curve_eval(uv, pc, a + (z - a) * k / 16);
            cb_analytic_eval(p, &s->analytic, uv[0], uv[1]);
            worst = fmax(worst, cb_topo_curve_project(&t, cv, p, e->t0, e->t1));
        }
        checked++;
    }
    CHECK(checked > 0, "linkrods: no B-spline pcurve on a plane");
    CHECK(worst < 1e-9, "linkrods: clamped pcurves on planes leave their edge curves by %g", worst);
    printf("linkrods: %d clamped B-spline pcurves on planes lie on their edge curves within %.3g\n",
           checked, worst);
    cb_topo_body_free(b);
}

/* ---------------------------------------------------------------- synthetic cubes ---------- */

typedef struct {
    char *text;
    size_t len, cap;
    int next_id;
} sbuf;

static int emit(sbuf *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int emit(sbuf *s, const char *fmt, ...)
{
    char line[1024];
    int id = s->next_id++;
    int n = snprintf(line, sizeof line, "#%d=", id);
    va_list ap;
    va_start(ap, fmt);
    n += vsnprintf(line + n, sizeof line - (size_t)n, fmt, ap);
    va_end(ap);
    line[n++] = '\n';
    if (s->len + (size_t)n + 1 > s->cap) {
        s->cap = 2 * (s->len + (size_t)n + 1024);
        s->text = realloc(s->text, s->cap);
    }
    memcpy(s->text + s->len, line, (size_t)n);
    s->len += (size_t)n;
    s->text[s->len] = '\0';
    return id;
}

static void raw(sbuf *s, const char *text)
{
    size_t n = strlen(text);
    if (s->len + n + 1 > s->cap) {
        s->cap = 2 * (s->len + n + 1024);
        s->text = realloc(s->text, s->cap);
    }
    memcpy(s->text + s->len, text, n + 1);
    s->len += n;
}

typedef struct {
    const char *unit; /* length unit entity text, e.g. "SI_UNIT(.MILLI.,.METRE.)" */
    int bspline_edge; /* edge 0 as an unclamped quadratic B-spline */
    int with_void;    /* a BREP_WITH_VOIDS with an inner cube */
    double offset[3]; /* assembly placement of the part, 0 for none */
    int assembly;
} cube_opts;

/* Ids of interesting entities of the last cube, for the corruption tests. */
static int id_vertex0, id_line0, id_plane0, id_face0, id_bspline, id_shell, id_edge0;

/* One closed shell of a cube [o, o + size]^3 with outward faces; returns the shell id. */
static int cube_shell(sbuf *s, const double o[3], double size, int bspline_edge)
{
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    static const double normals[6][3] = {{0, 0, -1}, {0, 0, 1},  {0, -1, 0},
                                         {0, 1, 0},  {-1, 0, 0}, {1, 0, 0}};
    double c[8][3];
    int vert[8], edge[8][8];
    memset(edge, 0, sizeof edge);
    for (int i = 0; i < 8; i++) {
        for (int k = 0; k < 3; k++)
            c[i][k] = o[k] + size * ((i >> k) & 1);
        int p = emit(s, "CARTESIAN_POINT('',(%.17g,%.17g,%.17g));", c[i][0], c[i][1], c[i][2]);
        vert[i] = emit(s, "VERTEX_POINT('',#%d);", p);
        if (i == 0)
            id_vertex0 = vert[i];
    }
    int face_ids[6];
    for (int f = 0; f < 6; f++) {
        int oe[4];
        for (int k = 0; k < 4; k++) {
            int a = faces[f][k], b = faces[f][(k + 1) % 4], lo = a < b ? a : b, hi = a < b ? b : a;
            if (!edge[lo][hi]) {
                double d[3];
                for (int j = 0; j < 3; j++)
                    d[j] = (c[hi][j] - c[lo][j]) / size;
                int geom;
                if (bspline_edge && lo == 0 && hi == 1) {
                    /* Uniform knots 0..6, domain [2, 4]: C(2) = c0, C(4) = c1. */
                    int q[4];
                    for (int j = 0; j < 4; j++) {
                        double t = -0.25 + 0.5 * j;
                        q[j] = emit(s, "CARTESIAN_POINT('',(%.17g,%.17g,%.17g));",
                                    c[0][0] + t * size * d[0], c[0][1] + t * size * d[1],
                                    c[0][2] + t * size * d[2]);
                    }
                    geom = id_bspline = emit(s,
                                             "B_SPLINE_CURVE_WITH_KNOTS('',2,(#%d,#%d,#%d,#%d),"
                                             ".UNSPECIFIED.,.F.,.F.,(1,1,1,1,1,1,1),"
                                             "(0.,1.,2.,3.,4.,5.,6.),.UNSPECIFIED.);",
                                             q[0], q[1], q[2], q[3]);
                } else {
                    int p = emit(s, "CARTESIAN_POINT('',(%.17g,%.17g,%.17g));", c[lo][0], c[lo][1],
                                 c[lo][2]);
                    int dir = emit(s, "DIRECTION('',(%g,%g,%g));", d[0], d[1], d[2]);
                    int vec = emit(s, "VECTOR('',#%d,%.17g);", dir, size);
                    geom = emit(s, "LINE('',#%d,#%d);", p, vec);
                    if (!id_line0)
                        id_line0 = geom;
                }
                edge[lo][hi] = emit(s, "EDGE_CURVE('',#%d,#%d,#%d,.T.);", vert[lo], vert[hi], geom);
                if (!id_edge0)
                    id_edge0 = edge[lo][hi];
            }
            oe[k] = emit(s, "ORIENTED_EDGE('',*,*,#%d,%s);", edge[lo][hi], a < b ? ".T." : ".F.");
        }
        int loop = emit(s, "EDGE_LOOP('',(#%d,#%d,#%d,#%d));", oe[0], oe[1], oe[2], oe[3]);
        int bound = emit(s, "FACE_OUTER_BOUND('',#%d,.T.);", loop);
        int po = emit(s, "CARTESIAN_POINT('',(%.17g,%.17g,%.17g));", c[faces[f][0]][0],
                      c[faces[f][0]][1], c[faces[f][0]][2]);
        const double *n = normals[f];
        int ax = emit(s, "DIRECTION('',(%g,%g,%g));", n[0], n[1], n[2]);
        int rf = emit(s, "DIRECTION('',(%g,%g,%g));", fabs(n[0]) > 0 ? 0. : 1.,
                      fabs(n[0]) > 0 ? 1. : 0., 0.);
        int pl = emit(s, "AXIS2_PLACEMENT_3D('',#%d,#%d,#%d);", po, ax, rf);
        int plane = emit(s, "PLANE('',#%d);", pl);
        if (!id_plane0)
            id_plane0 = plane;
        face_ids[f] = emit(s, "ADVANCED_FACE('',(#%d),#%d,.T.);", bound, plane);
        if (!id_face0)
            id_face0 = face_ids[f];
    }
    return emit(s, "CLOSED_SHELL('',(#%d,#%d,#%d,#%d,#%d,#%d));", face_ids[0], face_ids[1],
                face_ids[2], face_ids[3], face_ids[4], face_ids[5]);
}

static char *finish_file(sbuf *sb, int solid, const cube_opts *o);

/* The start of an exchange file, up to DATA. */
static void start_file(sbuf *s)
{
    raw(s, "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('cube /* not a comment */'),'2;1');\n"
           "FILE_NAME('cube','2024-01-01T00:00:00',('it''s me'),(''),'','','');\n"
           "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\n"
           "/* a comment\n   over two lines */\nDATA;\n");
}

/* A complete exchange file holding one cube solid of side 10 at the origin. */
static char *cube_file(const cube_opts *o)
{
    sbuf s = {NULL, 0, 0, 1};
    id_vertex0 = id_line0 = id_plane0 = id_face0 = id_bspline = id_shell = id_edge0 = 0;
    start_file(&s);
    double origin[3] = {0, 0, 0}, inner[3] = {4, 4, 4};
    int shell = id_shell = cube_shell(&s, origin, 10.0, o->bspline_edge);
    int solid;
    if (o->with_void) {
        int in = cube_shell(&s, inner, 2.0, 0);
        int oriented = emit(&s, "ORIENTED_CLOSED_SHELL('',*,#%d,.F.);", in);
        solid = emit(&s, "BREP_WITH_VOIDS('',#%d,(#%d));", shell, oriented);
    } else {
        solid = emit(&s, "MANIFOLD_SOLID_BREP('',#%d);", shell);
    }
    return finish_file(&s, solid, o);
}

/* The units, context and representation of a file whose solid is `solid` (o may place it in
 * an assembly), then the end: returns the file's text. */
static char *finish_file(sbuf *sb, int solid, const cube_opts *o)
{
    sbuf s = *sb;
    int lu = emit(&s, "( LENGTH_UNIT() NAMED_UNIT(*) %s );",
                  o->unit ? o->unit : "SI_UNIT(.MILLI.,.METRE.)");
    int au = emit(&s, "( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );");
    int unc = emit(
        &s,
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#%d,'distance_accuracy_value','');",
        lu);
    int ctx =
        emit(&s,
             "( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#%d)) "
             "GLOBAL_UNIT_ASSIGNED_CONTEXT((#%d,#%d)) REPRESENTATION_CONTEXT('',''));",
             unc, lu, au);
    int z = emit(&s, "DIRECTION('',(0.,0.,1.));"), x = emit(&s, "DIRECTION('',(1.,0.,0.));");
    int o0 = emit(&s, "CARTESIAN_POINT('',(0.,0.,0.));");
    int ax0 = emit(&s, "AXIS2_PLACEMENT_3D('',#%d,#%d,#%d);", o0, z, x);
    int rep = emit(&s, "ADVANCED_BREP_SHAPE_REPRESENTATION('',(#%d,#%d),#%d);", solid, ax0, ctx);
    if (o->assembly) {
        int op =
            emit(&s, "CARTESIAN_POINT('',(%g,%g,%g));", o->offset[0], o->offset[1], o->offset[2]);
        int axp = emit(&s, "AXIS2_PLACEMENT_3D('',#%d,#%d,#%d);", op, z, x);
        int top = emit(&s, "SHAPE_REPRESENTATION('',(#%d),#%d);", axp, ctx);
        int idt = emit(&s, "ITEM_DEFINED_TRANSFORMATION('','',#%d,#%d);", ax0, axp);
        emit(&s,
             "( REPRESENTATION_RELATIONSHIP('','',#%d,#%d) "
             "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#%d) "
             "SHAPE_REPRESENTATION_RELATIONSHIP() );",
             rep, top, idt);
    }
    raw(&s, "ENDSEC;\nEND-ISO-10303-21;\n");
    return s.text;
}

static cb_status read_text(cb_topo_body **b, const char *text, size_t len, cb_error *err)
{
    return cb_step_read_buffer(b, text, len, "cube.stp", err);
}

static int validates(cb_topo_body *b, const char *what)
{
    cb_topo_report r;
    cb_topo_report_init(&r);
    cb_error err;
    cb_status st = cb_topo_validate(&r, b, 0, 9, &err);
    CHECK(st == CB_OK && r.n == 0, "%s: %d problems, first: %s", what, r.n,
          r.n ? r.items[0] : err.msg);
    int ok = st == CB_OK && r.n == 0;
    cb_topo_report_clear(&r);
    return ok;
}

static void test_cubes(void)
{
    cb_error err;
    cb_topo_body *b;
    cube_opts plain = {0};
    char *text = cube_file(&plain);
    cb_status st = read_text(&b, text, strlen(text), &err);
    CHECK(st == CB_OK, "plain cube: %s", err.msg);
    if (!st) {
        CHECK(b->n_solids == 1 && b->n_faces == 6 && b->n_edges == 12 && b->n_vertices == 8 &&
                  b->n_coedges == 24,
              "cube: %d solids %d faces %d edges %d vertices", b->n_solids, b->n_faces, b->n_edges,
              b->n_vertices);
        CHECK(b->length_unit_mm == 1.0 && fabs(b->tol - 1e-7) < 1e-20, "cube: unit %g tol %g",
              b->length_unit_mm, b->tol);
        validates(b, "plain cube");
        /* Queries: each face has 4 neighbours, each vertex 3 edges, each edge 2 faces. */
        int out[8];
        for (int f = 0; f < 6; f++)
            CHECK(cb_topo_face_neighbours(out, 8, b, f) == 4, "face %d neighbours", f);
        for (int v = 0; v < 8; v++)
            CHECK(cb_topo_vertex_edges(out, 8, b, v) == 3, "vertex %d edges", v);
        for (int e = 0; e < 12; e++)
            CHECK(cb_topo_edge_faces(out, 8, b, e) == 2, "edge %d faces", e);
        cb_aabb box;
        cb_topo_body_edge_box(&box, b);
        CHECK(box.lo[0] == 0 && box.hi[2] == 10, "cube box %g .. %g", box.lo[0], box.hi[2]);

        /* A flipped coedge makes the validator report the edge and the open loop. */
        b->coedges[0].sense ^= 1;
        cb_topo_report r;
        cb_topo_report_init(&r);
        cb_topo_validate(&r, b, 0, 5, &err);
        int use = 0, open = 0;
        for (int k = 0; k < r.n; k++) {
            use |= strstr(r.items[k], "both coedges run") != NULL;
            open |= strstr(r.items[k], "is open") != NULL;
        }
        CHECK(use && open, "flipped coedge: %d problems, not both reported", r.n);
        cb_topo_report_clear(&r);
        /* A vertex moved off its edges is reported with the distance. */
        b->coedges[0].sense ^= 1;
        b->vertices[0].p[0] += 0.01;
        cb_topo_report_init(&r);
        cb_topo_validate(&r, b, 0, 5, &err);
        CHECK(r.n > 0 && strstr(r.items[0], "from vertex 0"), "moved vertex: '%s'",
              r.n ? r.items[0] : "");
        cb_topo_report_clear(&r);
        cb_topo_body_free(b);
    }
    free(text);

    static const struct {
        const char *unit;
        double mm;
    } units[] = {{"SI_UNIT(.CENTI.,.METRE.)", 10.0},
                 {"SI_UNIT($,.METRE.)", 1000.0},
                 {"CONVERSION_BASED_UNIT('INCH',#9000)", 25.4}};
    for (size_t k = 0; k < sizeof units / sizeof *units; k++) {
        cube_opts o = {.unit = units[k].unit};
        text = cube_file(&o);
        /* The inch's conversion factor, appended before ENDSEC. */
        char *end = strstr(text, "ENDSEC;\nEND-ISO");
        char tail[512];
        snprintf(tail, sizeof tail,
                 "#9000=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#9001);\n"
                 "#9001=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n%s",
                 end);
        size_t head = (size_t)(end - text);
        char *full = malloc(head + strlen(tail) + 1);
        memcpy(full, text, head);
        strcpy(full + head, tail);
        st = read_text(&b, full, strlen(full), &err);
        CHECK(st == CB_OK && fabs(b->length_unit_mm - units[k].mm) < 1e-12, "unit %s: %s, %g mm",
              units[k].unit, err.msg, st ? 0.0 : b->length_unit_mm);
        /* The tolerance 1e-7 is given in the length unit itself. */
        if (!st)
            CHECK(fabs(b->tol - 1e-7) < 1e-18, "unit %s: tol %g", units[k].unit, b->tol);
        cb_topo_body_free(b);
        free(full);
        free(text);
    }

    cube_opts spline = {.bspline_edge = 1};
    text = cube_file(&spline);
    st = read_text(&b, text, strlen(text), &err);
    CHECK(st == CB_OK, "cube with a B-spline edge: %s", err.msg);
    if (!st) {
        int found = 0;
        for (int c = 0; c < b->n_curves; c++) {
            const cb_topo_curve *cv = &b->curves[c];
            if (cv->kind != CB_CURVE_NURBS)
                continue;
            found = 1;
            double a, z, p[3], q[3];
            cb_nurbs_curve_domain(cv->nurbs, &a, &z);
            cb_topo_curve_eval(p, cv, a);
            cb_topo_curve_eval(q, cv, z);
            CHECK(a == 2.0 && z == 4.0 && cv->nurbs->knots[0] == 2.0 &&
                      cv->nurbs->knots[cv->nurbs->n + 2] == 4.0,
                  "clamped domain [%g, %g]", a, z);
            CHECK(cb_vec3_norm(p) < 1e-14 && fabs(q[0] - 10) < 1e-14 && fabs(q[1]) < 1e-14,
                  "clamped ends (%g %g %g) (%g %g %g)", p[0], p[1], p[2], q[0], q[1], q[2]);
            /* Knot insertion keeps the curve: C(3) = (P1 + P2) / 2 = 5 on the x axis. */
            cb_topo_curve_eval(p, cv, 3.0);
            CHECK(fabs(p[0] - 5) < 1e-14 && fabs(p[1]) < 1e-14, "C(3) = %g", p[0]);
        }
        CHECK(found, "no B-spline edge curve");
        validates(b, "B-spline cube");
        cb_topo_body_free(b);
    }
    free(text);

    cube_opts voids = {.with_void = 1};
    text = cube_file(&voids);
    st = read_text(&b, text, strlen(text), &err);
    CHECK(st == CB_OK && b->n_solids == 1 && b->n_shells == 2 && b->solids[0].count == 2 &&
              b->n_faces == 12,
          "cube with a void: %s", err.msg);
    if (!st) {
        validates(b, "cube with a void");
        /* The void's faces are reversed: their normals point into the void. */
        CHECK(!b->faces[6].same_sense && b->faces[0].same_sense, "void face senses");
        cb_topo_body_free(b);
    }
    free(text);

    /* The same void written inside out (ORIENTED_CLOSED_SHELL .T.: its faces pointing out of
     * the cavity, as some writers do): the reader turns it into its cavity by the sign of its
     * enclosed volume, and likewise an outer shell written inward. */
    for (int outer = 0; outer < 2; outer++) {
        text = cube_file(&voids);
        char *o = strstr(text, "ORIENTED_CLOSED_SHELL"), *fl = o ? strstr(o, ".F.") : NULL;
        if (fl)
            fl[1] = 'T';
        if (outer) /* every face of both cubes reversed */
            for (char *p = text; (p = strstr(p, "ADVANCED_FACE(")) && p < o; p++) {
                char *sense = strstr(p, ".T.);");
                if (sense && sense < o)
                    sense[1] = 'F';
            }
        st = read_text(&b, text, strlen(text), &err);
        CHECK(st == CB_OK && fl, "cube with an inside-out %s: %s", outer ? "solid" : "void",
              err.msg);
        if (!st) {
            validates(b, outer ? "cube written inward" : "void written inside out");
            CHECK(!b->faces[6].same_sense && b->faces[0].same_sense,
                  "inside-out %s: senses %d %d", outer ? "solid" : "void", b->faces[0].same_sense,
                  b->faces[6].same_sense);
            cb_topo_body_free(b);
        }
        free(text);
    }

    cube_opts placed = {.assembly = 1, .offset = {10, 20, 30}};
    text = cube_file(&placed);
    st = read_text(&b, text, strlen(text), &err);
    CHECK(st == CB_OK, "placed cube: %s", err.msg);
    if (!st) {
        const double *p = b->vertices[0].p;
        CHECK(p[0] == 10 && p[1] == 20 && p[2] == 30, "placed vertex 0 at %g %g %g", p[0], p[1],
              p[2]);
        validates(b, "placed cube");
        cb_topo_body_free(b);
    }
    free(text);
}

/* ---------------------------------------------------------------- bad input ---------------- */

/* Line number of the first occurrence of `what` in text (1-based), or 0. */
static int line_of(const char *text, const char *what)
{
    const char *at = strstr(text, what);
    if (!at)
        return 0;
    int line = 1;
    for (const char *p = text; p < at; p++)
        line += *p == '\n';
    return line;
}

/* text with the first `from` replaced by `to`. */
static char *replaced(const char *text, const char *from, const char *to)
{
    const char *at = strstr(text, from);
    CHECK(at != NULL, "test setup: '%s' not in the file", from);
    if (!at)
        at = text + strlen(text);
    size_t head = (size_t)(at - text), fl = at[0] ? strlen(from) : 0;
    char *out = malloc(strlen(text) - fl + strlen(to) + 1);
    memcpy(out, text, head);
    strcpy(out + head, to);
    strcat(out, at + fl);
    return out;
}

/* Writes the text to a file in /tmp and expects cb_step_read to fail with status `want` and a
 * message holding the file name and every one of words. */
static void expect_bad_len(const char *name, const char *text, size_t len, cb_status want,
                           const char *const *words)
{
    char path[] = "/tmp/colibri_step_XXXXXX";
    int fd = mkstemp(path);
    FILE *f = fdopen(fd, "wb");
    fwrite(text, 1, len, f);
    fclose(f);
    cb_topo_body *b = (void *)1;
    cb_error err;
    cb_error_clear(&err);
    double t0 = now();
    cb_status st = cb_step_read(&b, path, &err);
    double dt = now() - t0;
    CHECK(st == want, "%s: status %d, expected %d (%s)", name, st, want, err.msg);
    CHECK(strstr(err.msg, path) && check_msg_has(err.msg, words), "%s: message '%s'", name,
          err.msg);
    CHECK(b == NULL, "%s: body not NULL on failure", name);
    /* A hang guard, not a speed target: bad input must fail fast even under sanitizers. */
    CHECK(dt < 30.0, "%s: took %.1f s", name, dt);
    remove(path);
}

static void expect_bad(const char *name, const char *text, cb_status want, const char *const *words)
{
    expect_bad_len(name, text, strlen(text), want, words);
}

/* Reads text as cube.stp; validates it. NULL (and a failed check) when it does not load. */
static cb_topo_body *read_valid(const char *text, const char *what)
{
    cb_topo_body *b;
    cb_error err;
    cb_status st = text ? read_text(&b, text, strlen(text), &err) : CB_ERR_INVALID;
    CHECK(st == CB_OK, "%s: %s", what, text ? err.msg : "no text");
    if (st)
        return NULL;
    validates(b, what);
    return b;
}

/* Forms real files use: keywords and enumerations in any case, a measure with unit as a
 * complex instance, quotes in strings, B-splines whose knots the form implies, a
 * TRIMMED_CURVE running against its basis. */
static void test_forms(void)
{
    cube_opts plain = {0}, spline = {.bspline_edge = 1};
    char *text = cube_file(&plain), *t1, *t2, *t3, *t4;
    cb_topo_body *b;

    t1 = replaced(text, "HEADER;", "Header;");
    t2 = t1 ? replaced(t1, "ENDSEC;", "EndSec;") : NULL;
    t3 = t2 ? replaced(t2, "DATA;", "data;") : NULL;
    t4 = t3 ? replaced(t3, "MANIFOLD_SOLID_BREP", "Manifold_Solid_Brep") : NULL;
    free(t1);
    free(t2);
    free(t3);
    t1 = t4 ? replaced(t4, "SI_UNIT(.MILLI.,.METRE.)", "si_unit(.centi.,.Metre.)") : NULL;
    if ((b = read_valid(t1, "keywords in lower and mixed case"))) {
        CHECK(b->n_solids == 1 && b->length_unit_mm == 10, "mixed case: %d solids, unit %g mm",
              b->n_solids, b->length_unit_mm);
        cb_topo_body_free(b);
    }
    free(t1);
    free(t4);

    /* (LENGTH_MEASURE_WITH_UNIT() MEASURE_WITH_UNIT(value, unit)
     * UNCERTAINTY_MEASURE_WITH_UNIT(name, description)): 1e-7, not the default 1e-6. */
    t1 = replaced(text, "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),",
                  "(LENGTH_MEASURE_WITH_UNIT() MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),");
    t2 = t1 ? replaced(t1, ",'distance_accuracy_value','');",
                       ") UNCERTAINTY_MEASURE_WITH_UNIT('distance_accuracy_value',''));")
            : NULL;
    if ((b = read_valid(t2, "complex uncertainty measure"))) {
        CHECK(fabs(b->tol - 1e-7) < 1e-20, "complex uncertainty measure: tol %g", b->tol);
        cb_topo_body_free(b);
    }
    free(t1);
    free(t2);

    /* \S\' is a character, not the end of the string; a lone quote not followed by ',' or ')'
     * is taken as text. */
    t1 = replaced(text, "FILE_NAME('cube',", "FILE_NAME('cu\\S\\'be ' n',");
    if ((b = read_valid(t1, "quotes in a string")))
        cb_topo_body_free(b);
    free(t1);

    /* A TRIMMED_CURVE of the first edge's line, against its sense, with the edge's sense
     * flipped to match: the same edge. Ignoring sense_agreement would turn the edge round. */
    char from[64], to[64], trim[160];
    snprintf(from, sizeof from, ",#%d,.T.);", id_line0);
    snprintf(to, sizeof to, ",#900001,.F.);");
    snprintf(trim, sizeof trim,
             "#900001=TRIMMED_CURVE('',#%d,(PARAMETER_VALUE(0.)),(PARAMETER_VALUE(10.)),.F.,"
             ".PARAMETER.);\nENDSEC;\nEND-ISO",
             id_line0);
    t1 = replaced(text, from, to);
    t2 = t1 ? replaced(t1, "ENDSEC;\nEND-ISO", trim) : NULL;
    if ((b = read_valid(t2, "edge on a reversed TRIMMED_CURVE")))
        cb_topo_body_free(b);
    free(t1);
    free(t2);
    free(text);

    /* The B-spline edge (degree 2, 4 points, knots 0 .. 6) in the forms without knots. */
    text = cube_file(&spline);
    const char *knots = ".UNSPECIFIED.,.F.,.F.,(1,1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.,6.),.UNSPECIFIED.)";
    static const struct {
        const char *name, *to;
        double lo, hi; /* the domain the form implies */
    } forms[] = {{"UNIFORM_CURVE", "UNIFORM_CURVE('',2,", 0, 2},
                 {"QUASI_UNIFORM_CURVE", "QUASI_UNIFORM_CURVE('',2,", 0, 2},
                 {"BEZIER_CURVE", "BEZIER_CURVE('',3,", 0, 1}};
    for (size_t k = 0; k < sizeof forms / sizeof *forms; k++) {
        t1 = replaced(text, "B_SPLINE_CURVE_WITH_KNOTS('',2,", forms[k].to);
        t2 = t1 ? replaced(t1, knots, ".UNSPECIFIED.,.F.,.F.)") : NULL;
        if ((b = read_valid(t2, forms[k].name))) {
            int found = 0;
            for (int c = 0; c < b->n_curves; c++)
                if (b->curves[c].kind == CB_CURVE_NURBS) {
                    double lo, hi;
                    cb_nurbs_curve_domain(b->curves[c].nurbs, &lo, &hi);
                    CHECK(lo == forms[k].lo && hi == forms[k].hi, "%s: domain [%g, %g]",
                          forms[k].name, lo, hi);
                    found = 1;
                }
            CHECK(found, "%s: no B-spline edge", forms[k].name);
            cb_topo_body_free(b);
        }
        free(t1);
        free(t2);
    }
    /* The complex instance of the quasi-uniform form. */
    char *at = strstr(text, "B_SPLINE_CURVE_WITH_KNOTS('',2,(");
    if (at) {
        char pts[96];
        const char *p0 = at + strlen("B_SPLINE_CURVE_WITH_KNOTS('',2,");
        size_t n = (size_t)(strchr(p0, ')') - p0 + 1);
        snprintf(pts, sizeof pts, "%.*s", (int)n, p0);
        char head[512], whole[512];
        snprintf(head, sizeof head, "B_SPLINE_CURVE_WITH_KNOTS('',2,%s,%s", pts, knots);
        snprintf(whole, sizeof whole,
                 "(BOUNDED_CURVE() B_SPLINE_CURVE(2,%s,.UNSPECIFIED.,.F.,.F.) CURVE() "
                 "GEOMETRIC_REPRESENTATION_ITEM() QUASI_UNIFORM_CURVE() "
                 "RATIONAL_B_SPLINE_CURVE((1.,1.,1.,1.)) REPRESENTATION_ITEM(''))",
                 pts);
        t1 = replaced(text, head, whole);
        if ((b = read_valid(t1, "complex QUASI_UNIFORM_CURVE")))
            cb_topo_body_free(b);
        free(t1);
    }
    /* A piecewise Bezier form whose point count does not fit its degree is refused, naming
     * the entity. */
    t1 = replaced(text, "B_SPLINE_CURVE_WITH_KNOTS('',2,", "BEZIER_CURVE('',2,");
    t2 = t1 ? replaced(t1, knots, ".UNSPECIFIED.,.F.,.F.)") : NULL;
    cb_error err;
    cb_status st = t2 ? read_text(&b, t2, strlen(t2), &err) : CB_OK;
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "BEZIER_CURVE") &&
              strstr(err.msg, "not a multiple of 2"),
          "Bezier form of 4 points of degree 2: %d %s", st, st ? err.msg : "");
    if (!st)
        cb_topo_body_free(b);
    free(t1);
    free(t2);
    free(text);
}

/* The cube with the line of its first edge moved by dz (its vertices stay): the edge leaves
 * the face z = 0 and its vertices by |dz|. Returns the body (NULL on a read error) and the
 * index of the moved edge in *moved. */
static cb_topo_body *cube_moved_edge(double dz, const cb_step_options *opt, int *moved,
                                     cb_step_stats *ts)
{
    cube_opts plain = {0};
    char *text = cube_file(&plain), from[64], to[160];
    int p, v;
    snprintf(from, sizeof from, "#%d=LINE('',#", id_line0);
    const char *at = strstr(text, from);
    CHECK(at && sscanf(at + strlen(from) - 1, "#%d,#%d", &p, &v) == 2, "test setup: line #%d",
          id_line0);
    snprintf(from, sizeof from, "#%d=LINE('',#%d,#%d);", id_line0, p, v);
    snprintf(to, sizeof to, "#99001=CARTESIAN_POINT('',(0.,0.,%.17g));\n#%d=LINE('',#99001,#%d);",
             dz, id_line0, v);
    char *t = replaced(text, from, to);
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_step_read_buffer_opt(&b, t, strlen(t), "cube.stp", opt, ts, &err);
    CHECK(st == CB_OK, "cube with a moved edge: %s", err.msg);
    *moved = -1;
    for (int e = 0; b && e < b->n_edges; e++) {
        const cb_topo_curve *c = &b->curves[b->edges[e].curve];
        if (c->kind == CB_CURVE_LINE && c->frame.o[2] == dz)
            *moved = e;
    }
    CHECK(!b || *moved >= 0, "moved edge not found");
    free(t);
    free(text);
    return b;
}

/* Edge tolerances on import: an edge off its face by half the cap is raised to its deviation
 * (+5%) and alone; one off by ten times the cap keeps the file's tolerance and is reported. */
static void test_edge_tolerances(void)
{
    /* The edge box of the cube of side 10 (the moved edge adds a sliver to it). */
    double cap = CB_STEP_MAX_EDGE_TOL_REL * sqrt(300.0);
    cb_step_stats ts;
    int e;
    cb_topo_body *b = cube_moved_edge(-0.5 * cap, NULL, &e, &ts);
    if (b && e >= 0) {
        double want = CB_STEP_EDGE_TOL_MARGIN * 0.5 * cap;
        CHECK(ts.edges_tol_raised == 1 && ts.edges_over_cap == 0 &&
                  fabs(b->edges[e].tol - want) <= 1e-3 * want && ts.max_edge_tol == b->edges[e].tol,
              "half the cap: %d raised, %d over, edge %d tol %g, %g expected", ts.edges_tol_raised,
              ts.edges_over_cap, e, b->edges[e].tol, want);
        CHECK(fabs(ts.edge_tol_cap - cap) <= 1e-3 * cap, "cap %g, %g expected", ts.edge_tol_cap,
              cap);
        for (int k = 0; k < b->n_edges; k++)
            CHECK(k == e || b->edges[k].tol == b->tol, "edge %d raised to %g", k,
                  b->edges[k].tol);
        validates(b, "cube with an edge half the cap off");
        cb_topo_body_free(b);
    }
    /* Without the raise (cap 0) the same file is invalid. */
    cb_step_options none;
    cb_step_options_init(&none);
    CHECK(none.max_edge_tol_rel == CB_STEP_MAX_EDGE_TOL_REL, "default cap %g",
          none.max_edge_tol_rel);
    none.max_edge_tol_rel = 0;
    b = cube_moved_edge(-0.5 * cap, &none, &e, &ts);
    if (b) {
        cb_topo_report r;
        cb_topo_report_init(&r);
        cb_error err;
        cb_topo_validate(&r, b, 0, 9, &err);
        CHECK(ts.edges_tol_raised == 0 && r.n > 0, "cap 0: %d raised, %d problems",
              ts.edges_tol_raised, r.n);
        cb_topo_report_clear(&r);
        cb_topo_body_free(b);
    }
    b = cube_moved_edge(-10 * cap, NULL, &e, &ts);
    if (b && e >= 0) {
        CHECK(ts.edges_tol_raised == 0 && ts.edges_over_cap == 1 && b->edges[e].tol == b->tol,
              "ten times the cap: %d raised, %d over, edge tol %g", ts.edges_tol_raised,
              ts.edges_over_cap, b->edges[e].tol);
        cb_topo_report r;
        cb_topo_report_init(&r);
        cb_error err;
        cb_status st = cb_topo_validate(&r, b, 0, 9, &err);
        char off[64], vertex[64];
        snprintf(off, sizeof off, "edge %d: %.3g off the plane surface of face", e, 10 * cap);
        snprintf(vertex, sizeof vertex, "edge %d: curve start is %.3g from vertex", e, 10 * cap);
        int named_off = 0, named_vertex = 0;
        for (int k = 0; k < r.n; k++) {
            named_off |= strstr(r.items[k], off) == r.items[k];
            named_vertex |= strstr(r.items[k], vertex) == r.items[k];
        }
        CHECK(st == CB_OK && named_off && named_vertex, "ten times the cap: %d problems, '%s' "
              "and '%s' not both among them (first: %s)", r.n, off, vertex,
              r.n ? r.items[0] : "");
        cb_topo_report_clear(&r);
        cb_topo_body_free(b);
    }
}

static void test_bad_files(void)
{
    cube_opts spline = {.bspline_edge = 1};
    char *cube = cube_file(&spline), *t, a[64], b[64], c[64];
    char line[32];

    expect_bad("empty", "", CB_ERR_PARSE, (const char *const[]){"empty file", NULL});
    expect_bad("blank", " \n\n", CB_ERR_PARSE, (const char *const[]){"empty file", NULL});
    expect_bad("not step", "solid cube\nfacet normal 0 0 1\n", CB_ERR_PARSE,
               (const char *const[]){":1:", "not a STEP file", NULL});
    {
        char garbage[256];
        for (int k = 0; k < 256; k++)
            garbage[k] = (char)(k * 37 + 11);
        expect_bad_len("binary garbage", garbage, sizeof garbage, CB_ERR_PARSE,
                       (const char *const[]){":1:", NULL});
        /* Garbage in the middle of the DATA section names the entity it interrupts. */
        snprintf(a, sizeof a, "#%d=VERTEX_POINT(", id_vertex0);
        snprintf(b, sizeof b, "#%d=VERTEX_POINT(\x01\xff", id_vertex0);
        t = replaced(cube, a, b);
        snprintf(line, sizeof line, ":%d:", line_of(cube, a));
        snprintf(c, sizeof c, "#%d VERTEX_POINT", id_vertex0);
        expect_bad("garbage in data", t, CB_ERR_PARSE,
                   (const char *const[]){line, c, "byte 0x01", NULL});
        free(t);
    }
    /* Truncated: everything from the middle on missing, or cut inside an entity. */
    size_t half = strlen(cube) / 2;
    expect_bad_len("truncated", cube, half, CB_ERR_PARSE, (const char *const[]){":", NULL});
    char *cut = strstr(cube + half, "EDGE_LOOP(");
    expect_bad_len("cut in an entity", cube, (size_t)(cut - cube) + 14, CB_ERR_PARSE,
                   (const char *const[]){"EDGE_LOOP", NULL});
    t = replaced(cube, "ENDSEC;\nEND-ISO-10303-21;\n", "ENDSEC;\n");
    expect_bad("no trailer", t, CB_ERR_PARSE, (const char *const[]){"END-ISO-10303-21", NULL});
    free(t);

    /* Missing ';': the next instance is reported where it starts. */
    snprintf(a, sizeof a, "VERTEX_POINT('',#1);");
    t = replaced(cube, a, "VERTEX_POINT('',#1)");
    snprintf(line, sizeof line, ":%d:", line_of(cube, a) + 1);
    snprintf(b, sizeof b, "#%d VERTEX_POINT", id_vertex0);
    expect_bad("missing ;", t, CB_ERR_PARSE, (const char *const[]){line, b, "expected ';'", NULL});
    free(t);

    expect_bad("unterminated string",
               "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('abc,(0.,0.,0.));\n",
               CB_ERR_PARSE,
               (const char *const[]){":5:", "#1 CARTESIAN_POINT", "unterminated string", NULL});
    expect_bad("unterminated comment",
               "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\n"
               "/* never closed\n#2=DIRECTION('',(0.,0.,1.));\n",
               CB_ERR_PARSE, (const char *const[]){":6:", "unterminated comment", NULL});

    /* Dangling reference. */
    snprintf(a, sizeof a, "#%d=VERTEX_POINT('',#1);", id_vertex0);
    snprintf(b, sizeof b, "#%d=VERTEX_POINT('',#99999);", id_vertex0);
    t = replaced(cube, a, b);
    snprintf(line, sizeof line, ":%d:", line_of(cube, a));
    snprintf(c, sizeof c, "#%d VERTEX_POINT", id_vertex0);
    expect_bad("dangling", t, CB_ERR_INVALID,
               (const char *const[]){line, c, "#99999 is not defined", NULL});
    free(t);

    /* Cyclic reference: an edge whose curve is a SURFACE_CURVE of itself. */
    snprintf(a, sizeof a, "#%d=LINE(", id_line0);
    snprintf(b, sizeof b, "#%d=SURFACE_CURVE('',#%d,(),.CURVE_3D.);\n#77777=LINE(", id_line0,
             id_line0);
    t = replaced(cube, a, b);
    snprintf(c, sizeof c, "#%d SURFACE_CURVE", id_line0);
    expect_bad("cycle", t, CB_ERR_INVALID, (const char *const[]){c, "cyclic reference", NULL});
    free(t);

    /* Duplicate instance name. */
    snprintf(a, sizeof a, "#%d=LINE(", id_line0);
    snprintf(b, sizeof b, "#%d=DIRECTION('',(1.,0.,0.));\n#%d=LINE(", id_line0, id_line0);
    t = replaced(cube, a, b);
    snprintf(c, sizeof c, "#%d", id_line0);
    expect_bad("duplicate id", t, CB_ERR_PARSE, (const char *const[]){c, "used again", NULL});
    free(t);

    /* Wrong argument count and wrong argument type. */
    snprintf(a, sizeof a, "#%d=PLANE('',", id_plane0);
    snprintf(b, sizeof b, "#%d=PLANE(", id_plane0);
    t = replaced(cube, a, b);
    snprintf(line, sizeof line, ":%d:", line_of(cube, a));
    snprintf(c, sizeof c, "#%d PLANE", id_plane0);
    expect_bad("argument count", t, CB_ERR_PARSE,
               (const char *const[]){line, c, "1 parameters given, 2 expected", NULL});
    free(t);
    snprintf(a, sizeof a, "#%d=EDGE_CURVE(", id_edge0);
    char *edge = strstr(cube, a);
    char orig[128];
    snprintf(orig, sizeof orig, "%.*s", (int)(strchr(edge, '\n') - edge), edge);
    char bad_edge[160];
    snprintf(bad_edge, sizeof bad_edge, "%.*s1.5);", (int)(strlen(orig) - 5), orig);
    t = replaced(cube, orig, bad_edge);
    snprintf(c, sizeof c, "#%d EDGE_CURVE", id_edge0);
    expect_bad("argument type", t, CB_ERR_PARSE,
               (const char *const[]){c, "same_sense: .T. or .F. expected, found a real", NULL});
    free(t);
    snprintf(a, sizeof a, "#%d=ADVANCED_FACE('',(", id_face0);
    snprintf(b, sizeof b, "#%d=ADVANCED_FACE('',(#%d,", id_face0, id_vertex0);
    t = replaced(cube, a, b);
    snprintf(c, sizeof c, "#%d VERTEX_POINT", id_vertex0);
    expect_bad("entity of the wrong type", t, CB_ERR_INVALID,
               (const char *const[]){c, "FACE_BOUND expected", NULL});
    free(t);

    /* Absurd numbers. */
    t = replaced(cube, "CARTESIAN_POINT('',(0,", "CARTESIAN_POINT('',(1e999,");
    expect_bad("overflow", t, CB_ERR_PARSE,
               (const char *const[]){":", "#1 CARTESIAN_POINT", "not a finite double", NULL});
    free(t);
    t = replaced(cube, "CARTESIAN_POINT('',(0,", "CARTESIAN_POINT('',(1e300,");
    expect_bad("absurd coordinate", t, CB_ERR_INVALID,
               (const char *const[]){"#1 CARTESIAN_POINT", "beyond", NULL});
    free(t);
    t = replaced(cube, "ORIENTED_EDGE('',*,*,#", "ORIENTED_EDGE('',*,*,#123456789012345678901");
    expect_bad("huge reference", t, CB_ERR_PARSE,
               (const char *const[]){"ORIENTED_EDGE", "malformed reference", NULL});
    free(t);
    t = replaced(cube, "B_SPLINE_CURVE_WITH_KNOTS('',2,",
                 "B_SPLINE_CURVE_WITH_KNOTS('',2000000000,");
    snprintf(c, sizeof c, "#%d B_SPLINE_CURVE_WITH_KNOTS", id_bspline);
    expect_bad("absurd degree", t, CB_ERR_INVALID,
               (const char *const[]){c, "degree: 2000000000 is outside [1, 32]", NULL});
    free(t);

    /* Knot vectors: one knot too few (the message of cb_nurbs_curve_make, prefixed), and a
     * multiplicity above degree + 1. */
    t = replaced(cube, "(1,1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.,6.)",
                 "(1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.)");
    snprintf(line, sizeof line, ":%d:", line_of(cube, "B_SPLINE_CURVE_WITH_KNOTS"));
    expect_bad("knot count", t, CB_ERR_INVALID,
               (const char *const[]){line, c, "6 knots given, 7 expected", NULL});
    free(t);
    t = replaced(cube, "(1,1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.,6.)", "(4,1,1,1),(0.,1.,2.,3.)");
    expect_bad("multiplicity", t, CB_ERR_INVALID,
               (const char *const[]){c, "knot multiplicity 1: 4 is outside [1, 3]", NULL});
    free(t);
    t = replaced(cube, "(1,1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.,6.)",
                 "(1,1,1,1,1,1,1),(0.,1.,2.,3.,2.,5.,6.)");
    expect_bad("decreasing knots", t, CB_ERR_INVALID,
               (const char *const[]){c, "not non-decreasing", NULL});
    free(t);
    t = replaced(cube, "(1,1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.,6.)",
                 "(1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.,6.)");
    expect_bad("multiplicities vs knots", t, CB_ERR_INVALID,
               (const char *const[]){c, "6 knot multiplicities for 7 knot values", NULL});
    free(t);

    /* Unsupported geometry that is needed, and a zero direction. */
    snprintf(a, sizeof a, "#%d=PLANE('',", id_plane0);
    snprintf(b, sizeof b, "#%d=OFFSET_SURFACE('',", id_plane0);
    t = replaced(cube, a, b);
    snprintf(c, sizeof c, "#%d OFFSET_SURFACE", id_plane0);
    expect_bad("unsupported surface", t, CB_ERR_UNSUPPORTED,
               (const char *const[]){c, "surface type not supported", NULL});
    free(t);
    t = replaced(cube, "DIRECTION('',(1,0,0))", "DIRECTION('',(0,0,0))");
    expect_bad("zero direction", t, CB_ERR_INVALID, (const char *const[]){"zero direction", NULL});
    free(t);

    /* Deep nesting and a file with no solid. */
    {
        size_t n = 200000;
        char *deep = malloc(n + 200);
        strcpy(deep, "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=X(");
        size_t len = strlen(deep);
        for (size_t k = 0; k < n; k++)
            deep[len++] = '(';
        deep[len] = '\0';
        expect_bad("deep nesting", deep, CB_ERR_PARSE,
                   (const char *const[]){":5:", "#1 X", "nested deeper", NULL});
        free(deep);
    }
    expect_bad("no solid",
               "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\n"
               "ENDSEC;\nEND-ISO-10303-21;\n",
               CB_ERR_INVALID, (const char *const[]){"no MANIFOLD_SOLID_BREP", NULL});

    cb_topo_body *body = (void *)1;
    cb_error err;
    CHECK(cb_step_read(&body, "/nonexistent/dir/x.step", &err) == CB_ERR_IO &&
              strstr(err.msg, "/nonexistent/dir/x.step: cannot open") && body == NULL,
          "missing file: '%s'", err.msg);
    CHECK(cb_step_read(&body, "/tmp", &err) != CB_OK && body == NULL,
          "a directory read as a STEP file");
    free(cube);
}


/* ---------------------------------------------------------------- whole faces -------------- */

/* Valid, of the expected counts and volume, meshed closed without crossings: returns the
 * volume (NaN when it could not be integrated). */
static double check_whole(const char *what, cb_topo_body *b, int faces, int edges, int vertices,
                          double volume)
{
    cb_error err;
    CHECK(b->n_solids == 1 && b->n_faces == faces && b->n_edges == edges &&
              b->n_vertices == vertices,
          "%s: %d solids, %d faces, %d edges, %d vertices; 1, %d, %d, %d expected", what,
          b->n_solids, b->n_faces, b->n_edges, b->n_vertices, faces, edges, vertices);
    cb_topo_report r;
    cb_topo_report_init(&r);
    cb_status st = cb_topo_validate(&r, b, 0, 33, &err);
    CHECK(st == CB_OK && r.n == 0, "%s: not valid: %s", what, st ? err.msg : r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    cb_mass_props m;
    st = cb_mass_body(&m, b, 1e-12, NULL, &err);
    CHECK(st == CB_OK && fabs(m.volume - volume) <= 1e-9 * volume,
          "%s: volume %.15g, %.15g expected (%s)", what, st ? NAN : m.volume, volume,
          st ? err.msg : "");
    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_mesh_check_report cr;
    cb_status ms = cb_tess_body(mesh, b, NULL, NULL, &err);
    if (!ms)
        ms = cb_mesh_check(&cr, mesh, &err);
    CHECK(ms == CB_OK && cb_mesh_check_passed(&cr), "%s: mesh %s: closed %d, self-intersections %d",
          what, ms ? err.msg : "checked", ms ? -1 : cr.closed, ms ? -1 : cr.self_intersections);
    cb_mesh_clear(mesh);
    return st ? NAN : m.volume;
}

/* Faces as Open CASCADE writes them (tests/data/occt): a whole sphere or ellipsoid as one face
 * bounded by a VERTEX_LOOP (analytic, B-spline, turned), or by nothing; a torus as one face
 * bounded by its two seams, or by a VERTEX_LOOP; a cone with its apex as a vertex on its side
 * face. Each loads valid with the seams and poles of its surface (cb_topo_close_faces), its
 * volume the closed form within 1e-9, its mesh closed without crossings, and written back and
 * read again the same. (The spheres failed with "face 0: no boundary loop", the torus came out
 * valid with volume -2 pi^2 R r^2, and the B-spline sphere's seam pieces were reported 0.11 off
 * their surface near the poles.) */
static void test_whole_faces(void)
{
    const double pi = 3.14159265358979323846;
    const double sphere = 4 * pi / 3, torus = 2 * pi * pi * 0.09, cone = pi * 0.64 * 1.5 / 3,
                 ellipsoid = 4 * pi / 3 * 1.2 * 0.8 * 0.6;
    static const struct {
        const char *file;
        int faces, edges, vertices;
        int kind; /* 0 sphere, 1 torus, 2 cone, 3 ellipsoid */
    } cases[] = {{"sphere.step", 1, 1, 2, 0},       {"sphere_nurbs.step", 1, 1, 2, 0},
                 {"sphere_rot.step", 1, 1, 2, 0},   {"sphere_nobound.step", 1, 1, 2, 0},
                 {"torus.step", 1, 2, 1, 1},        {"torus_nurbs.step", 1, 2, 1, 1},
                 {"torus_vertex_loop.step", 1, 2, 1, 1}, {"cone.step", 2, 2, 2, 2},
                 {"cone_nurbs.step", 2, 2, 2, 2},   {"cone_rot_nurbs.step", 2, 2, 2, 2},
                 {"ellipsoid.step", 1, 1, 2, 3}};
    const double volumes[4] = {sphere, torus, cone, ellipsoid};
    const char *tmp = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        char path[1024], back[1024];
        snprintf(path, sizeof path, "%s/tests/data/occt/%s", source_dir(), cases[k].file);
        snprintf(back, sizeof back, "%s/colibri_io_step_%d_%s", tmp, (int)getpid(),
                 cases[k].file);
        cb_topo_body *b = NULL, *c = NULL;
        cb_error err;
        cb_status st = cb_step_read(&b, path, &err);
        CHECK(st == CB_OK, "%s: %s", cases[k].file, err.msg);
        if (st)
            continue;
        double v = volumes[cases[k].kind];
        double got = check_whole(cases[k].file, b, cases[k].faces, cases[k].edges,
                                 cases[k].vertices, v);
        st = cb_step_write(b, back, "whole", &err);
        if (!st)
            st = cb_step_read(&c, back, &err);
        CHECK(st == CB_OK, "%s written back: %s", cases[k].file, err.msg);
        if (!st) {
            char what[1100];
            snprintf(what, sizeof what, "%s written back", cases[k].file);
            check_whole(what, c, cases[k].faces, cases[k].edges, cases[k].vertices, v);
        }
        printf("%-24s volume %.15g (rel %.1e), written back and read again\n", cases[k].file, got,
               fabs(got - v) / v);
        remove(back);
        cb_topo_body_free(b);
        cb_topo_body_free(c);
    }
}

/* ---------------------------------------------------------------- bands -------------------- */

/* AXIS2_PLACEMENT_3D at (0, 0, z), axis z, reference direction at angle phase in the xy
 * plane. */
static int placement_z(sbuf *s, double z, double phase)
{
    int o = emit(s, "CARTESIAN_POINT('',(0.,0.,%.17g));", z);
    int ax = emit(s, "DIRECTION('',(0.,0.,1.));");
    int rf = emit(s, "DIRECTION('',(%.17g,%.17g,0.));", cos(phase), sin(phase));
    return emit(s, "AXIS2_PLACEMENT_3D('',#%d,#%d,#%d);", o, ax, rf);
}

/* A closed circle edge about the z axis at height z, radius r, counter-clockwise about z, its
 * one vertex at angle phase. */
static int circle_edge(sbuf *s, double z, double r, double phase)
{
    int p = emit(s, "CARTESIAN_POINT('',(%.17g,%.17g,%.17g));", r * cos(phase), r * sin(phase),
                 z);
    int v = emit(s, "VERTEX_POINT('',#%d);", p);
    int c = emit(s, "CIRCLE('',#%d,%.17g);", placement_z(s, z, phase), r);
    return emit(s, "EDGE_CURVE('',#%d,#%d,#%d,.T.);", v, v, c);
}

/* A face on `surface` bounded by the circle edges e[0..n) used in senses sense[k]. */
static int circles_face(sbuf *s, int surface, int same_sense, const int *e, const int *sense,
                        int n)
{
    int bound[2];
    for (int k = 0; k < n; k++) {
        int oe = emit(s, "ORIENTED_EDGE('',*,*,#%d,%s);", e[k], sense[k] ? ".T." : ".F.");
        int lp = emit(s, "EDGE_LOOP('',(#%d));", oe);
        bound[k] = emit(s, "FACE_BOUND('',#%d,.T.);", lp);
    }
    if (n == 1)
        return emit(s, "ADVANCED_FACE('',(#%d),#%d,%s);", bound[0], surface,
                    same_sense ? ".T." : ".F.");
    return emit(s, "ADVANCED_FACE('',(#%d,#%d),#%d,%s);", bound[0], bound[1], surface,
                same_sense ? ".T." : ".F.");
}

/* Solids whose side faces are bands bounded by two full circles with no seam edge, as many
 * CAD files write them (OCC2368.stp: 13 of its 18 faces). The seam goes at u = 0 of the
 * surface (cb_topo_close_faces), so the edge counts tell which circles were split there:
 * kind 0 a cylinder (r 1.5, z 0..2) whose bottom circle's vertex is at its u = 0, the top's
 * at angle 1 (split); kind 1 a cone frustum (r 1.5 to 2 over z 0..2), both vertices at angle
 * 0 but the cone's u = 0 at angle 0.3 (both split); each closed by two discs. Kind 2 a ring:
 * the outer half of a torus (R 3, r 1, u = 0 at angle 0) and the cylinder r 3 (u = 0 at angle
 * 0.5) between the circles z = -1 (vertex at angle 0) and z = 1 (angle 2): two bands sharing
 * both circles (split three times), the torus band's seam across its v period. Kinds 3 and 4:
 * a face bounded by one circle (vertex at angle 0.5, split) that ends in a point, a cone (apex
 * at the origin, r 1 at z 2) and a sphere cap (r 1 above z 0.5), each closed by a disc: the
 * seam runs from the circle to the apex or pole. Kind 5: kind 0's cylinder as a rational
 * B-spline, its vertices at angles 1 and 2 (both split); kind 6: as a circle extruded. */
static char *band_file(int kind)
{
    sbuf s = {NULL, 0, 0, 1};
    start_file(&s);
    int faces[3], n;
    if (kind < 2 || kind == 6) {
        double r1 = kind == 1 ? 2.0 : 1.5;
        int bottom = circle_edge(&s, 0, 1.5, 0), top = circle_edge(&s, 2, r1, kind == 1 ? 0 : 1);
        int side;
        if (kind == 0) {
            side = emit(&s, "CYLINDRICAL_SURFACE('',#%d,1.5);", placement_z(&s, 0, 0));
        } else if (kind == 1) {
            side = emit(&s, "CONICAL_SURFACE('',#%d,1.5,%.17g);", placement_z(&s, 0, 0.3),
                        atan(0.25));
        } else {
            int profile = emit(&s, "CIRCLE('',#%d,1.5);", placement_z(&s, 0, 0));
            int dir = emit(&s, "DIRECTION('',(0.,0.,1.));");
            int vec = emit(&s, "VECTOR('',#%d,1.);", dir);
            side = emit(&s, "SURFACE_OF_LINEAR_EXTRUSION('',#%d,#%d);", profile, vec);
        }
        int pb = emit(&s, "PLANE('',#%d);", placement_z(&s, 0, 0));
        int pt = emit(&s, "PLANE('',#%d);", placement_z(&s, 2, 0));
        const int e2[2] = {bottom, top}, s2[2] = {1, 0}, f = 0, t = 1;
        faces[0] = circles_face(&s, side, 1, e2, s2, 2);
        faces[1] = circles_face(&s, pb, 0, &bottom, &f, 1);
        faces[2] = circles_face(&s, pt, 1, &top, &t, 1);
        n = 3;
    } else if (kind == 5) {
        /* The cylinder of kind 0 as a rational B-spline (u: the circle from angle 0, v: z),
         * its circles' vertices at angles 1 and 2: both are split at the domain's start. */
        int bottom = circle_edge(&s, 0, 1.5, 1), top = circle_edge(&s, 2, 1.5, 2), pt[9][2];
        for (int i = 0; i < 9; i++)
            for (int j = 0; j < 2; j++) {
                double a = i * 0.25 * 3.14159265358979323846, r = i % 2 ? 1.5 * sqrt(2) : 1.5;
                pt[i][j] = emit(&s, "CARTESIAN_POINT('',(%.17g,%.17g,%d.));", r * cos(a),
                                r * sin(a), 2 * j);
            }
        char rows[512] = "", weights[512] = "";
        for (int i = 0; i < 9; i++) {
            double w = i % 2 ? sqrt(0.5) : 1;
            snprintf(rows + strlen(rows), sizeof rows - strlen(rows), "%s(#%d,#%d)", i ? "," : "",
                     pt[i][0], pt[i][1]);
            snprintf(weights + strlen(weights), sizeof weights - strlen(weights), "%s(%.17g,%.17g)",
                     i ? "," : "", w, w);
        }
        int side = emit(&s,
                        "( BOUNDED_SURFACE() B_SPLINE_SURFACE(2,1,(%s),.UNSPECIFIED.,.T.,.F.,.F.) "
                        "B_SPLINE_SURFACE_WITH_KNOTS((3,2,2,2,3),(2,2),(0.,0.25,0.5,0.75,1.),"
                        "(0.,1.),.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() "
                        "RATIONAL_B_SPLINE_SURFACE((%s)) REPRESENTATION_ITEM('') SURFACE() );",
                        rows, weights);
        int pb = emit(&s, "PLANE('',#%d);", placement_z(&s, 0, 0));
        int pt2 = emit(&s, "PLANE('',#%d);", placement_z(&s, 2, 0));
        const int e2[2] = {bottom, top}, s2[2] = {1, 0}, f = 0, t = 1;
        faces[0] = circles_face(&s, side, 1, e2, s2, 2);
        faces[1] = circles_face(&s, pb, 0, &bottom, &f, 1);
        faces[2] = circles_face(&s, pt2, 1, &top, &t, 1);
        n = 3;
    } else if (kind > 2) {
        /* One circle, the face beyond it ending in the cone's apex or the sphere's pole. */
        double z = kind == 3 ? 2 : 0.5;
        int rim = circle_edge(&s, z, kind == 3 ? 1 : sqrt(0.75), 0.5);
        int cap = kind == 3 ? emit(&s, "CONICAL_SURFACE('',#%d,0.,%.17g);", placement_z(&s, 0, 0),
                                   atan(0.5))
                            : emit(&s, "SPHERICAL_SURFACE('',#%d,1.);", placement_z(&s, 0, 0));
        int lid = emit(&s, "PLANE('',#%d);", placement_z(&s, z, 0));
        const int along = 1, against = 0;
        faces[0] = circles_face(&s, cap, 1, &rim, kind == 3 ? &against : &along, 1);
        faces[1] = circles_face(&s, lid, kind == 3, &rim, kind == 3 ? &along : &against, 1);
        n = 2;
    } else {
        int bottom = circle_edge(&s, -1, 3, 0), top = circle_edge(&s, 1, 3, 2);
        int torus = emit(&s, "TOROIDAL_SURFACE('',#%d,3.,1.);", placement_z(&s, 0, 0));
        int cyl = emit(&s, "CYLINDRICAL_SURFACE('',#%d,3.);", placement_z(&s, -1, 0.5));
        const int e2[2] = {bottom, top}, out[2] = {1, 0}, in[2] = {0, 1};
        faces[0] = circles_face(&s, torus, 1, e2, out, 2);
        faces[1] = circles_face(&s, cyl, 0, e2, in, 2);
        n = 2;
    }
    int shell = n == 3 ? emit(&s, "CLOSED_SHELL('',(#%d,#%d,#%d));", faces[0], faces[1], faces[2])
                       : emit(&s, "CLOSED_SHELL('',(#%d,#%d));", faces[0], faces[1]);
    int solid = emit(&s, "MANIFOLD_SOLID_BREP('',#%d);", shell);
    cube_opts plain = {0};
    return finish_file(&s, solid, &plain);
}

/* Band faces (band_file) load valid with a seam each (cb_topo_close_faces): the edge counts
 * say which circles were split and that each band got one seam; the volume is the closed form
 * within 1e-9, the mesh closed without crossings, and the file written back reads the same.
 * Before the seams the mesher refused them ("loop 0 wraps around the periodic surface without
 * a seam edge") and the Booleans dropped the faces. */
static void test_band_faces(void)
{
    const double pi = 3.14159265358979323846;
    static const struct {
        const char *what;
        int faces, edges, vertices;
    } cases[7] = {{"cylinder band", 3, 4, 3}, {"cone band", 3, 5, 4}, {"torus ring", 2, 7, 5},
                  {"cone to apex", 2, 3, 3},   {"sphere cap", 2, 3, 3},
                  {"B-spline band", 3, 5, 4},  {"extrusion band", 3, 4, 3}};
    const double volumes[7] = {pi * 2.25 * 2, pi * 2 / 3 * (2.25 + 3 + 4), pi * pi * 3 + 4 * pi / 3,
                               pi * 2 / 3,    pi * 0.25 * 2.5 / 3,          pi * 2.25 * 2,
                               pi * 2.25 * 2};
    for (int k = 0; k < 7; k++) {
        char *text = band_file(k);
        cb_topo_body *b = NULL, *c = NULL;
        cb_error err;
        cb_status st = read_text(&b, text, strlen(text), &err);
        free(text);
        CHECK(st == CB_OK, "%s: %s", cases[k].what, err.msg);
        if (st)
            continue;
        double got = check_whole(cases[k].what, b, cases[k].faces, cases[k].edges,
                                 cases[k].vertices, volumes[k]);
        char back[1024];
        const char *tmp = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
        snprintf(back, sizeof back, "%s/colibri_io_step_%d_band%d.step", tmp, (int)getpid(), k);
        st = cb_step_write(b, back, "band", &err);
        if (!st)
            st = cb_step_read(&c, back, &err);
        CHECK(st == CB_OK, "%s written back: %s", cases[k].what, err.msg);
        if (!st) {
            char what[64];
            snprintf(what, sizeof what, "%s written back", cases[k].what);
            check_whole(what, c, cases[k].faces, cases[k].edges, cases[k].vertices, volumes[k]);
        }
        printf("%-14s volume %.15g (rel %.1e), written back and read again\n", cases[k].what, got,
               fabs(got - volumes[k]) / volumes[k]);
        remove(back);
        cb_topo_body_free(b);
        cb_topo_body_free(c);
    }
}

/* Files measuring plane angles in degrees write the angle parameters of their pcurves in degrees
 * too (ISO 10303-42: u of cylinders and cones, u and v of spheres and tori; trj4_k1_top-pe-214.stp
 * of the shared corpus). tests/data/degrees holds Open CASCADE's cylinder, cone and torus
 * (tests/data/occt) rewritten so by tests/data/degrees/to_degrees.py: each loads valid with the
 * volume and area of its radian original. (Read as radians, the loops ran over dozens of turns:
 * the cylinder's volume was not integrated, the cone's side face spanned no area.) */
static void test_degree_pcurves(void)
{
    static const char *files[] = {"steinmetz_seams_rot_a.step", "cone.step", "torus.step"};
    for (size_t k = 0; k < sizeof files / sizeof *files; k++) {
        cb_mass_props m[2];
        int ok = 1;
        for (int deg = 0; deg < 2 && ok; deg++) {
            char path[1024];
            snprintf(path, sizeof path, "%s/tests/data/%s/%s", source_dir(),
                     deg ? "degrees" : "occt", files[k]);
            cb_topo_body *b = NULL;
            cb_error err;
            cb_status st = cb_step_read(&b, path, &err);
            int valid = !st && validates(b, path);
            if (valid)
                st = cb_mass_body(&m[deg], b, 1e-12, NULL, &err);
            CHECK(st == CB_OK, "%s: %s", path, err.msg);
            ok = valid && st == CB_OK;
            cb_topo_body_free(b);
        }
        if (!ok)
            continue;
        double dv = fabs(m[1].volume - m[0].volume), da = fabs(m[1].area - m[0].area);
        CHECK(dv <= 1e-10 * m[0].volume && da <= 1e-10 * m[0].area,
              "%s in degrees: volume %.15g area %.15g, in radians %.15g %.15g", files[k],
              m[1].volume, m[1].area, m[0].volume, m[0].area);
        printf("%-28s in degrees: volume %.15g (rel %.1e from radians)\n", files[k], m[1].volume,
               dv / m[0].volume);
    }
}

int main(void)
{
    double t0 = now();
    test_whole_faces();
    test_degree_pcurves();
    test_band_faces();
    test_models();
    test_clamped_pcurves();
    test_cubes();
    test_edge_tolerances();
    test_forms();
    test_bad_files();
    printf("io_step: %.2f s\n", now() - t0);
    return check_report("io_step");
}
