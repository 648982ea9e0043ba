/* STEP writer (io/step_write.c): every shared model read, written and read back keeps its
 * topology, surface types and geometry; bad bodies and paths are refused. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "io/step.h"
#include "io/step_write.h"

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

/* Largest distance between the two surfaces' points on a parameter grid: the whole domain for
 * B-splines, a window of the (unbounded or periodic) parameters otherwise. */
static double surface_deviation(const cb_topo_surface *a, const cb_topo_surface *b)
{
    double box[4] = {0, 6.283185307179586, -1, 1};
    if (a->kind == CB_SURFACE_NURBS)
        cb_nurbs_surface_domain(a->nurbs, box);
    double dev = 0;
    for (int i = 0; i <= 12; i++)
        for (int j = 0; j <= 12; j++) {
            double u = box[0] + (box[1] - box[0]) * i / 12, v = box[2] + (box[3] - box[2]) * j / 12;
            double da[6][3], db[6][3];
            cb_topo_surface_eval_derivs(da, a, u, v);
            cb_topo_surface_eval_derivs(db, b, u, v);
            dev = fmax(dev, cb_vec3_dist(da[0], db[0]));
        }
    return dev;
}

static void round_trip(const char *file)
{
    char in[1024], out[1024];
    snprintf(in, sizeof in, "%s/models/%s", shared_dir(), file);
    snprintf(out, sizeof out, "/tmp/colibri_rt_%d_%s", (int)getpid(), file);
    cb_topo_body *a = NULL, *b = NULL;
    cb_error err;
    cb_error_clear(&err);
    CHECK(cb_step_read(&a, in, &err) == CB_OK, "%s: read: %s", file, err.msg);
    if (!a)
        return;
    CHECK(cb_step_write(a, out, file, &err) == CB_OK, "%s: write: %s", file, err.msg);
    CHECK(cb_step_read(&b, out, &err) == CB_OK, "%s: read back: %s", file, err.msg);
    if (b) {
        CHECK(a->n_solids == b->n_solids && a->n_shells == b->n_shells &&
                  a->n_faces == b->n_faces && a->n_loops == b->n_loops &&
                  a->n_coedges == b->n_coedges && a->n_edges == b->n_edges &&
                  a->n_vertices == b->n_vertices,
              "%s: counts changed: faces %d/%d edges %d/%d vertices %d/%d", file, a->n_faces,
              b->n_faces, a->n_edges, b->n_edges, a->n_vertices, b->n_vertices);
        CHECK(a->length_unit_mm == b->length_unit_mm && a->tol == b->tol,
              "%s: unit %g/%g tol %g/%g", file, a->length_unit_mm, b->length_unit_mm, a->tol,
              b->tol);
        double size = 0, worst_surface = 0, worst_coedge = 0;
        for (int k = 0; k < a->n_vertices; k++)
            size = fmax(size, cb_vec3_norm(a->vertices[k].p));
        for (int f = 0; f < a->n_faces && f < b->n_faces; f++) {
            const cb_topo_surface *sa = &a->surfaces[a->faces[f].surface];
            const cb_topo_surface *sb = &b->surfaces[b->faces[f].surface];
            CHECK(!strcmp(cb_topo_surface_type_name(sa), cb_topo_surface_type_name(sb)) &&
                      a->faces[f].same_sense == b->faces[f].same_sense &&
                      a->faces[f].count == b->faces[f].count,
                  "%s: face %d: %s/%s", file, f, cb_topo_surface_type_name(sa),
                  cb_topo_surface_type_name(sb));
            worst_surface = fmax(worst_surface, surface_deviation(sa, sb));
        }
        for (int c = 0; c < a->n_coedges && c < b->n_coedges; c++) {
            double s0[3], e0[3], s1[3], e1[3];
            cb_topo_coedge_ends(s0, e0, a, c);
            cb_topo_coedge_ends(s1, e1, b, c);
            worst_coedge = fmax(worst_coedge, fmax(cb_vec3_dist(s0, s1), cb_vec3_dist(e0, e1)));
        }
        CHECK(worst_surface <= 1e-12 * size && worst_coedge <= 1e-12 * size,
              "%s: geometry moved: surfaces %g, coedge ends %g (size %g)", file, worst_surface,
              worst_coedge, size);
        /* The validator finds the same in both (the models' own tolerance slips included). */
        cb_topo_report ra, rb;
        cb_topo_report_init(&ra);
        cb_topo_report_init(&rb);
        cb_topo_validate(&ra, a, 0, 5, &err);
        cb_topo_validate(&rb, b, 0, 5, &err);
        CHECK(ra.n == rb.n && ra.max_edge_surface == rb.max_edge_surface,
              "%s: %d problems before, %d after the round trip", file, ra.n, rb.n);
        cb_topo_report_clear(&ra);
        cb_topo_report_clear(&rb);
        printf("%-20s round trip: %d faces, surface deviation %.1e, coedge ends %.1e\n", file,
               b->n_faces, worst_surface, worst_coedge);
    }
    remove(out);
    cb_topo_body_free(a);
    cb_topo_body_free(b);
}

static void test_bad_bodies(void)
{
    cb_error err;
    cb_topo_body *empty = cb_topo_body_new();
    CHECK(cb_step_write(empty, "/tmp/colibri_never.step", NULL, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "no faces"),
          "empty body: '%s'", err.msg);
    CHECK(access("/tmp/colibri_never.step", F_OK) != 0, "a refused body left a file");
    cb_topo_body_free(empty);

    char in[1024];
    snprintf(in, sizeof in, "%s/models/ujoint_cross.step", shared_dir());
    cb_topo_body *b = NULL;
    if (cb_step_read(&b, in, &err) != CB_OK)
        return;
    CHECK(cb_step_write(b, "/nonexistent/dir/x.step", NULL, &err) == CB_ERR_IO &&
              strstr(err.msg, "cannot create"),
          "bad path: '%s'", err.msg);
    b->vertices[0].p[1] = NAN;
    CHECK(cb_step_write(b, "/tmp/colibri_never.step", NULL, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "vertex 0"),
          "NaN vertex: '%s'", err.msg);
    CHECK(access("/tmp/colibri_never.step", F_OK) != 0, "a refused body left a file");
    cb_topo_body_free(b);
}

int main(void)
{
    round_trip("trj5_k1-al-214.stp");
    round_trip("linkrods.step");
    round_trip("ujoint_fork.step");
    round_trip("ujoint_cross.step");
    test_bad_bodies();
    return check_report("io_step_write");
}
