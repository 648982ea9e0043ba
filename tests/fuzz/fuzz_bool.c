/* libFuzzer target: the Boolean entry (cb_bool_run) on small generated solids. The bytes pick
 * two primitives (box, sphere, cylinder; analytic or exact rational B-spline faces), their
 * sizes and placements on a coarse grid (so that touching, coincident and tangent
 * configurations come up often) and the operation. Every run must return a status, never
 * crash, leak or read out of bounds; a result it returns must be indexed and pass through
 * validation without error. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "boolean/bool.h"
#include "brep/prim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Next byte of the input, 0 when it runs out. */
static unsigned next(const uint8_t *data, size_t size, size_t *at)
{
    return *at < size ? data[(*at)++] : 0;
}

static cb_topo_body *make(const uint8_t *data, size_t size, size_t *at)
{
    unsigned kind = next(data, size, at) % 3, nurbs = next(data, size, at) & 1;
    double o[3], s[3];
    for (int k = 0; k < 3; k++)
        o[k] = ((int)(next(data, size, at) % 9) - 4) * 0.25;
    for (int k = 0; k < 3; k++)
        s[k] = 0.25 + (next(data, size, at) % 8) * 0.25;
    double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const double *axis = axes[next(data, size, at) % 3];
    const double *ref = axes[(next(data, size, at) % 2 + (axis == axes[0] ? 1 : 0)) % 3];
    if (ref == axis)
        ref = axes[(axis - axes[0] + 1) % 3];
    cb_frame f;
    cb_error err;
    cb_topo_body *b = NULL;
    if (cb_frame_make(&f, o, axis, ref, &err))
        return NULL;
    double lo[3] = {0, 0, 0};
    switch (kind) {
    case 0:
        cb_prim_box(&b, &f, lo, s, (int)nurbs, 0, &err);
        break;
    case 1:
        cb_prim_sphere(&b, &f, s[0], (int)nurbs, 0, &err);
        break;
    default:
        cb_prim_cylinder(&b, &f, s[0], s[1], (int)nurbs, 0, &err);
        break;
    }
    return b;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    size_t at = 0;
    cb_bool_op op = (cb_bool_op)(next(data, size, &at) % 3);
    cb_topo_body *a = make(data, size, &at), *b = make(data, size, &at), *r = NULL;
    if (a && b) {
        cb_error err;
        if (cb_bool_run(&r, NULL, op, a, b, NULL, NULL, &err) == CB_OK) {
            if (!r || !r->edge_start)
                abort();
            cb_topo_report rep;
            cb_topo_report_init(&rep);
            if (cb_topo_validate(&rep, r, r->tol, 5, &err) != CB_OK)
                abort();
            cb_topo_report_clear(&rep);
        }
    }
    cb_topo_body_free(r);
    cb_topo_body_free(a);
    cb_topo_body_free(b);
    return 0;
}
