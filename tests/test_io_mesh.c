/* Mesh files through OpenMesh: every shape written in every format reads back with the same
 * counts, sharing and triangles, and every coordinate rounded to float at most (OpenMesh 9.0
 * passes floats in every format); bad files are rejected with a message that says why. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brep/mesh.h"
#include "brep/mesh_shapes.h"
#include "check.h"
#include "io/mesh.h"

static char dir[64];

static void path_in_dir(char *path, size_t size, const char *name)
{
    snprintf(path, size, "%s/%s", dir, name);
}

static double rel_diff(double a, double b)
{
    return fabs(a - b) / fmax(fabs(a), fabs(b));
}

typedef struct {
    const char *ext;
    int stl_ascii;
    int indexed; /* the file stores vertex indices, so they must come back as written */
} format_case;

static const format_case FORMATS[] = {
    {"stl", 0, 0}, {"stl", 1, 0}, {"obj", 0, 1}, {"ply", 0, 1}, {"off", 0, 1}, {"OBJ", 0, 1}};

/* Writes m as `name` in every format and reads it back. */
static void round_trip(const char *name, const cb_mesh_t m)
{
    cb_mesh_t back;
    cb_mesh_init(back);
    cb_error err;
    double vol = cb_mesh_volume(m), worst_volume = 0;
    for (size_t k = 0; k < sizeof FORMATS / sizeof *FORMATS; k++) {
        const format_case *fc = &FORMATS[k];
        char path[128], file[64];
        snprintf(file, sizeof file, "%s%s.%s", name, fc->stl_ascii ? "_ascii" : "", fc->ext);
        path_in_dir(path, sizeof path, file);
        cb_mesh_write_options opt = {.stl_ascii = fc->stl_ascii};
        cb_error_clear(&err);
        CHECK(cb_mesh_write(path, m, &opt, &err) == CB_OK, "%s: write: %s", file, err.msg);
        CHECK(cb_mesh_read(back, path, &err) == CB_OK, "%s: read: %s", file, err.msg);
        CHECK(back->n_vertices == m->n_vertices && back->n_triangles == m->n_triangles,
              "%s: %d vertices, %d triangles; wrote %d, %d", file, back->n_vertices,
              back->n_triangles, m->n_vertices, m->n_triangles);
        if (back->n_vertices != m->n_vertices || back->n_triangles != m->n_triangles)
            continue;
        /* STL stores points, not indices: OpenMesh numbers them in order of first use. Map
         * through the triangles to compare each corner with the one written. */
        double worst = 0;
        int same_indices = 1;
        for (int f = 0; f < m->n_triangles; f++)
            for (int c = 0; c < 3; c++) {
                const double *p = m->xyz + 3 * m->tri[3 * f + c];
                const double *q = back->xyz + 3 * back->tri[3 * f + c];
                for (int j = 0; j < 3; j++) {
                    double d = fabs(p[j] - q[j]) / fmax(fabs(p[j]), 1e-300);
                    worst = d > worst ? d : worst;
                }
                same_indices &= back->tri[3 * f + c] == m->tri[3 * f + c];
            }
        CHECK(same_indices || !fc->indexed, "%s: triangle indices changed", file);
        /* Rounding to float moves a coordinate by half an ulp at most: 2^-24 relative. */
        CHECK(worst <= 0x1p-24, "%s: a coordinate moved by %.3g relative", file, worst);
        double dv = rel_diff(cb_mesh_volume(back), vol);
        CHECK(dv < 1e-6, "%s: volume %.17g, wrote %.17g", file, cb_mesh_volume(back), vol);
        if (dv > worst_volume)
            worst_volume = dv;
    }
    printf("%s: %d vertices, %d triangles; largest relative volume change %.2e\n", name,
           m->n_vertices, m->n_triangles, worst_volume);
    cb_mesh_clear(back);
}

static void test_round_trips(void)
{
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_error err;
    const double tet[4][3] = {{0.1, 0.2, 0.3}, {1.7, 0.1, 0.05}, {0.3, 1.9, 0.2}, {0.4, 0.5, 2.1}};
    CHECK(cb_mesh_tetrahedron(m, tet, &err) == CB_OK, "%s", err.msg);
    round_trip("tetrahedron", m);
    const double lo[3] = {-1.25, 0.5, 1.0 / 3}, hi[3] = {2, 3.75, 4.0 / 3};
    CHECK(cb_mesh_box(m, lo, hi, &err) == CB_OK, "%s", err.msg);
    round_trip("box", m);
    const double c[3] = {0.1, -0.2, 0.3};
    CHECK(cb_mesh_icosphere(m, c, 1.5, 3, &err) == CB_OK, "%s", err.msg);
    round_trip("icosphere", m);
    CHECK(cb_mesh_torus(m, c, 2, 0.5, 40, 20, &err) == CB_OK, "%s", err.msg);
    round_trip("torus", m);
    /* Non-manifold meshes are written and read as they are: three triangles keep their edge. */
    CHECK(cb_mesh_box(m, lo, hi, &err) == CB_OK, "%s", err.msg);
    const double fin[3] = {-3, -3, 1};
    cb_mesh_append_vertex(m, fin, &err);
    cb_mesh_append_triangle(m, 0, 4, 8, &err);
    round_trip("fin", m);
    cb_mesh_clear(m);
}

/* Writes text to the file `name` in dir and returns cb_mesh_read's status on it. */
static cb_status read_text(const char *name, const char *text, cb_mesh_t m, cb_error *err)
{
    char path[128];
    path_in_dir(path, sizeof path, name);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    cb_error_clear(err);
    return cb_mesh_read(m, path, err);
}

static void test_errors(void)
{
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_error err;
    cb_status st;
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    cb_mesh_box(m, lo, hi, &err);

    st = cb_mesh_write("/tmp/colibri_mesh.step", m, NULL, &err);
    CHECK(st == CB_ERR_UNSUPPORTED && strstr(err.msg, "unknown mesh format"), "%d %s", st,
          err.msg);
    st = cb_mesh_write("/nonexistent/dir/x.stl", m, NULL, &err);
    CHECK(st == CB_ERR_IO && strstr(err.msg, "x.stl: cannot create"), "%d %s", st, err.msg);
    st = cb_mesh_read(m, "/nonexistent/x.obj", &err);
    CHECK(st == CB_ERR_IO && strstr(err.msg, "x.obj: cannot open"), "%d %s", st, err.msg);
    CHECK(m->n_vertices == 0 && m->n_triangles == 0, "mesh not emptied on failure");
    st = cb_mesh_read(m, "noextension", &err);
    CHECK(st == CB_ERR_UNSUPPORTED, "%d %s", st, err.msg);

    st = read_text("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", m, &err);
    CHECK(st == CB_ERR_UNSUPPORTED && strstr(err.msg, "face 0 has 4 vertices"), "%d %s", st,
          err.msg);
    st = read_text("repeat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", m, &err);
    CHECK(st == CB_ERR_PARSE && strstr(err.msg, "repeat.off: face 0: ") &&
              strstr(err.msg, "repeats a vertex"),
          "%d %s", st, err.msg);
    st = read_text("garbage.off", "no mesh here\n\x01\x02\n", m, &err);
    CHECK(st == CB_ERR_PARSE && strstr(err.msg, "garbage.off"), "%d %s", st, err.msg);
    st = read_text("garbage.ply", "ply\nformat nonsense\n", m, &err);
    CHECK(st == CB_ERR_PARSE && strstr(err.msg, "garbage.ply"), "%d %s", st, err.msg);
    st = read_text("empty.obj", "# nothing\n", m, &err);
    CHECK(st == CB_ERR_PARSE && strstr(err.msg, "empty.obj: no triangles read"), "%d %s", st,
          err.msg);
    st = read_text("empty.stl", "", m, &err);
    CHECK(st == CB_ERR_PARSE, "empty STL: %d %s", st, err.msg);
    /* A well-formed file of another program reads: an OBJ with normals and texture indices. */
    st = read_text("other.obj",
                   "# made elsewhere\nmtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                   "vn 0 0 1\nvt 0 0\nf 1/1/1 3/1/1 2/1/1\nf 1//1 2//1 4//1\nf 1 4 3\nf 2 3 4\n",
                   m, &err);
    CHECK(st == CB_OK && m->n_vertices == 4 && m->n_triangles == 4 &&
              rel_diff(cb_mesh_volume(m), 1.0 / 6) < 1e-15,
          "other.obj: %d %s, %d vertices, %d triangles", st, err.msg, m->n_vertices,
          m->n_triangles);
    cb_mesh_clear(m);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/colibri_io_mesh_%ld", (long)getpid());
    char cmd[128];
    snprintf(cmd, sizeof cmd, "mkdir -p %s", dir);
    if (system(cmd) != 0) {
        fprintf(stderr, "cannot make %s\n", dir);
        return 1;
    }
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    test_round_trips();
    test_errors();
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("io_mesh: %.2f s\n",
           (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK(system(cmd) == 0, "cannot remove %s", dir);
    return check_report("io_mesh");
}
