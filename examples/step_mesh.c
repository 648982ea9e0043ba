/* step_mesh.c — Colibri from a C program: read a STEP model, validate it, compute its volume
 * from the B-rep, tessellate it, check the mesh and write it.
 *
 *   step_mesh MODEL.step OUT.{stl,obj,ply,off} [CHORD_TOL]
 *
 * Exit status: 0 the mesh was written and passed every check, 1 a check failed, 2 bad usage or
 * an input that could not be read. Progress goes to stderr when it is a terminal. */
#include <colibri/colibri.h>

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static void show_progress(void *user, double fraction, const char *stage)
{
    (void)user;
    fprintf(stderr, "\r%s %3.0f%%", stage, 100 * fraction);
    if (fraction >= 1)
        fputc('\n', stderr);
}

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: step_mesh MODEL.step OUT.{stl,obj,ply,off} [CHORD_TOL]\n");
        return 2;
    }
    printf("colibri %s\n", cb_version());

    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *body = NULL;
    cb_status st = cb_step_read(&body, argv[1], &err);
    if (st) {
        fprintf(stderr, "step_mesh: %s\n", err.msg);
        return 2;
    }

    cb_topo_report report;
    cb_topo_report_init(&report);
    int code = 0;
    st = cb_topo_validate(&report, body, 0, 9, &err);
    if (st || report.n > 0) {
        fprintf(stderr, "step_mesh: %s\n", st ? err.msg : report.items[0]);
        code = 1;
    }
    cb_topo_report_clear(&report);

    cb_context ctx;
    cb_context_init(&ctx);
    if (isatty(STDERR_FILENO))
        ctx.progress = show_progress;

    cb_mass_props mass;
    if (!code) {
        st = cb_mass_body(&mass, body, CB_MASS_REL_TOL, &ctx, &err);
        if (st) {
            fprintf(stderr, "step_mesh: %s\n", err.msg);
            code = 1;
        } else {
            printf("B-rep volume %.10g, area %.10g (model units, 1 unit = %g mm)\n", mass.volume,
                   mass.area, body->length_unit_mm);
        }
    }

    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    if (!code) {
        cb_tess_opts opts;
        cb_tess_opts_init(&opts);
        if (argc == 4)
            opts.chord_tol = atof(argv[3]);
        cb_context_progress_reset(&ctx);
        st = cb_tess_body(mesh, body, &opts, &ctx, &err);
        if (st) {
            fprintf(stderr, "step_mesh: %s\n", err.msg);
            code = 1;
        }
    }
    if (!code) {
        cb_mesh_check_report check;
        st = cb_mesh_check(&check, mesh, &err);
        if (st || !cb_mesh_check_passed(&check)) {
            fprintf(stderr, "step_mesh: mesh check %s\n", st ? err.msg : "failed");
            code = 1;
        } else {
            printf("mesh: %d vertices, %d triangles, closed, manifold, outward, no "
                   "self-intersections; volume %.10g (%.2e relative to the B-rep)\n",
                   check.vertices, check.triangles, check.volume,
                   (check.volume - mass.volume) / mass.volume);
        }
    }
    if (!code) {
        st = cb_mesh_write(argv[2], mesh, NULL, &err);
        if (st) {
            fprintf(stderr, "step_mesh: %s\n", err.msg);
            code = 2;
        } else {
            printf("wrote %s\n", argv[2]);
        }
    }
    cb_mesh_clear(mesh);
    cb_topo_body_free(body);
    return code;
}
