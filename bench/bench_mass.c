/* Mass properties (brep/mass.h): time per primitive (analytic and B-spline faces) and per
 * shipped STEP model, at relative accuracies 1e-6 and 1e-10, with the volume and area found.
 * Usage: bench_mass [threads] (default 1; models from $COLIBRI_SHARED/models). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "brep/mass.h"
#include "brep/prim.h"
#include "io/step.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void run(const char *name, const cb_topo_body *b, int threads)
{
    static const double rels[2] = {1e-6, 1e-10};
    printf("%-24s", name);
    for (int k = 0; k < 2; k++) {
        cb_context ctx;
        cb_context_init(&ctx);
        ctx.threads = threads;
        cb_mass_props m;
        cb_error err;
        double t = now();
        cb_status st = cb_mass_body(&m, b, rels[k], &ctx, &err);
        t = now() - t;
        double u = b->length_unit_mm;
        if (st)
            printf(" | rel %.0e: %s", rels[k], err.msg);
        else
            printf(" | rel %.0e: %9.4f s  V %.12g  A %.12g", rels[k], t, m.volume * u * u * u,
                   m.area * u * u);
        fflush(stdout);
    }
    printf("\n");
}

int main(int argc, char **argv)
{
    int threads = argc > 1 ? atoi(argv[1]) : 1;
    const char *shared = getenv("COLIBRI_SHARED");
    if (!shared)
        shared = "../shared";
    printf("mass properties, %d thread(s); volumes mm^3, areas mm^2\n", threads);
    for (int nurbs = 0; nurbs < 2; nurbs++) {
        const double lo[3] = {-1, -0.5, 0.25}, hi[3] = {2, 1.5, 1.25};
        cb_topo_body *b[7] = {NULL};
        const char *names[7] = {"box",     "sphere", "ellipsoid", "cylinder",
                                "frustum", "cone",   "torus"};
        cb_error err;
        cb_prim_box(&b[0], NULL, lo, hi, nurbs, 0, &err);
        cb_prim_sphere(&b[1], NULL, 1.5, nurbs, 0, &err);
        cb_prim_ellipsoid(&b[2], NULL, 2, 1, 0.5, nurbs, 0, &err);
        cb_prim_cylinder(&b[3], NULL, 0.75, 2, nurbs, 0, &err);
        cb_prim_cone(&b[4], NULL, 1, 0.5, 1.5, nurbs, 0, &err);
        cb_prim_cone(&b[5], NULL, 1.25, 0, 2, nurbs, 0, &err);
        cb_prim_torus(&b[6], NULL, 2, 0.5, nurbs, 0, &err);
        for (int k = 0; k < 7; k++) {
            char name[64];
            snprintf(name, sizeof name, "%s (%s)", names[k], nurbs ? "B-spline" : "analytic");
            if (b[k])
                run(name, b[k], threads);
            cb_topo_body_free(b[k]);
        }
    }
    const char *files[4] = {"ujoint_cross.step", "ujoint_fork.step", "trj5_k1-al-214.stp",
                            "linkrods.step"};
    for (int k = 0; k < 4; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/models/%s", shared, files[k]);
        cb_topo_body *b = NULL;
        cb_error err;
        int dropped;
        if (cb_step_read(&b, path, &err) || cb_topo_repair_pcurves(b, b->tol, 17, &dropped, &err)) {
            printf("%-24s %s\n", files[k], err.msg);
            cb_topo_body_free(b);
            continue;
        }
        run(files[k], b, threads);
        cb_topo_body_free(b);
    }
    return 0;
}
