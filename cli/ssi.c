/* colibri ssi: intersection curves of the faces of two STEP models. */
#define _POSIX_C_SOURCE 200809L /* isatty */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "boolean/bool.h"
#include "cli/commands.h"
#include "cli/ssi_svg.h"
#include "io/step.h"
#include "ssi/ssi.h"
#include "io/json.h"

static const char SSI_USAGE[] =
    "usage: colibri ssi A.step B.step [--json OUT.json] [--svg DIR] [--tol T] [--threads N]\n"
    "                   [--max-phi-degree D] [--quiet] [--rotate-b AX AY AZ DEG]\n"
    "                   [--translate-b X Y Z]\n"
    "\n"
    "Intersects every face of A with every face of B whose boxes overlap, with the\n"
    "topology-guaranteed surface/surface intersection, and prints the counts: curves,\n"
    "isolated points, face pairs, patch pairs (culled by boxes, proved empty, certified,\n"
    "resolved within tolerance, refused), the patch pairs taken by the subdivision route\n"
    "(B-spline pairs) and the\n"
    "sub-patch pairs it examined, the largest distance of an output point to each surface,\n"
    "and timings.\n"
    "Handled and tested: analytic (plane, cylinder, cone, sphere, torus) against B-spline\n"
    "faces; B-spline pairs (low degrees algebraically, the rest by certified subdivision).\n"
    "Curves and isolated points are clipped to both faces' trimming loops: a curve leaving a\n"
    "face ends on its boundary, refined onto both surfaces. Every result is certified,\n"
    "resolved within tolerance (its region listed) or refused (listed), never dropped; a\n"
    "refused region proved to lie outside one of the trimmed faces is listed, not refused.\n"
    "\n"
    "options:\n"
    "  --json OUT   write {\"tolerance\", \"time_s\", \"branches\": [{\"face_a\", \"face_b\",\n"
    "               \"kind\": \"curve\"|\"point\", \"closed\", \"tangential\", \"certified\",\n"
    "               \"xyz\", \"uv_a\", \"uv_b\"}], \"pairs\": {\"certified\",\n"
    "               \"within_tolerance\", \"outside_face\", \"refused\"}, \"coincident\":\n"
    "               [{\"face_a\", \"face_b\", \"patch_pairs\", \"whole\", \"exact\", \"width\",\n"
    "               \"same_face_normal\"}], \"within_tolerance\": [{\"face_a\", \"face_b\",\n"
    "               \"patch_a\", \"patch_b\", \"kind\":\n"
    "               \"coincidence\"|\"near_node\"|\"contact_band\"|\"side\"|\"outside_face\",\n"
    "               \"width\", \"box_a\", \"box_b\", \"lo\", \"hi\"}], \"not_certified\":\n"
    "               [{\"face_a\", \"face_b\", \"patch_a\", \"patch_b\", \"status\",\n"
    "               \"message\"}] (the refused)}; a periodic parameter lies in one\n"
    "               period around the face's loops (a loop around a cylinder jumps\n"
    "               by the period at the seam)\n"
    "  --svg DIR    write DIR/pair_FA_FB.svg (DIR made if missing) for every face pair with\n"
    "               a curve or point: both parameter domains with the curves, isolated\n"
    "               points, the certified topology's critical, helping and box-side points,\n"
    "               knot lines (Bezier patch boundaries) and trimming loops\n"
    "  --tol T      distance of every output point to both surfaces (default 1e-6 times\n"
    "               the diagonal of the models' box)\n"
    "  --threads N  threads for patch pairs (default 0: all hardware threads)\n"
    "  --max-phi-degree D  highest degree of phi = F(Q) in s or t that the algebraic route\n"
    "               takes (default 12); pairs above it take the subdivision route (B-spline\n"
    "               pairs) or are listed not certified. The paper's Example 2 needs 27 (about\n"
    "               6 s); the topology's time grows fast with it\n"
    "  --quiet      print nothing on stdout (the exit status and --json OUT still tell)\n"
    "               and no progress (face pairs done, on stderr when it is a terminal);\n"
    "               errors still go to stderr\n"
    "  --rotate-b AX AY AZ DEG  turn B by DEG degrees about the axis (AX, AY, AZ) through\n"
    "               the origin first (B against a moved copy of itself)\n"
    "  --translate-b X Y Z  then move B by (X, Y, Z)\n"
    "\n"
    "Exit status: 0 every pair was certified or resolved within tolerance, 1 the work failed\n"
    "(numerically or unsupported) or some pair was refused, 2 bad usage or a file that cannot\n"
    "be used (missing, unreadable, malformed: the message names file:line and the entity #id),\n"
    "including an OUT.json or DIR that cannot be written.\n";

static double wall_s(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void json_points(FILE *f, const char *key, const cb_ssi_point *p, slong n, int which)
{
    fprintf(f, "\"%s\": [", key);
    for (slong i = 0; i < n; i++) {
        if (which == 0)
            fprintf(f, "%s[%.17g, %.17g, %.17g]", i ? ", " : "", p[i].xyz[0], p[i].xyz[1],
                    p[i].xyz[2]);
        else {
            const double *uv = which == 1 ? p[i].uv_a : p[i].uv_b;
            fprintf(f, "%s[%.17g, %.17g]", i ? ", " : "", uv[0], uv[1]);
        }
    }
    fprintf(f, "]");
}

static void json_branch(FILE *f, int first, int fa, int fb, const char *kind, int closed,
                        int tangential, int certified, const cb_ssi_point *p, slong n)
{
    fprintf(f, "%s\n  {\"face_a\": %d, \"face_b\": %d, \"kind\": \"%s\", \"closed\": %s, "
               "\"tangential\": %s, \"certified\": %s, ",
            first ? "" : ",", fa, fb, kind, closed ? "true" : "false",
            tangential ? "true" : "false", certified ? "true" : "false");
    json_points(f, "xyz", p, n, 0);
    fprintf(f, ", ");
    json_points(f, "uv_a", p, n, 1);
    fprintf(f, ", ");
    json_points(f, "uv_b", p, n, 2);
    fprintf(f, "}");
}

static int write_json(const char *path, const cb_ssi_result_t r, double t)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "colibri ssi: cannot write %s\n", path);
        return 0;
    }
    fprintf(f, "{\"tolerance\": %.17g, \"time_s\": %.6f,\n \"branches\": [", r->tol, t);
    int first = 1;
    for (slong c = 0; c < r->n_curves; c++, first = 0) {
        const cb_ssi_curve *cv = r->curve + c;
        json_branch(f, first, cv->face_a, cv->face_b, "curve", cv->closed, cv->tangential,
                    cv->certified, cv->pt, cv->n);
    }
    for (slong q = 0; q < r->n_points; q++, first = 0) {
        const cb_ssi_isolated *p = r->point + q;
        json_branch(f, first, p->face_a, p->face_b, "point", 0, p->tangential, p->certified,
                    &p->p, 1);
    }
    fprintf(f, "],\n \"pairs\": {\"certified\": %ld, \"within_tolerance\": %ld, "
               "\"outside_face\": %ld, \"refused\": %ld},\n \"coincident\": [",
            (long)r->pairs_certified, (long)r->pairs_within_tolerance,
            (long)r->pairs_outside_face, (long)r->n_failed);
    for (slong k = 0; k < r->n_coincident; k++) {
        const cb_ssi_coincident *c = r->coincident + k;
        fprintf(f, "%s\n  {\"face_a\": %d, \"face_b\": %d, \"patch_pairs\": %ld, \"whole\": %s, "
                   "\"exact\": %s, \"width\": %.17g, \"same_face_normal\": %s}",
                k ? "," : "", c->face_a, c->face_b, (long)c->patch_pairs,
                c->whole ? "true" : "false", c->exact ? "true" : "false", c->width,
                c->same_face_normal ? "true" : "false");
    }
    fprintf(f, "],\n \"within_tolerance\": [");
    for (slong k = 0; k < r->n_regions; k++) {
        const cb_ssi_region *g = r->region + k;
        fprintf(f, "%s\n  {\"face_a\": %d, \"face_b\": %d, \"patch_a\": %d, \"patch_b\": %d, "
                   "\"kind\": \"%s\", \"width\": %.17g, \"box_a\": [%.17g, %.17g, %.17g, %.17g], "
                   "\"box_b\": [%.17g, %.17g, %.17g, %.17g], \"lo\": [%.17g, %.17g, %.17g], "
                   "\"hi\": [%.17g, %.17g, %.17g]}",
                k ? "," : "", g->face_a, g->face_b, g->patch_a, g->patch_b,
                cb_ssi_region_kind_name(g->kind), g->width, g->box_a[0], g->box_a[1],
                g->box_a[2], g->box_a[3], g->box_b[0], g->box_b[1], g->box_b[2], g->box_b[3],
                g->lo[0], g->lo[1], g->lo[2], g->hi[0], g->hi[1], g->hi[2]);
    }
    fprintf(f, "],\n \"not_certified\": [");
    for (slong k = 0; k < r->n_failed; k++) {
        const cb_ssi_failure *x = r->failed + k;
        fprintf(f, "%s\n  {\"face_a\": %d, \"face_b\": %d, \"patch_a\": %d, \"patch_b\": %d, "
                   "\"status\": \"%s\", \"message\": ",
                k ? "," : "", x->face_a, x->face_b, x->patch_a, x->patch_b,
                cb_status_name(x->status));
        cb_json_string(f, x->msg);
        fprintf(f, "}");
    }
    fprintf(f, "]}\n");
    int ok = !ferror(f);
    ok &= fclose(f) == 0;
    if (!ok)
        fprintf(stderr, "colibri ssi: error writing %s\n", path);
    return ok;
}

int cb_cli_ssi(int argc, char **argv)
{
    const char *files[2] = {NULL, NULL}, *json = NULL, *svg = NULL;
    int nfiles = 0, quiet = 0, moved;
    cb_cli_move move;
    cb_cli_move_init(&move);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(SSI_USAGE, stdout);
            return 0;
        } else if (!strcmp(a, "--json") && i + 1 < argc) {
            json = argv[++i];
        } else if (!strcmp(a, "--svg") && i + 1 < argc) {
            svg = argv[++i];
        } else if (!strcmp(a, "--tol") && i + 1 < argc) {
            if (cb_cli_tol_arg(&o.tol, argv[++i]))
                return 2;
        } else if (!strcmp(a, "--threads") && i + 1 < argc) {
            if (cb_cli_threads_arg(&o.threads, argv[++i]))
                return 2;
        } else if (!strcmp(a, "--max-phi-degree") && i + 1 < argc) {
            char *end;
            long d = strtol(argv[++i], &end, 10);
            if (end == argv[i] || *end || d < 1 || d > 64) {
                fprintf(stderr, "colibri ssi: --max-phi-degree needs a degree in [1, 64], not "
                                "'%s'\n", argv[i]);
                return 2;
            }
            o.max_phi_degree = d;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if ((moved = cb_cli_move_parse(&move, argc, argv, &i, "ssi")) != 0) {
            if (moved < 0)
                return 2;
        } else if (a[0] == '-') {
            fprintf(stderr, "colibri ssi: unknown or incomplete option '%s'\n%s", a, SSI_USAGE);
            return 2;
        } else if (nfiles < 2) {
            files[nfiles++] = a;
        } else {
            fprintf(stderr, "colibri ssi: too many files\n%s", SSI_USAGE);
            return 2;
        }
    }
    if (nfiles != 2) {
        fprintf(stderr, "colibri ssi: two STEP files are needed\n%s", SSI_USAGE);
        return 2;
    }
    cb_topo_body *body[2] = {NULL, NULL};
    cb_error err;
    double t0 = wall_s();
    for (int k = 0; k < 2; k++) {
        cb_error_clear(&err);
        cb_status rs = cb_step_read(body + k, files[k], &err);
        if (rs != CB_OK) {
            fprintf(stderr, "colibri: %s\n", err.msg);
            cb_topo_body_free(body[0]);
            return cb_cli_input_exit(rs);
        }
    }
    cb_cli_move_apply(&move, body[1]);
    double t1 = wall_s();
    o.keep_marks = svg != NULL;
    /* Models against moved copies of themselves run for minutes: the face pairs done. */
    cb_context ctx;
    cb_context_init(&ctx);
    int tty = !quiet && isatty(STDERR_FILENO), shown = -1;
    if (tty) {
        ctx.progress = cb_cli_progress;
        ctx.user = &shown;
        o.progress = &ctx;
    }
    cb_ssi_result_t r;
    cb_ssi_result_init(r);
    cb_error_clear(&err);
    cb_status st = cb_ssi_bodies(r, body[0], body[1], &o, &err);
    if (tty)
        fputc('\n', stderr);
    slong untrimmed[2] = {r->n_curves, r->n_points};
    if (st == CB_OK)
        st = cb_bool_ssi_trim(r, body[0], body[1], r->tol, &err);
    double t2 = wall_s();
    int rc = 0;
    if (st != CB_OK) {
        fprintf(stderr, "colibri ssi: %s\n", err.msg);
        rc = 1;
    } else if (!quiet) {
        slong npts = 0;
        for (slong c = 0; c < r->n_curves; c++)
            npts += r->curve[c].n;
        printf("faces            %d x %d\n", body[0]->n_faces, body[1]->n_faces);
        printf("curves           %ld (%ld polyline points)\n", (long)r->n_curves, (long)npts);
        printf("isolated points  %ld\n", (long)r->n_points);
        printf("trimming         %ld curves and %ld isolated points on the faces' surfaces, "
               "clipped to the trimmed faces\n",
               (long)untrimmed[0], (long)untrimmed[1]);
        printf("patch pairs      %ld: culled %ld, proved empty %ld, certified %ld, "
               "within tolerance %ld (%ld regions), refused outside a face %ld, refused %ld\n",
               (long)r->pairs_total, (long)r->pairs_culled, (long)r->pairs_empty,
               (long)r->pairs_certified, (long)r->pairs_within_tolerance,
               (long)r->n_regions, (long)r->pairs_outside_face, (long)r->n_failed);
        printf("subdivision      %ld patch pairs, %ld sub-patch pairs examined\n",
               (long)r->pairs_subdivided, (long)r->subpairs);
        printf("tolerance        %.3g (max distance to A %.3g, to B %.3g)\n", r->tol,
               r->max_dist_a, r->max_dist_b);
        printf("time             read %.3f s, intersect %.3f s (topology %.3f s, tracing "
               "%.3f s summed over pairs)\n",
               t1 - t0, t2 - t1, r->time_topo, r->time_trace);
        for (slong k = 0; k < r->n_failed && k < 20; k++)
            printf("not certified    faces %d, %d patches %d, %d: %s: %s\n", r->failed[k].face_a,
                   r->failed[k].face_b, r->failed[k].patch_a, r->failed[k].patch_b,
                   cb_status_name(r->failed[k].status), r->failed[k].msg);
        if (r->n_failed > 20)
            printf("not certified    ... %ld more (see --json)\n", (long)r->n_failed - 20);
    }
    if (st == CB_OK) {
        slong nomem = 0;
        for (slong k = 0; k < r->n_failed; k++)
            nomem += r->failed[k].status == CB_ERR_NOMEM;
        if (nomem)
            fprintf(stderr, "colibri ssi: out of memory in %ld face pair%s (not certified)\n",
                    (long)nomem, nomem == 1 ? "" : "s");
        if (r->n_failed > 0)
            rc = 1;
        if (json && !write_json(json, r, t2 - t1))
            rc = 2;
        if (svg) {
            int src = cb_cli_ssi_svg(svg, r, body[0], body[1]);
            rc = src > rc ? src : rc;
        }
    }
    cb_ssi_result_clear(r);
    cb_topo_body_free(body[0]);
    cb_topo_body_free(body[1]);
    return rc;
}
