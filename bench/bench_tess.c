/* bench_tess: tessellation time, triangle count, mesh volume error and peak memory per model,
 * at the default chordal tolerance and finer ones, with 1 thread and all threads. Each model
 * is read and meshed in a process of its own (this program started again with --model), so
 * that its peak resident memory, a high-water mark of the whole process, is its own: the
 * peak of loading it and meshing it at every tolerance listed.
 * Usage: bench_tess [SHARED_DIR]  (default $COLIBRI_SHARED or ../shared)
 * Internal: bench_tess --model K SHARED_DIR */
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

/* Peak resident set of this process, MiB. */
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
                   "rel.err %.2e\n",
                   name, o.chord_tol, threads == 1 ? "1" : "all", m->n_triangles, dt, v,
                   ref_mm3 > 0 ? fabs(v - ref_mm3) / ref_mm3 : NAN);
            cb_mesh_clear(m);
        }
    }
}

static const struct {
    const char *file; /* in SHARED_DIR/models; NULL: the hummingbird */
    double volume;    /* mm^3, models/SOURCES.md; 0: none */
} models[] = {{"trj5_k1-al-214.stp", 7936.1475},
              {"linkrods.step", 3.847013},
              {"ujoint_fork.step", 81046.104},
              {"ujoint_cross.step", 95097.336},
              {NULL, 0}};

/* Model k, read or built, meshed at every tolerance, then this process's peak. */
static int model_mode(int k, const char *dir)
{
    cb_topo_body *b = NULL;
    cb_error err;
    const char *name = models[k].file ? models[k].file : "hummingbird";
    if (models[k].file) {
        char path[1024];
        snprintf(path, sizeof path, "%s/models/%s", dir, models[k].file);
        if (cb_step_read(&b, path, &err)) {
            printf("%-20s %s\n", name, err.msg);
            return 1;
        }
    } else {
        cb_hummingbird_params p;
        cb_hummingbird_params_default(&p);
        if (cb_model_hummingbird(&b, &p, &err) || cb_topo_compute_pcurves(b, b->tol, &err)) {
            printf("%-20s %s\n", name, err.msg);
            cb_topo_body_free(b);
            return 1;
        }
    }
    run(name, b, models[k].volume);
    cb_topo_body_free(b);
    printf("%-20s peak %.1f MiB (the process that loaded it and made every mesh above)\n", name,
           peak_mib());
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "--model"))
        return model_mode(atoi(argv[2]), argv[3]);
    const char *dir = argc > 1 ? argv[1] : getenv("COLIBRI_SHARED") ? getenv("COLIBRI_SHARED")
                                                                     : "../shared";
    printf("tessellation (%d hardware threads); rel.err against models/SOURCES.md volumes\n",
           cb_parallel_max_threads());
    fflush(stdout);
    int bad = 0;
    for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
        char cmd[4096], line[512];
        snprintf(cmd, sizeof cmd, "'%s' --model %zu '%s'", argv[0], k, dir);
        FILE *p = popen(cmd, "r");
        if (!p) {
            printf("model %zu: cannot start %s\n", k, argv[0]);
            bad = 1;
            continue;
        }
        while (fgets(line, sizeof line, p))
            fputs(line, stdout);
        bad |= pclose(p) != 0;
        fflush(stdout);
    }
    return bad;
}
