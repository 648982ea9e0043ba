/* Point classification speed (boolean/bool.h): for each model, the time to prepare the solid
 * (faces, boxes, BVH) and the points per second of cb_bool_solid_classify on uniform random
 * points of the solid's box, on one thread and on all threads (cb_parallel_for), with the
 * fraction found inside against the reference volume (../shared/models/SOURCES.md; none for
 * the hummingbird, whose volume test_bool_classify computes).
 * Usage: bench_classify [points per model] (default 20000). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "boolean/bool.h"
#include "brep/parallel.h"
#include "brep/prim.h"
#include "io/step.h"
#include "models/models.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

typedef struct {
    const cb_bool_solid *s;
    const double *pts;
    cb_bool_where *where;
    cb_status *st;
} job;

static void classify_range(void *ctx, size_t begin, size_t end)
{
    job *j = ctx;
    for (size_t k = begin; k < end; k++)
        j->st[k] = cb_bool_solid_classify(&j->where[k], j->s, j->pts + 3 * k, NULL);
}

static void run(const char *name, cb_topo_body *b, double tol, double volume, int n)
{
    cb_bool_solid *s;
    cb_error err;
    double t0 = now();
    if (cb_bool_solid_new(&s, b, tol, &err)) {
        printf("%-22s %s\n", name, err.msg);
        return;
    }
    double prep = now() - t0;
    cb_aabb box;
    cb_bool_solid_box(&box, s);
    double *pts = malloc((size_t)n * 3 * sizeof *pts);
    cb_bool_where *where = malloc((size_t)n * sizeof *where);
    cb_status *st = malloc((size_t)n * sizeof *st);
    unsigned long long x = 0;
    for (int k = 0; k < 3 * n; k++) { /* splitmix64 */
        unsigned long long z = (x += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        int i = k % 3;
        pts[k] = box.lo[i] + (box.hi[i] - box.lo[i]) * ((z >> 11) * 0x1.0p-53);
    }
    job j = {s, pts, where, st};
    t0 = now();
    cb_parallel_for((size_t)n, 64, 1, classify_range, &j);
    double one = now() - t0;
    t0 = now();
    cb_parallel_for((size_t)n, 64, 0, classify_range, &j);
    double all = now() - t0;
    int in = 0, on = 0, failed = 0;
    for (int k = 0; k < n; k++) {
        failed += st[k] != CB_OK;
        in += st[k] == CB_OK && where[k] == CB_BOOL_IN;
        on += st[k] == CB_OK && where[k] == CB_BOOL_ON;
    }
    double ratio = volume > 0 ? volume / pow(b->length_unit_mm, 3) / cb_aabb_volume(&box) : NAN;
    printf("%-22s %6d %9.1f %11.0f %11.0f %8.4f %8.4f %5d %5d\n", name, b->n_faces, 1e3 * prep,
           n / one, n / all, (double)in / n, ratio, on, failed);
    free(pts);
    free(where);
    free(st);
    cb_bool_solid_free(s);
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 20000;
    if (n < 1)
        n = 1;
    const char *dir = getenv("COLIBRI_SHARED");
    if (!dir)
        dir = "../shared";
    printf("point classification, %d random points of each solid's box, %d threads\n", n,
           cb_parallel_max_threads());
    printf("%-22s %6s %9s %11s %11s %8s %8s %5s %5s\n", "model", "faces", "prep ms", "pts/s 1thr",
           "pts/s all", "in frac", "vol/box", "on", "fail");
    static const struct {
        const char *file;
        double volume;
    } models[] = {{"ujoint_fork.step", 81046.104},
                  {"ujoint_cross.step", 95097.336},
                  {"linkrods.step", 3.847013},
                  {"trj5_k1-al-214.stp", 7936.1475}};
    for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/models/%s", dir, models[k].file);
        cb_topo_body *b;
        cb_error err;
        if (cb_step_read(&b, path, &err)) {
            printf("%-22s %s\n", models[k].file, err.msg);
            continue;
        }
        run(models[k].file, b, b->tol, models[k].volume, n);
        cb_topo_body_free(b);
    }
    cb_hummingbird_params hp;
    cb_hummingbird_params_default(&hp);
    cb_topo_body *bird;
    cb_error err;
    if (cb_model_hummingbird(&bird, &hp, &err) == CB_OK) {
        if (cb_topo_compute_pcurves(bird, 10 * bird->tol, &err) == CB_OK)
            run("hummingbird", bird, 100 * bird->tol, NAN, n);
        cb_topo_body_free(bird);
    }
    for (int nurbs = 0; nurbs < 2; nurbs++) {
        cb_topo_body *b;
        cb_error err;
        if (cb_prim_torus(&b, NULL, 2.0, 0.6, nurbs, 0, &err) == CB_OK) {
            run(nurbs ? "torus (B-spline)" : "torus (analytic)", b, 1e-7,
                2 * 3.14159265358979324 * 3.14159265358979324 * 2.0 * 0.36, n);
            cb_topo_body_free(b);
        }
    }
    return 0;
}
