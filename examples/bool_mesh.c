/* bool_mesh.c — a Boolean from a C program: read two STEP solids, compute their union,
 * intersection or difference, integrate the result's volume, mesh it, check and write it.
 *
 *   bool_mesh union|intersection|difference A.step B.step OUT.{stl,obj,ply,off}
 *
 * Exit status: 0 a checked mesh was written, 1 the operation or a check failed, 2 bad usage or
 * an operand that could not be read. */
#include <colibri/colibri.h>

#include <stdio.h>
#include <string.h>

static int fail(const char *what, const cb_error *err, int code)
{
    fprintf(stderr, "bool_mesh: %s: %s\n", what, err->msg);
    return code;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: bool_mesh union|intersection|difference A.step B.step OUT\n");
        return 2;
    }
    cb_bool_op op;
    if (!strcmp(argv[1], "union"))
        op = CB_BOOL_UNION;
    else if (!strcmp(argv[1], "intersection"))
        op = CB_BOOL_INTERSECTION;
    else if (!strcmp(argv[1], "difference"))
        op = CB_BOOL_DIFFERENCE;
    else {
        fprintf(stderr, "bool_mesh: unknown operation '%s'\n", argv[1]);
        return 2;
    }
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *a = NULL, *b = NULL, *result = NULL;
    if (cb_step_read(&a, argv[2], &err))
        return fail(argv[2], &err, 2);
    if (cb_step_read(&b, argv[3], &err)) {
        cb_topo_body_free(a);
        return fail(argv[3], &err, 2);
    }

    /* Defaults: tolerance 1e-6 of the operands' size, all hardware threads, no progress. */
    cb_bool_stats stats;
    int code = 0;
    if (cb_bool_run(&result, &stats, op, a, b, NULL, NULL, &err))
        code = fail(cb_bool_op_name(op), &err, 1);
    cb_mass_props mass;
    if (!code && cb_mass_body(&mass, result, CB_MASS_REL_TOL, NULL, &err))
        code = fail("volume", &err, 1);
    if (!code)
        printf("%s: %d intersection curves, result %d faces, volume %.10g\n",
               cb_bool_op_name(op), stats.curves, result->n_faces, mass.volume);

    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_mesh_check_report check;
    if (!code && cb_tess_body(mesh, result, NULL, NULL, &err))
        code = fail("tessellation", &err, 1);
    if (!code && cb_mesh_check(&check, mesh, &err))
        code = fail("mesh check", &err, 1);
    if (!code && !cb_mesh_check_passed(&check)) {
        fprintf(stderr, "bool_mesh: the mesh failed its checks\n");
        code = 1;
    }
    if (!code && cb_mesh_write(argv[4], mesh, NULL, &err))
        code = fail(argv[4], &err, 2);
    if (!code)
        printf("wrote %s: %d triangles, mesh volume %.10g\n", argv[4], check.triangles,
               check.volume);
    cb_mesh_clear(mesh);
    cb_topo_body_free(result);
    cb_topo_body_free(a);
    cb_topo_body_free(b);
    return code;
}
