/* bench_ssi.c — B-spline/B-spline intersection by the subdivision route on the hummingbird
 * (312 bicubic faces) against a posed copy, as in the paper's Fig. 12 (Yang, Jia, Yan, ACM TOG
 * 2023: 99 intersecting patch pairs there). Prints times for 1, 2 and all threads, the counts,
 * the largest distance of a curve point to each face at its own parameters, and whether the
 * runs agree point for point.
 *
 * usage: bench_ssi [angle_deg [tx ty tz]]   (default pose: 25 degrees about (0.3, 1, 0.2),
 *                                            translated by (0.35, 0.25, 0.12)) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench_ssi_same.h"
#include "models/models.h"
#include "ssi/ssi.h"

static double now_s(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double face_dist(const cb_topo_body *b, int face, const double uv[2], const double X[3])
{
    double p[3];
    cb_nurbs_surface_eval(p, b->surfaces[b->faces[face].surface].nurbs, uv[0], uv[1]);
    return sqrt((p[0] - X[0]) * (p[0] - X[0]) + (p[1] - X[1]) * (p[1] - X[1]) +
                (p[2] - X[2]) * (p[2] - X[2]));
}

int main(int argc, char **argv)
{
    cb_hummingbird_params pa, pb;
    cb_hummingbird_params_default(&pa);
    cb_hummingbird_params_default(&pb);
    pb.axis[0] = 0.3;
    pb.axis[1] = 1;
    pb.axis[2] = 0.2;
    pb.angle_deg = argc > 1 ? atof(argv[1]) : 25;
    pb.translate[0] = argc > 4 ? atof(argv[2]) : 0.35;
    pb.translate[1] = argc > 4 ? atof(argv[3]) : 0.25;
    pb.translate[2] = argc > 4 ? atof(argv[4]) : 0.12;
    cb_topo_body *a = NULL, *b = NULL;
    cb_error err;
    cb_error_clear(&err);
    double t0 = now_s();
    if (cb_model_hummingbird(&a, &pa, &err) != CB_OK ||
        cb_model_hummingbird(&b, &pb, &err) != CB_OK) {
        fprintf(stderr, "bench_ssi: %s\n", err.msg);
        return 1;
    }
    printf("hummingbird x posed copy (%.0f deg about (0.3, 1, 0.2), moved by (%g, %g, %g)): "
           "%d x %d faces, built in %.2f s\n",
           pb.angle_deg, pb.translate[0], pb.translate[1], pb.translate[2], a->n_faces, b->n_faces,
           now_s() - t0);
    const int threads[3] = {1, 2, 0};
    cb_ssi_result_t r[3];
    for (int k = 0; k < 3; k++) {
        cb_ssi_opts o;
        cb_ssi_opts_default(&o);
        o.threads = threads[k];
        cb_ssi_result_init(r[k]);
        t0 = now_s();
        clock_t c0 = clock();
        cb_status st = cb_ssi_bodies(r[k], a, b, &o, &err);
        double t = now_s() - t0, cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
        if (st != CB_OK) {
            fprintf(stderr, "bench_ssi: %s\n", err.msg);
            return 1;
        }
        printf("threads %d: %.2f s wall, %.2f s cpu (summed over Bezier pairs: subdivision, "
               "certification and marching %.2f s)\n",
               threads[k], t, cpu, r[k]->time_topo);
    }
    const cb_ssi_result_struct *R = r[0];
    /* Face pairs with a curve (the paper's "intersecting patch pairs"). */
    char *hit = calloc((size_t)a->n_faces * (size_t)b->n_faces, 1);
    slong pairs_hit = 0, closed = 0, npts = 0;
    double dmax = 0;
    for (slong c = 0; c < R->n_curves; c++) {
        const cb_ssi_curve *cv = R->curve + c;
        char *h = hit + (size_t)cv->face_a * (size_t)b->n_faces + (size_t)cv->face_b;
        pairs_hit += !*h;
        *h = 1;
        closed += cv->closed;
        npts += cv->n;
        for (slong i = 0; i < cv->n; i++) {
            dmax = fmax(dmax, face_dist(a, cv->face_a, cv->pt[i].uv_a, cv->pt[i].xyz));
            dmax = fmax(dmax, face_dist(b, cv->face_b, cv->pt[i].uv_b, cv->pt[i].xyz));
        }
    }
    printf("face pairs with a curve: %ld; curves %ld (%ld closed, %ld points), isolated %ld\n",
           (long)pairs_hit, (long)R->n_curves, (long)closed, (long)npts, (long)R->n_points);
    printf("Bezier patch pairs: %ld considered, %ld culled by boxes, %ld by subdivision, "
           "%ld certified; sub-patch pairs %ld\n",
           (long)R->pairs_total, (long)R->pairs_culled, (long)R->pairs_subdivided,
           (long)R->pairs_certified, (long)R->subpairs);
    printf("not certified: %ld pairs (status %s)\n", (long)R->n_failed, cb_status_name(R->status));
    for (slong k = 0; k < R->n_failed && k < 10; k++) {
        const cb_ssi_failure *f = R->failed + k;
        printf("  faces %d, %d patches %d, %d: %s", f->face_a, f->face_b, f->patch_a, f->patch_b,
               f->msg);
        if (f->has_box)
            printf(" boxes [%.4g, %.4g] x [%.4g, %.4g] / [%.4g, %.4g] x [%.4g, %.4g]", f->box_a[0],
                   f->box_a[1], f->box_a[2], f->box_a[3], f->box_b[0], f->box_b[1], f->box_b[2],
                   f->box_b[3]);
        printf("\n");
    }
    /* Curves of neighbouring face pairs must continue each other: every end of an open curve
     * meets the end of another curve (the intersection of two closed surfaces has no ends). */
    slong ends = 0, lonely = 0;
    for (slong c = 0; c < R->n_curves; c++) {
        const cb_ssi_curve *cv = R->curve + c;
        if (cv->closed)
            continue;
        for (int e = 0; e < 2; e++) {
            const double *X = cv->pt[e ? cv->n - 1 : 0].xyz;
            int found = 0;
            for (slong d = 0; d < R->n_curves && !found; d++) {
                const cb_ssi_curve *dv = R->curve + d;
                for (int f = 0; f < 2 && !found; f++) {
                    if (d == c && f == e)
                        continue;
                    const double *Y = dv->pt[f ? dv->n - 1 : 0].xyz;
                    found = fabs(X[0] - Y[0]) + fabs(X[1] - Y[1]) + fabs(X[2] - Y[2]) <= 2 * R->tol;
                }
            }
            ends++;
            lonely += !found;
            if (!found && lonely <= 5)
                printf("  end %d of curve %ld (faces %d, %d; %ld points) at (%.9g, %.9g, %.9g) "
                       "uv_a (%.9g, %.9g) uv_b (%.9g, %.9g) has no continuation\n",
                       e, (long)c, cv->face_a, cv->face_b, (long)cv->n, X[0], X[1], X[2],
                       cv->pt[e ? cv->n - 1 : 0].uv_a[0], cv->pt[e ? cv->n - 1 : 0].uv_a[1],
                       cv->pt[e ? cv->n - 1 : 0].uv_b[0], cv->pt[e ? cv->n - 1 : 0].uv_b[1]);
        }
    }
    printf("curve ends: %ld, without a continuation: %ld\n", (long)ends, (long)lonely);
    printf("largest distance of a curve point to its faces: %.2e (tol %.2e): %s\n", dmax, R->tol,
           dmax <= R->tol ? "ok" : "FAILED");
    printf("1 vs 2 threads identical: %s; 1 vs all: %s\n",
           bench_ssi_same(r[0], r[1]) ? "yes" : "NO", bench_ssi_same(r[0], r[2]) ? "yes" : "NO");
    free(hit);
    for (int k = 0; k < 3; k++)
        cb_ssi_result_clear(r[k]);
    cb_topo_body_free(a);
    cb_topo_body_free(b);
    return 0;
}
