/* Tessellation of a whole body: shared edge samples, faces in parallel, assembly in face
 * order, then the contacts refined. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/mesh_check.h"
#include "brep/parallel.h"
#include "brep/tess.h"
#include "brep/tess_internal.h"

/* Rounds of refinement where the meshes of two faces cross; each quarters the chordal
 * tolerance there (halves the triangles' size). */
#define CONTACT_ROUNDS 8
/* A round whose mesh would have more than this many times the triangles of the first is not
 * taken: a bound on the work where refining does not settle the crossings (a body that
 * really crosses itself; a contact along a curve, where the refined triangles of one face
 * keep meeting coarser ones of the other). */
#define CONTACT_GROWTH 16
/* Rounds of finer edge sampling where chords of a face's boundary cross in (u, v); each
 * quarters the chordal tolerance there. */
#define CROSS_ROUNDS 4
/* Rounds of splitting segments that triangles of two faces share (shared_sides). */
#define SPLIT_ROUNDS 3

/* The edge samples and the faces' triangles of a body. */
typedef struct {
    cb_tess_edges es;
    cb_tess_face_mesh *fm; /* one per face */
} body_mesh;

static void body_mesh_clear(body_mesh *m, int nf)
{
    if (m->fm)
        for (int f = 0; f < nf; f++)
            cb_tess_face_mesh_clear(&m->fm[f]);
    free(m->fm);
    m->fm = NULL;
    cb_tess_edges_clear(&m->es);
}

typedef struct {
    const cb_topo_body *b;
    const cb_tess_edges *es;
    const cb_tess_opts *o;
    const cb_tess_hints *h;
    cb_context *ctx;
    cb_tess_face_mesh *fm;
    const int *faces; /* the faces to mesh; NULL: all, with progress */
    cb_status *st;
    cb_error *errs;
    int done;
} body_job;

static void face_body(void *arg, size_t begin, size_t end)
{
    body_job *j = arg;
    for (size_t i = begin; i < end; i++) {
        int f = j->faces ? j->faces[i] : (int)i;
        if (cb_context_cancelled(j->ctx)) {
            j->st[i] = cb_error_set(&j->errs[i], CB_ERR_CANCELLED, "tessellation: cancelled");
            continue;
        }
        j->st[i] = cb_tess_face_hinted(&j->fm[f], j->b, f, j->es, j->o, j->h, j->ctx,
                                       &j->errs[i]);
        int done = __atomic_add_fetch(&j->done, 1, __ATOMIC_RELAXED);
        if (!j->faces)
            cb_context_progress(j->ctx, 1 + 19.0 * done / j->b->n_faces, 20, "tessellate");
    }
}

/* Meshes faces[0 .. n) (NULL: all n faces) of b into fm[face] in parallel (cb_parallel_for,
 * ctx's thread count). The error is the first failure in the list's order, so the message
 * does not depend on scheduling; a cancellation wins over the errors it may have caused. */
static cb_status mesh_faces(cb_tess_face_mesh *fm, const int *faces, int n, const cb_topo_body *b,
                            const cb_tess_edges *es, const cb_tess_opts *o,
                            const cb_tess_hints *h, cb_context *ctx, cb_error *err)
{
    body_job j = {b, es, o, h, ctx, fm, faces, NULL, NULL, 0};
    j.st = calloc((size_t)n + 1, sizeof(cb_status));
    j.errs = calloc((size_t)n + 1, sizeof(cb_error));
    cb_status st = CB_OK;
    if (!j.st || !j.errs)
        st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    if (!st)
        st = cb_parallel_for((size_t)n, 1, cb_context_threads(ctx), face_body, &j);
    if (st == CB_ERR_NOMEM)
        cb_error_set(err, st, "tessellation: the thread pool failed");
    for (int i = 0; i < n && !st; i++)
        if (j.st[i] == CB_ERR_CANCELLED)
            st = cb_error_set(err, CB_ERR_CANCELLED, "tessellation: cancelled");
    for (int i = 0; i < n && !st; i++)
        if (j.st[i]) {
            st = j.st[i];
            if (err)
                *err = j.errs[i];
        }
    if (!st && cb_context_cancelled(ctx))
        st = cb_error_set(err, CB_ERR_CANCELLED, "tessellation: cancelled");
    free(j.st);
    free(j.errs);
    return st;
}

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

/* The signed distance of p from the surface of face f, positive on its outer side (the side
 * its mesh's normals point to), or NAN where the nearest point has no normal (a pole). */
static double outer_distance(const cb_topo_body *b, int f, const cb_topo_inverter *inv,
                             const double p[3])
{
    double uv[2], d[6][3], n[3];
    cb_topo_inverter_invert(uv, inv, p, NULL);
    cb_topo_inverter_eval_derivs(d, inv, uv[0], uv[1]);
    cb_vec3_cross(n, d[1], d[2]);
    if (!(cb_vec3_normalize(n) > 0))
        return NAN;
    double s = b->faces[f].same_sense ? 1 : -1;
    return s * (cb_vec3_dot(p, n) - cb_vec3_dot(d[0], n));
}

/* Whether triangle t of face f reaches past the surface of face g where it crosses triangle
 * u of g: a point of t (its centroid, the midpoints of its sides, the feet on it of u's
 * corners) lies on the other side of g's surface than the points of f's surface they stand
 * for do (the side of the one farthest from g, which must be more than eps away: at the
 * contact itself the side is not defined), or, where f's surface stays within eps of g's,
 * one lies more than eps from its surface point. Both surfaces keep to their sides where
 * the faces only touch; a chord that does not is what crosses g's mesh, and refining t
 * brings it back. */
static int reaches_past(const cb_mesh_t m, int t, int f, int u, int g, const cb_topo_body *b,
                        const cb_topo_inverter *inv, double eps)
{
    const double *P[3], *U[3];
    for (int k = 0; k < 3; k++) {
        P[k] = m->xyz + 3 * m->tri[3 * t + k];
        U[k] = m->xyz + 3 * m->tri[3 * u + k];
    }
    double side = 0, dq[7], chord = 0;
    int n_q = 0;
    for (int k = 0; k < 7; k++) {
        double x[3], uv[2], s[3], b1 = 0, b2 = 0;
        static const double MID[3][2] = {{0.5, 0}, {0.5, 0.5}, {0, 0.5}};
        if (k < 3) {
            b1 = MID[k][0];
            b2 = MID[k][1];
        } else if (k == 3) {
            b1 = b2 = 1.0 / 3;
        } else if (cb_tri3_foot(&b1, &b2, P[0], P[1], P[2], U[k - 4]) < 0 || b1 < 0 ||
                   b2 < 0 || b1 + b2 > 1) {
            continue; /* the foot of u's corner on t's plane falls outside t */
        }
        for (int i = 0; i < 3; i++)
            x[i] = P[0][i] + b1 * (P[1][i] - P[0][i]) + b2 * (P[2][i] - P[0][i]);
        cb_topo_inverter_invert(uv, &inv[f], x, NULL);
        cb_topo_inverter_eval(s, &inv[f], uv[0], uv[1]);
        double ds = outer_distance(b, g, &inv[g], s);
        dq[n_q++] = outer_distance(b, g, &inv[g], x);
        if (fabs(ds) > fabs(side))
            side = ds;
        chord = fmax(chord, cb_vec3_dist(s, x));
    }
    /* Where the surfaces lie within eps of each other there are no sides, but chords that
     * leave their surface by more than eps can still cross by more. */
    if (!(fabs(side) > eps))
        return chord > eps;
    for (int k = 0; k < n_q; k++)
        if (dq[k] * side < 0)
            return 1;
    return 0;
}

/* Adds a zone of face f round `at`, of radius r, at chordal tolerance tol, unless one as
 * tight already holds it. (settle_contacts puts it round the centroid of a triangle found
 * reaching past, as far as its longest side: its neighbours' chords, and its face's edges
 * there, reach past too. Zones round the points found past were seen to miss them: the
 * crossings moved beside the zones, round by round.) */
static cb_status add_zone(cb_tess_zone **zs, int *n, int *cap, const double at[3], double r,
                          int f, double tol, cb_error *err)
{
    cb_tess_zone z = {{at[0], at[1], at[2]}, r, tol, f};
    for (int k = 0; k < *n; k++)
        if ((*zs)[k].face == f && (*zs)[k].chord_tol <= tol &&
            cb_vec3_dist((*zs)[k].c, z.c) + z.r <= (*zs)[k].r)
            return CB_OK;
    if (*n == *cap) {
        int nc = *cap ? 2 * *cap : 64;
        cb_tess_zone *g = realloc(*zs, (size_t)nc * sizeof *g);
        if (!g)
            return cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
        *zs = g;
        *cap = nc;
    }
    (*zs)[(*n)++] = z;
    return CB_OK;
}

/* Longest side of triangle t of m. */
static double longest_side(const cb_mesh_t m, int t)
{
    double l = 0;
    for (int k = 0; k < 3; k++)
        l = fmax(l, cb_vec3_dist(m->xyz + 3 * m->tri[3 * t + k],
                                 m->xyz + 3 * m->tri[3 * t + (k + 1) % 3]));
    return l;
}

static int face_of(const int *first, int nf, int t)
{
    int lo = 0, hi = nf;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (first[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The mesh of m's faces for new edge samples es2 and zones: the faces with new zones
 * (fresh[f]) or an edge sampled anew are meshed again; the others keep their triangles, their
 * shared samples renumbered. Into m2 (empty on failure). */
static cb_status remesh(body_mesh *m2, const body_mesh *m, const cb_tess_edges *es2,
                        const unsigned char *fresh, const cb_topo_body *b, const cb_tess_opts *o,
                        const cb_tess_hints *h, cb_context *ctx, cb_error *err)
{
    const cb_tess_edges *es = &m->es;
    int nf = b->n_faces, n_dirty = 0;
    unsigned char *changed = calloc((size_t)b->n_edges + 1, 1);
    int *map = malloc(((size_t)es->n_points + 1) * sizeof(int));
    int *dirty = malloc(((size_t)nf + 1) * sizeof(int));
    m2->fm = calloc((size_t)nf + 1, sizeof(cb_tess_face_mesh));
    cb_status st = changed && map && dirty && m2->fm
                       ? CB_OK
                       : cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    for (int i = 0; i < es->n_points && !st; i++)
        map[i] = i < b->n_vertices ? i : -1;
    for (int e = 0; e < b->n_edges && !st; e++) {
        int s = es->start[e], n = es->start[e + 1] - s, s2 = es2->start[e];
        changed[e] = n != es2->start[e + 1] - s2 || memcmp(es->t + s, es2->t + s2,
                                                            (size_t)n * sizeof(double));
        for (int k = 1; !changed[e] && k + 1 < n; k++)
            map[es->ids[s + k]] = es2->ids[s2 + k];
    }
    for (int f = 0; f < nf && !st; f++) {
        int d = fresh[f];
        const cb_topo_face *F = &b->faces[f];
        for (int l = F->first; l < F->first + F->count && !d; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++)
                d |= changed[b->coedges[c].edge];
        if (d) {
            dirty[n_dirty++] = f;
            continue;
        }
        const cb_tess_face_mesh *A = &m->fm[f];
        cb_tess_face_mesh *B = &m2->fm[f];
        B->xyz = malloc(((size_t)A->n_points + 1) * 3 * sizeof(double));
        B->tri = malloc(((size_t)A->n_tris + 1) * 3 * sizeof(int));
        if (!B->xyz || !B->tri) {
            st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
            break;
        }
        B->cap_points = A->n_points + 1;
        B->cap_tris = A->n_tris + 1;
        B->n_points = A->n_points;
        B->n_tris = A->n_tris;
        memcpy(B->xyz, A->xyz, (size_t)A->n_points * 3 * sizeof(double));
        for (int k = 0; k < 3 * A->n_tris; k++) {
            int x = A->tri[k];
            B->tri[k] = x < es->n_points ? map[x] : x - es->n_points + es2->n_points;
        }
    }
    if (!st)
        st = mesh_faces(m2->fm, dirty, n_dirty, b, es2, o, h, ctx, err);
    if (st) {
        for (int f = 0; m2->fm && f < nf; f++)
            cb_tess_face_mesh_clear(&m2->fm[f]);
        free(m2->fm);
        m2->fm = NULL;
    }
    free(changed);
    free(map);
    free(dirty);
    return st;
}

/* Where the meshes of two faces cross, the faces touch (a void touching its wall, along a
 * circle or at a point) or the body is wrong. Where they touch, each surface keeps to its
 * side, but a chord of one, within the chordal tolerance of its surface, can reach past the
 * other surface and its mesh. Such a triangle's face is refined there, its edges too
 * (CONTACT_ROUNDS rounds, the chordal tolerance quartered each round), until no triangles
 * cross. Crossings that remain are left for the mesh check to report, as are those of a
 * wrong body, which no refinement removes; so is a mesh a round could not make, or one
 * that would grow past CONTACT_GROWTH. out is m assembled, and stays so. The zones it starts
 * from, zs[0 .. n_zones) of cap_zones (those of crossing chords), are its own afterwards (freed
 * here); splits as cb_tess_hints. */
static cb_status settle_contacts(cb_mesh_t out, body_mesh *m, const cb_topo_body *b,
                                 const cb_tess_opts *o, cb_tess_zone *zs, int n_zones,
                                 int cap_zones, const int *splits, int n_splits,
                                 cb_context *ctx, cb_error *err)
{
    int nf = b->n_faces;
    int *first = malloc(((size_t)nf + 1) * sizeof(int));
    unsigned char *fresh = malloc((size_t)nf + 1), *ready = calloc((size_t)nf + 1, 1);
    cb_topo_inverter *inv = calloc((size_t)nf + 1, sizeof *inv);
    cb_mesh_t next;
    cb_mesh_init(next);
    cb_status st = first && fresh && ready && inv
                       ? CB_OK
                       : cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    double eps = b->tol > 0 ? b->tol : 1e-9 * o->chord_tol, tol = o->chord_tol;
    int n_first = out->n_triangles;
    for (int round = 0; round < CONTACT_ROUNDS && !st; round++) {
        int *pairs = NULL, n_pairs = 0;
        cb_error e2;
        /* A mesh the contact check cannot take (open, or with an edge of three triangles) is
         * the mesh check's to report. */
        if (cb_mesh_check_crossings(&pairs, &n_pairs, out, eps, &e2) || n_pairs == 0)
            break;
        first[0] = 0;
        for (int f = 0; f < nf; f++)
            first[f + 1] = first[f] + m->fm[f].n_tris;
        memset(fresh, 0, (size_t)nf);
        /* Below the body's tolerance a chord's error is no error: the surfaces are as close
         * there, and their meshes may cross by that much (cb_mesh_check_contacts). */
        tol = fmax(0.25 * tol, eps);
        int before = n_zones;
        for (int k = 0; k < n_pairs && !st; k++) {
            int t[2] = {pairs[2 * k], pairs[2 * k + 1]}, f[2];
            for (int i = 0; i < 2; i++)
                f[i] = face_of(first, nf, t[i]);
            if (f[0] == f[1])
                continue;
            /* Inverters only for the faces that cross. */
            for (int i = 0; i < 2 && !st; i++)
                if (!ready[f[i]] && !(st = cb_topo_inverter_init(
                                          &inv[f[i]], &b->surfaces[b->faces[f[i]].surface],
                                          b->tol, err)))
                    ready[f[i]] = 1;
            for (int i = 0; i < 2 && !st; i++) {
                if (!reaches_past(out, t[i], f[i], t[1 - i], f[1 - i], b, inv, eps))
                    continue;
                /* Round t, or, when t is far larger than the triangle it crosses, round
                 * that one: the crossing lies inside both. */
                double lt = longest_side(out, t[i]), lu = longest_side(out, t[1 - i]);
                int c = lt > 4 * lu ? t[1 - i] : t[i], had = n_zones;
                double at[3];
                for (int j = 0; j < 3; j++)
                    at[j] = (out->xyz[3 * out->tri[3 * c] + j] +
                             out->xyz[3 * out->tri[3 * c + 1] + j] +
                             out->xyz[3 * out->tri[3 * c + 2] + j]) / 3;
                st = add_zone(&zs, &n_zones, &cap_zones, at, fmin(lt, 4 * lu), f[i], tol, err);
                if (n_zones > had)
                    fresh[f[i]] = 1;
            }
        }
        free(pairs);
        if (st || n_zones == before)
            break;
        cb_error e3;
        cb_tess_edges es2;
        body_mesh m2 = {{0}, NULL};
        cb_tess_edges_init(&es2);
        cb_status s2 = cb_tess_edges_sample_zoned(&es2, b, o, zs, n_zones, ctx, &e3);
        cb_tess_hints h = {zs, n_zones, splits, n_splits};
        if (!s2)
            s2 = remesh(&m2, m, &es2, fresh, b, o, &h, ctx, &e3);
        m2.es = es2;
        if (!s2)
            s2 = assemble(next, &m2.es, m2.fm, nf, &e3);
        if (s2 == CB_ERR_CANCELLED || s2 == CB_ERR_NOMEM) {
            st = s2;
            if (err)
                *err = e3;
        }
        if (s2 || next->n_triangles > CONTACT_GROWTH * (double)n_first) {
            body_mesh_clear(&m2, nf);
            break;
        }
        body_mesh_clear(m, nf);
        *m = m2;
        cb_mesh_clear(out);
        *out = *next;
        cb_mesh_init(next);
    }
    cb_mesh_clear(next);
    for (int f = 0; inv && ready && f < nf; f++)
        if (ready[f])
            cb_topo_inverter_clear(&inv[f]);
    free(inv);
    free(ready);
    free(first);
    free(fresh);
    free(zs);
    return st;
}

/* Segments between two shared samples that are sides of triangles of more than one face
 * while no face's boundary joins them: where two faces meet at a thin wedge (surfaces
 * crossing at a small angle), both see a bend of their common edges from its convex side
 * and may cut across it by the same segment, an edge of four triangles. Appends the ones
 * not listed yet to splits (pairs; *n pairs, *cap) and sets dirty[f] for the faces using
 * them. */
static cb_status shared_sides(int **splits, int *n, int *cap, unsigned char *dirty,
                              const cb_tess_face_mesh *fm, int nf, int n_points, cb_error *err)
{
    long count = 0;
    for (int f = 0; f < nf; f++)
        count += 3L * fm[f].n_tris;
    int *side = malloc(((size_t)count + 1) * 3 * sizeof(int)), m = 0;
    if (!side)
        return cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    for (int f = 0; f < nf; f++)
        for (int t = 0; t < fm[f].n_tris; t++)
            for (int k = 0; k < 3; k++) {
                int x = fm[f].tri[3 * t + k], y = fm[f].tri[3 * t + (k + 1) % 3];
                if (x >= n_points || y >= n_points)
                    continue;
                side[3 * m] = x < y ? x : y;
                side[3 * m + 1] = x < y ? y : x;
                side[3 * m + 2] = f;
                m++;
            }
    qsort(side, (size_t)m, 3 * sizeof(int), cb_tess_cmp_int3);
    cb_status st = CB_OK;
    for (int i = 0, j; i < m && !st; i = j) {
        for (j = i + 1; j < m && side[3 * j] == side[3 * i] && side[3 * j + 1] == side[3 * i + 1];
             j++)
            ;
        /* A segment of the body's edges has the triangles of its two faces beside it. */
        if (j - i <= 2)
            continue;
        int listed = 0;
        for (int k = 0; k < *n && !listed; k++)
            listed = (*splits)[2 * k] == side[3 * i] && (*splits)[2 * k + 1] == side[3 * i + 1];
        if (listed)
            continue;
        if (*n == *cap) {
            int nc = *cap ? 2 * *cap : 16;
            int *g = realloc(*splits, (size_t)nc * 2 * sizeof(int));
            if (!g) {
                st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
                break;
            }
            *splits = g;
            *cap = nc;
        }
        (*splits)[2 * *n] = side[3 * i];
        (*splits)[2 * *n + 1] = side[3 * i + 1];
        (*n)++;
        for (int k = i; k < j; k++)
            dirty[side[3 * k + 2]] = 1;
    }
    free(side);
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
    int nf = b->n_faces, n_zones = 0, cap_zones = 0;
    cb_tess_zone *zs = NULL;
    body_mesh m = {{0}, NULL};
    cb_tess_edges_init(&m.es);
    st = cb_tess_edges_sample(&m.es, b, &ro, ctx, err);
    if (!st) {
        m.fm = calloc((size_t)nf + 1, sizeof(cb_tess_face_mesh));
        if (!m.fm)
            st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    }
    /* A face whose boundary chords cross cannot be triangulated: its edges are sampled anew,
     * more finely round the crossing, and every face is meshed again. */
    for (int round = 0; !st; round++) {
        cb_tess_hints h = {zs, n_zones, NULL, 0};
        st = mesh_faces(m.fm, NULL, nf, b, &m.es, &ro, &h, ctx, err);
        if (st != CB_ERR_NUMERIC || round == CROSS_ROUNDS)
            break;
        int before = n_zones;
        double tol = fmax(ldexp(ro.chord_tol, -2 * (round + 1)), b->tol);
        cb_status s2 = CB_OK;
        for (int f = 0; f < nf && !s2; f++)
            if (m.fm[f].cross_r > 0)
                s2 = add_zone(&zs, &n_zones, &cap_zones, m.fm[f].cross_at, m.fm[f].cross_r, f,
                              tol, err);
        if (s2 || n_zones == before) {
            st = s2 ? s2 : st;
            break;
        }
        /* Sampling that the zones leave as it was would fail the same way. */
        cb_tess_edges es2;
        cb_tess_edges_init(&es2);
        s2 = cb_tess_edges_sample_zoned(&es2, b, &ro, zs, n_zones, ctx, err);
        int same = !s2 && es2.n_points == m.es.n_points &&
                   !memcmp(es2.t, m.es.t, (size_t)m.es.start[b->n_edges] * sizeof(double));
        cb_tess_edges_clear(&m.es);
        m.es = es2;
        if (s2 || same) {
            st = s2 ? s2 : st;
            break;
        }
        st = CB_OK;
    }
    /* Segments that triangles of two faces share are split in those faces. */
    int *splits = NULL, n_splits = 0, cap_splits = 0, *list = NULL;
    unsigned char *dirty = NULL;
    if (!st) {
        list = malloc(((size_t)nf + 1) * sizeof(int));
        dirty = malloc((size_t)nf + 1);
        if (!list || !dirty)
            st = cb_error_set(err, CB_ERR_NOMEM, "tessellation: out of memory");
    }
    for (int round = 0; round < SPLIT_ROUNDS && !st; round++) {
        int before = n_splits, n_list = 0;
        memset(dirty, 0, (size_t)nf);
        st = shared_sides(&splits, &n_splits, &cap_splits, dirty, m.fm, nf, m.es.n_points, err);
        if (st || n_splits == before)
            break;
        for (int f = 0; f < nf; f++)
            if (dirty[f])
                list[n_list++] = f;
        cb_tess_hints h = {zs, n_zones, splits, n_splits};
        st = mesh_faces(m.fm, list, n_list, b, &m.es, &ro, &h, ctx, err);
    }
    free(list);
    free(dirty);
    if (!st)
        st = assemble(out, &m.es, m.fm, nf, err);
    if (!st)
        st = settle_contacts(out, &m, b, &ro, zs, n_zones, cap_zones, splits, n_splits, ctx,
                             err);
    else
        free(zs);
    free(splits);
    body_mesh_clear(&m, nf);
    if (st)
        cb_mesh_clear(out);
    return st;
}
