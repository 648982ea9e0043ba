/* bench_tess: tessellation time, triangle count, mesh volume error and peak memory per model,
 * at the default chordal tolerance and finer ones, with 1 thread and all threads.
 * Usage: bench_tess [SHARED_DIR]  (default $COLIBRI_SHARED or ../shared) */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "brep/parallel.h"
#include "brep/tess.h"
#include "io/step.h"
#include "models/models.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Peak resident set of the process so far, MiB. */
static double peak_mib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss / 1024.0;
}

static void run(const char *name, const cb_topo_body *b, double ref_mm3)
{
    cb_tess_opts o;
    cb_error err;
    if (cb_tess_opts_resolve(&o, NULL, b, &err)) {
        printf("%-20s %s\n", name, err.msg);
        return;
    }
    double c0 = o.chord_tol, u3 = pow(b->length_unit_mm, 3);
    for (int level = 0; level < 4; level++) {
        o.chord_tol = c0 / pow(10, 0.5 * level);
        for (int threads = 1; threads <= 2; threads++) {
            cb_context ctx;
            cb_context_init(&ctx);
            ctx.threads = threads == 1 ? 1 : 0;
            cb_mesh_t m;
            cb_mesh_init(m);
            double t0 = now();
            cb_status st = cb_tess_body(m, b, &o, &ctx, &err);
            double dt = now() - t0;
            if (st) {
                printf("%-20s chord %-10.3g %s\n", name, o.chord_tol, err.msg);
                cb_mesh_clear(m);
                break;
            }
            double v = cb_mesh_volume(m) * u3;
            printf("%-20s chord %-10.3g threads %-3s %9d triangles %9.3f s  volume %-14.8g "
                   "rel.err %-10.2e peak %.1f MiB\n",
                   name, o.chord_tol, threads == 1 ? "1" : "all", m->n_triangles, dt, v,
                   ref_mm3 > 0 ? fabs(v - ref_mm3) / ref_mm3 : NAN, peak_mib());
            cb_mesh_clear(m);
        }
    }
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : getenv("COLIBRI_SHARED") ? getenv("COLIBRI_SHARED")
                                                                     : "../shared";
    static const struct {
        const char *file;
        double volume;
    } models[] = {{"trj5_k1-al-214.stp", 7936.1475},
                  {"linkrods.step", 3.847013},
                  {"ujoint_fork.step", 81046.104},
                  {"ujoint_cross.step", 95097.336}};
    printf("tessellation (%d hardware threads); rel.err against models/SOURCES.md volumes\n",
           cb_parallel_max_threads());
    for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/models/%s", dir, models[k].file);
        cb_topo_body *b;
        cb_error err;
        if (cb_step_read(&b, path, &err)) {
            printf("%-20s %s\n", models[k].file, err.msg);
            continue;
        }
        run(models[k].file, b, models[k].volume);
        cb_topo_body_free(b);
    }
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    cb_topo_body *b;
    cb_error err;
    if (cb_model_hummingbird(&b, &p, &err) || cb_topo_compute_pcurves(b, b->tol, &err)) {
        printf("hummingbird: %s\n", err.msg);
        return 1;
    }
    run("hummingbird", b, 0);
    cb_topo_body_free(b);
    return 0;
}
