/* Tessellation of a whole body: shared edge samples, faces in parallel, assembly in face
 * order. */
#include <stdlib.h>
#include <string.h>

#include "brep/parallel.h"
#include "brep/tess.h"

typedef struct {
    const cb_topo_body *b;
    const cb_tess_edges *es;
    const cb_tess_opts *o;
    cb_context *ctx;
    cb_tess_face_mesh *fm;
    cb_status *st;
    cb_error *errs;
    int done;
} body_job;

static void face_body(void *arg, size_t begin, size_t end)
{
    body_job *j = arg;
    for (size_t f = begin; f < end; f++) {
        if (cb_context_cancelled(j->ctx)) {
            j->st[f] = cb_error_set(&j->errs[f], CB_ERR_CANCELLED, "tessellation: cancelled");
            continue;
        }
        j->st[f] = cb_tess_face(&j->fm[f], j->b, (int)f, j->es, j->o, j->ctx, &j->errs[f]);
        int done = __atomic_add_fetch(&j->done, 1, __ATOMIC_RELAXED);
        cb_context_progress(j->ctx, 1 + 19.0 * done / j->b->n_faces, 20, "tessellate");
    }
}

/* Vertices used by a triangle, renumbered in order (shared samples, then each face's own). */
static cb_status assemble(cb_mesh_t out, const cb_tess_edges *es, const cb_tess_face_mesh *fm,
                          int n_faces, cb_error *err)
{
    long nv = 0, nt = 0;
    for (int f = 0; f < n_faces; f++) {
        nv += fm[f].n_points;
        nt += fm[f].n_tris;
    }
    int *map = malloc((size_t)(es->n_points + 1) * sizeof(int));
    if (!map)
        return cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    for (int i = 0; i < es->n_points; i++)
        map[i] = -1;
    for (int f = 0; f < n_faces; f++)
        for (int k = 0; k < 3 * fm[f].n_tris; k++)
            if (fm[f].tri[k] < es->n_points)
                map[fm[f].tri[k]] = 0;
    int n_shared = 0;
    for (int i = 0; i < es->n_points; i++)
        if (map[i] == 0)
            map[i] = n_shared++;
    cb_status st = CB_OK;
    if (n_shared + nv > 2000000000L || nt > 2000000000L)
        st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: mesh too large (%ld triangles)", nt);
    if (!st)
        st = cb_mesh_reserve(out, (int)(n_shared + nv), (int)nt, err);
    for (int i = 0; i < es->n_points && !st; i++)
        if (map[i] >= 0)
            st = cb_mesh_append_vertex(out, es->xyz + 3 * i, err);
    int base = n_shared;
    for (int f = 0; f < n_faces && !st; f++) {
        for (int k = 0; k < fm[f].n_points && !st; k++)
            st = cb_mesh_append_vertex(out, fm[f].xyz + 3 * k, err);
        for (int t = 0; t < fm[f].n_tris && !st; t++) {
            int v[3];
            for (int i = 0; i < 3; i++) {
                int x = fm[f].tri[3 * t + i];
                v[i] = x < es->n_points ? map[x] : base + x - es->n_points;
            }
            st = cb_mesh_append_triangle(out, v[0], v[1], v[2], err);
        }
        base += fm[f].n_points;
    }
    free(map);
    return st;
}

cb_status cb_tess_body(cb_mesh_t out, const cb_topo_body *b, const cb_tess_opts *o,
                       cb_context *ctx, cb_error *err)
{
    cb_mesh_clear(out);
    cb_tess_opts ro;
    cb_status st = cb_tess_opts_resolve(&ro, o, b, err);
    if (st)
        return st;
    if (!b->edge_start)
        return cb_error_set(err, CB_ERR_INVALID,
                            "tessellation: the body is not indexed (cb_topo_body_index)");
    cb_tess_edges es;
    cb_tess_edges_init(&es);
    if ((st = cb_tess_edges_sample(&es, b, &ro, ctx, err)))
        return st;
    int nf = b->n_faces;
    body_job j = {b, &es, &ro, ctx, NULL, NULL, NULL, 0};
    j.fm = calloc((size_t)nf + 1, sizeof(cb_tess_face_mesh));
    j.st = calloc((size_t)nf + 1, sizeof(cb_status));
    j.errs = calloc((size_t)nf + 1, sizeof(cb_error));
    if (!j.fm || !j.st || !j.errs)
        st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    if (!st)
        st = cb_parallel_for((size_t)nf, 1, cb_context_threads(ctx), face_body, &j);
    if (st == CB_ERR_NOMEM)
        cb_error_set(err, st, "tessellation: the thread pool failed");
    /* The first failure in face order, so the message does not depend on scheduling; a
     * cancellation wins over the errors it may have caused. */
    for (int f = 0; f < nf && !st; f++)
        if (j.st[f] == CB_ERR_CANCELLED)
            st = cb_error_set(err, CB_ERR_CANCELLED, "tessellation: cancelled");
    for (int f = 0; f < nf && !st; f++)
        if (j.st[f]) {
            st = j.st[f];
            if (err)
                *err = j.errs[f];
        }
    if (!st && cb_context_cancelled(ctx))
        st = cb_error_set(err, CB_ERR_CANCELLED, "tessellation: cancelled");
    if (!st)
        st = assemble(out, &es, j.fm, nf, err);
    if (j.fm)
        for (int f = 0; f < nf; f++)
            cb_tess_face_mesh_clear(&j.fm[f]);
    free(j.fm);
    free(j.st);
    free(j.errs);
    cb_tess_edges_clear(&es);
    if (st)
        cb_mesh_clear(out);
    return st;
}
