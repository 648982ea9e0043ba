/* Point classification against a closed B-rep: distance to the nearby faces for ON, ray
 * parity by votes for IN and OUT. */
#include <stdlib.h>
#include <string.h>

#include "boolean/bool.h"

enum { MAX_HITS = 64 };

struct cb_bool_solid {
    const cb_topo_body *b;
    cb_face *faces;
    int n_faces;
    cb_bool_bvh bvh;
    cb_aabb box;
    double tol;
};

void cb_bool_solid_free(cb_bool_solid *s)
{
    if (!s)
        return;
    for (int k = 0; k < s->n_faces; k++)
        cb_face_clear(&s->faces[k]);
    free(s->faces);
    cb_bool_bvh_clear(&s->bvh);
    free(s);
}

cb_status cb_bool_solid_new(cb_bool_solid **out, const cb_topo_body *b, double tol, cb_error *err)
{
    *out = NULL;
    if (!(tol > 0))
        return cb_error_set(err, CB_ERR_INVALID, "point in solid: tolerance %g is not > 0", tol);
    cb_bool_solid *s = calloc(1, sizeof *s);
    cb_aabb *boxes = malloc((size_t)(b->n_faces + 1) * sizeof *boxes);
    if (!s || !boxes) {
        free(s);
        free(boxes);
        return cb_error_set(err, CB_ERR_NOMEM, "point in solid: out of memory");
    }
    s->b = b;
    s->tol = tol;
    s->faces = calloc((size_t)(b->n_faces + 1), sizeof *s->faces);
    cb_status st = CB_OK;
    if (!s->faces)
        st = cb_error_set(err, CB_ERR_NOMEM, "point in solid: out of memory");
    double prep = b->tol > 0 ? b->tol : tol;
    for (int k = 0; k < b->n_faces && !st; k++) {
        st = cb_face_init(&s->faces[k], b, k, prep, err);
        if (!st) {
            s->n_faces++;
            cb_face_box(&boxes[k], &s->faces[k]);
        }
    }
    if (!st)
        st = cb_bool_bvh_init(&s->bvh, boxes, b->n_faces, err);
    free(boxes);
    if (st) {
        cb_bool_solid_free(s);
        return cb_error_prefix(err, "point in solid: ");
    }
    s->box = b->n_faces ? s->bvh.nodes[0].box : (cb_aabb){{0, 0, 0}, {0, 0, 0}};
    *out = s;
    return CB_OK;
}

const cb_face *cb_bool_solid_face(const cb_bool_solid *s, int k) { return &s->faces[k]; }

void cb_bool_solid_box(cb_aabb *box, const cb_bool_solid *s) { *box = s->box; }

/* Direction k of a fixed sequence: points spread on the sphere by a golden-angle spiral
 * through a shuffled order, turned by a fixed irrational rotation so that no direction lies
 * along a world axis or a coordinate plane (where modelled faces often are). */
static void direction(double d[3], int k)
{
    static const int shuffle[CB_BOOL_MAX_RAYS] = {0,  13, 7, 20, 3,  16, 10, 23, 1,  14, 8,  21,
                                                  4,  17, 11, 22, 2,  15, 9,  19, 5,  18, 12, 6};
    int j = shuffle[k % CB_BOOL_MAX_RAYS];
    double z = 1 - (2 * j + 1.0) / CB_BOOL_MAX_RAYS, r = sqrt(fmax(0, 1 - z * z));
    double phi = 2.39996322972865332 * j + 0.3183098861837907;
    double x = r * cos(phi), y = r * sin(phi);
    /* Rotation by 0.61 rad about (1, 2, 3) / |(1, 2, 3)|. */
    static const double ax[3] = {0.2672612419124244, 0.5345224838248488, 0.8017837257372732};
    double c = cos(0.61), s = sin(0.61), v[3] = {x, y, z}, kx[3];
    cb_vec3_cross(kx, ax, v);
    double kd = cb_vec3_dot(ax, v);
    for (int i = 0; i < 3; i++)
        d[i] = v[i] * c + kx[i] * s + ax[i] * kd * (1 - c);
}

/* Parity of the crossings of the ray from p along d: 0 or 1, or -1 when a hit grazes or lies
 * on an edge. */
static int ray_parity(const cb_bool_solid *s, const double p[3], const double d[3], double len,
                      int *cand, int lo, int hi)
{
    int n = cb_bool_bvh_query_ray(cand, s->n_faces, &s->bvh, p, d, 0, len, s->tol);
    int count = 0;
    cb_face_hit hits[MAX_HITS];
    for (int k = 0; k < n; k++) {
        if (cand[k] < lo || cand[k] >= hi)
            continue;
        int m = cb_face_ray(hits, MAX_HITS, &s->faces[cand[k]], p, d, 0, len, s->tol,
                            CB_BOOL_GRAZE_COS);
        if (m > MAX_HITS)
            return -1;
        for (int h = 0; h < m; h++)
            if (hits[h].kind != CB_FACE_HIT_CROSS)
                return -1;
        count += m;
    }
    return count % 2;
}

/* cb_bool_solid_classify counting only the faces lo <= k < hi. */
static cb_status classify_range(cb_bool_where *where, const cb_bool_solid *s, const double p[3],
                                int lo, int hi, cb_error *err);

cb_status cb_bool_solid_classify(cb_bool_where *where, const cb_bool_solid *s, const double p[3],
                                 cb_error *err)
{
    return classify_range(where, s, p, 0, s->n_faces, err);
}

cb_status cb_bool_solid_classify_faces(cb_bool_where *where, const cb_bool_solid *s,
                                       const double p[3], int first, int count, cb_error *err)
{
    return classify_range(where, s, p, first, first + count, err);
}

static cb_status classify_range(cb_bool_where *where, const cb_bool_solid *s, const double p[3],
                                int lo, int hi, cb_error *err)
{
    *where = CB_BOOL_OUT;
    if (!isfinite(p[0] + p[1] + p[2]))
        return cb_error_set(err, CB_ERR_INVALID, "point in solid: point not finite");
    cb_aabb pt = {{p[0], p[1], p[2]}, {p[0], p[1], p[2]}};
    if (!s->n_faces || !cb_aabb_overlap(&s->box, &pt, s->tol))
        return CB_OK;
    int *cand = malloc((size_t)s->n_faces * sizeof *cand);
    if (!cand)
        return cb_error_set(err, CB_ERR_NOMEM, "point in solid: out of memory");
    int n = cb_bool_bvh_query_box(cand, s->n_faces, &s->bvh, &pt, s->tol);
    for (int k = 0; k < n; k++)
        if (cand[k] >= lo && cand[k] < hi &&
            cb_face_distance(NULL, &s->faces[cand[k]], p) <= s->tol) {
            *where = CB_BOOL_ON;
            free(cand);
            return CB_OK;
        }
    /* Long enough to leave the body's box from any point inside it. */
    double len = 0;
    for (int i = 0; i < 3; i++) {
        double e = fmax(fabs(s->box.hi[i] - p[i]), fabs(p[i] - s->box.lo[i]));
        len += e * e;
    }
    len = 2 * sqrt(len) + s->tol;
    int votes[2] = {0, 0}, rejected = 0;
    for (int k = 0; k < CB_BOOL_MAX_RAYS; k++) {
        double d[3];
        direction(d, k);
        int r = ray_parity(s, p, d, len, cand, lo, hi);
        if (r < 0) {
            rejected++;
            continue;
        }
        votes[r]++;
        if (votes[r] >= CB_BOOL_AGREE + 2 * votes[!r]) {
            *where = r ? CB_BOOL_IN : CB_BOOL_OUT;
            free(cand);
            return CB_OK;
        }
    }
    free(cand);
    return cb_error_set(err, CB_ERR_NUMERIC,
                        "point in solid: (%.17g, %.17g, %.17g): rays do not agree (%d in, %d "
                        "out, %d rejected as grazing or through an edge)",
                        p[0], p[1], p[2], votes[1], votes[0], rejected);
}

int cb_bool_solid_normal_at(double n[3], const cb_bool_solid *s, const double p[3])
{
    cb_aabb pt = {{p[0], p[1], p[2]}, {p[0], p[1], p[2]}};
    if (!s->n_faces || !cb_aabb_overlap(&s->box, &pt, s->tol))
        return 0;
    int *cand = malloc((size_t)s->n_faces * sizeof *cand);
    if (!cand)
        return 0;
    int m = cb_bool_bvh_query_box(cand, s->n_faces, &s->bvh, &pt, s->tol), best = -1;
    double best_d = s->tol, best_uv[2] = {0, 0};
    for (int k = 0; k < m; k++) {
        double uv[2];
        double d = cb_face_distance(uv, &s->faces[cand[k]], p);
        if (d <= best_d) {
            best_d = d;
            best = cand[k];
            best_uv[0] = uv[0];
            best_uv[1] = uv[1];
        }
    }
    free(cand);
    return best >= 0 && cb_face_normal(n, &s->faces[best], best_uv[0], best_uv[1]) > 0;
}

cb_status cb_bool_point_in_solid(cb_bool_where *where, const cb_topo_body *b, const double p[3],
                                 double tol, cb_error *err)
{
    cb_bool_solid *s;
    *where = CB_BOOL_OUT;
    cb_status st = cb_bool_solid_new(&s, b, tol, err);
    if (st)
        return st;
    st = cb_bool_solid_classify(where, s, p, err);
    cb_bool_solid_free(s);
    return st;
}
