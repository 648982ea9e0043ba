/* The yoke (fork) of the Cardan joint: an extruded U, optionally filleted, with two bores and
 * a shaft (models.h). */
#include <math.h>

#include "brep/geom.h"
#include "models/cardan_internal.h"

enum { MAX_PROFILE = 10 };

/* The U in (x, z), clockwise seen from +y, so that the tangent of segment k crossed with +y is
 * the outward normal of side face k. Segment k runs from point k to point k + 1; a fillet
 * segment is the quarter circle about centre[k] whose angle starts (t = 0) at ref[k] in the
 * direction of the next point, so the segment runs against its circle. */
typedef struct {
    int n;
    double pt[MAX_PROFILE][2];
    int fillet[MAX_PROFILE];
    double centre[MAX_PROFILE][2], ref[MAX_PROFILE][3];
} profile;

static void add_point(profile *pr, double x, double z)
{
    pr->pt[pr->n][0] = x;
    pr->pt[pr->n][1] = z;
    pr->fillet[pr->n++] = 0;
}

static void make_profile(profile *pr, const cb_yoke_shape *y)
{
    const double B = y->half_span, g = y->gap, t = y->base_height, H = y->height;
    const double f = y->fillet_radius;
    pr->n = 0;
    add_point(pr, -B, 0);
    add_point(pr, -B, H);
    add_point(pr, -g, H);
    if (f > 0) {
        add_point(pr, -g, t + f);
        int k = pr->n - 1;
        pr->fillet[k] = 1;
        pr->centre[k][0] = -g + f;
        pr->centre[k][1] = t + f;
        pr->ref[k][0] = pr->ref[k][1] = 0;
        pr->ref[k][2] = -1;
        add_point(pr, -g + f, t);
        add_point(pr, g - f, t);
        k = pr->n - 1;
        pr->fillet[k] = 1;
        pr->centre[k][0] = g - f;
        pr->centre[k][1] = t + f;
        pr->ref[k][1] = pr->ref[k][2] = 0;
        pr->ref[k][0] = 1;
        add_point(pr, g, t + f);
    } else {
        add_point(pr, -g, t);
        add_point(pr, g, t);
    }
    add_point(pr, g, H);
    add_point(pr, B, H);
    add_point(pr, B, 0);
}

cb_status cb_cardan_build_yoke(cb_topo_body **out, const cb_cardan_params *p, cb_error *err)
{
    const cb_yoke_shape *y = &p->yoke;
    const double B = y->half_span, g = y->gap, hw = 0.5 * y->width, hb = y->bore_height;
    cb_build bd;
    cb_status st =
        cb_build_start(&bd, p, fmax(2 * B, fmax(y->height + y->shaft_length, y->width)), err);
    if (st)
        return st;
    profile pr;
    make_profile(&pr, y);
    const int n = pr.n;
    /* Vertices at y = -w/2 (front) and +w/2 (back); edges of segment k at the front, the
     * back, and the lateral line at point k. fwd[k]: the segment edges run from point k to
     * k + 1 (lines) or back (fillet arcs). */
    int vf[MAX_PROFILE], vk[MAX_PROFILE], ef[MAX_PROFILE], ek[MAX_PROFILE], el[MAX_PROFILE];
    int fwd[MAX_PROFILE];
    const double ydir[3] = {0, 1, 0};
    for (int k = 0; k < n; k++) {
        const double qf[3] = {pr.pt[k][0], -hw, pr.pt[k][1]};
        const double qk[3] = {pr.pt[k][0], hw, pr.pt[k][1]};
        vf[k] = cb_build_vertex(&bd, qf);
        vk[k] = cb_build_vertex(&bd, qk);
    }
    for (int k = 0; k < n && !bd.st; k++) {
        int k1 = (k + 1) % n;
        fwd[k] = !pr.fillet[k];
        if (pr.fillet[k]) {
            const double cf[3] = {pr.centre[k][0], -hw, pr.centre[k][1]};
            const double ck[3] = {pr.centre[k][0], hw, pr.centre[k][1]};
            ef[k] = cb_build_quarter_arc(&bd, cf, ydir, pr.ref[k], y->fillet_radius, vf[k1],
                                         vf[k]);
            ek[k] = cb_build_quarter_arc(&bd, ck, ydir, pr.ref[k], y->fillet_radius, vk[k1],
                                         vk[k]);
        } else {
            ef[k] = cb_build_line(&bd, vf[k], vf[k1]);
            ek[k] = cb_build_line(&bd, vk[k], vk[k1]);
        }
        el[k] = cb_build_line(&bd, vf[k], vk[k]);
    }
    if (bd.st)
        return cb_build_finish(out, &bd, "yoke");
    cb_build_tube bore[2], shaft;
    const double down[3] = {0, 0, -1}, xdir[3] = {1, 0, 0}, zero[3] = {0, 0, 0};
    const double bore_o[2][3] = {{-B, 0, hb}, {g, 0, hb}};
    for (int m = 0; m < 2; m++)
        cb_build_tube_edges(&bd, &bore[m], bore_o[m], xdir, down, y->bore_radius, B - g);
    cb_build_tube_edges(&bd, &shaft, zero, down, xdir, y->shaft_radius, y->shaft_length);
    for (int k = 0; k < n; k++) {
        int k1 = (k + 1) % n;
        const int es[4][2] = {{ef[k], fwd[k]}, {el[k1], 1}, {ek[k], !fwd[k]}, {el[k], 0}};
        if (pr.fillet[k]) {
            const double o[3] = {pr.centre[k][0], -hw, pr.centre[k][1]};
            cb_build_fillet_face(&bd, o, ydir, pr.ref[k], y->fillet_radius, y->width);
            cb_build_loop(&bd, 4, es);
            continue;
        }
        double pts[4][3] = {{pr.pt[k][0], -hw, pr.pt[k][1]},
                            {pr.pt[k1][0], -hw, pr.pt[k1][1]},
                            {pr.pt[k1][0], hw, pr.pt[k1][1]},
                            {pr.pt[k][0], hw, pr.pt[k][1]}};
        double d[3] = {pr.pt[k1][0] - pr.pt[k][0], 0, pr.pt[k1][1] - pr.pt[k][1]}, nrm[3];
        cb_vec3_normalize(d);
        cb_vec3_cross(nrm, d, ydir);
        cb_build_polygon_face(&bd, pts[0], nrm, d, 4, (const double(*)[3])pts);
        cb_build_loop(&bd, 4, es);
        /* Holes, clockwise about the face normal (a circle runs counter-clockwise about its
         * tube's direction +x or -z): the arms' outer and inner faces, and the bottom. */
        double x = pr.pt[k][0];
        if (d[0] == 0 && (x == -B || x == g)) {
            const int hole[1][2] = {{bore[x == g].c0, 1}};
            cb_build_loop(&bd, 1, hole);
        } else if (d[0] == 0 && (x == -g || x == B)) {
            const int hole[1][2] = {{bore[x == B].c1, 0}};
            cb_build_loop(&bd, 1, hole);
        } else if (k == n - 1) {
            const int hole[1][2] = {{shaft.c0, 0}};
            cb_build_loop(&bd, 1, hole);
        }
    }
    cb_build_profile_ends(&bd, n, (const double(*)[2])pr.pt, hw, ef, ek, fwd);
    for (int m = 0; m < 2; m++)
        cb_build_tube_face(&bd, &bore[m], 0);
    cb_build_tube_face(&bd, &shaft, 1);
    cb_build_cap_face(&bd, &shaft);
    return cb_build_finish(out, &bd, "yoke");
}
