/* bracket.c — an L-shaped bracket with a tangent blend in its inner corner and a hole through
 * each leg (models.h: cb_model_bracket). */
#include <math.h>
#include <string.h>

#include "brep/geom.h"
#include "models/cardan_internal.h"

#define PI 3.14159265358979323846

enum { N_PROFILE = 7 };

void cb_bracket_params_default(cb_bracket_params *p)
{
    memset(p, 0, sizeof *p);
    p->shape.length = 4;
    p->shape.height = 3;
    p->shape.thickness = 0.5;
    p->shape.width = 2;
    p->shape.fillet = 0.5;
    p->shape.hole_radius = 0.3;
    p->shape.hole_x = 2.5;
    p->shape.hole_z = 2;
    p->pose.axis[2] = 1;
}

double cb_bracket_volume(const cb_bracket_shape *s)
{
    double t = s->thickness, f = s->fillet, r = s->hole_radius;
    return s->width * (s->length * t + (s->height - t) * t + (1 - PI / 4) * f * f) -
           2 * PI * r * r * t;
}

static cb_status check(const cb_bracket_shape *s, cb_error *err)
{
    const double L = s->length, H = s->height, t = s->thickness, f = s->fillet;
    const double r = s->hole_radius, w = s->width;
    int ok = isfinite(L + H + t + f + r + w + s->hole_x + s->hole_z) && t > 0 && t < L &&
             t < H && w > 0 && f > 0 && t + f < H && t + f < L && r > 0 && r < 0.5 * w &&
             s->hole_x - r > t + f && s->hole_x + r < L && s->hole_z - r > t + f &&
             s->hole_z + r < H;
    if (!ok)
        return cb_error_set(err, CB_ERR_INVALID,
                            "bracket: needs 0 < t < length, height; width > 0; fillet > 0 with "
                            "t + fillet below both legs; 0 < hole radius < width / 2; each hole "
                            "clear of the fillet and of the leg's end");
    return CB_OK;
}

cb_status cb_model_bracket(cb_topo_body **out, const cb_bracket_params *p, cb_error *err)
{
    *out = NULL;
    const cb_bracket_shape *s = &p->shape;
    cb_status st = check(s, err);
    if (st)
        return st;
    const double L = s->length, H = s->height, t = s->thickness, f = s->fillet;
    const double hw = 0.5 * s->width;
    cb_cardan_params cp;
    memset(&cp, 0, sizeof cp);
    cp.pose = p->pose;
    cp.as_nurbs = p->as_nurbs;
    cp.tol = p->tol;
    cb_build bd;
    st = cb_build_start(&bd, &cp, fmax(fmax(L, H), s->width), err);
    if (st)
        return st;
    /* The L in (x, z), clockwise seen from +y (segment k from point k to k + 1; tangent x +y
     * is the outward normal of side face k); segment 3 is the fillet, a quarter circle about
     * (t + f, t + f) starting (t = 0) towards the next point, so its edges run against it. */
    const double pt[N_PROFILE][2] = {{0, 0}, {0, H}, {t, H}, {t, t + f},
                                     {t + f, t}, {L, t}, {L, 0}};
    const int fillet = 3;
    const double centre[2] = {t + f, t + f}, ref[3] = {0, 0, -1}, ydir[3] = {0, 1, 0};
    int vf[N_PROFILE], vk[N_PROFILE], ef[N_PROFILE], ek[N_PROFILE], el[N_PROFILE];
    int fwd[N_PROFILE];
    int n = N_PROFILE;
    for (int k = 0; k < n; k++) {
        const double qf[3] = {pt[k][0], -hw, pt[k][1]}, qk[3] = {pt[k][0], hw, pt[k][1]};
        vf[k] = cb_build_vertex(&bd, qf);
        vk[k] = cb_build_vertex(&bd, qk);
    }
    for (int k = 0; k < n && !bd.st; k++) {
        int k1 = (k + 1) % n;
        fwd[k] = k != fillet;
        if (k == fillet) {
            const double cf[3] = {centre[0], -hw, centre[1]}, ck[3] = {centre[0], hw, centre[1]};
            ef[k] = cb_build_quarter_arc(&bd, cf, ydir, ref, f, vf[k1], vf[k]);
            ek[k] = cb_build_quarter_arc(&bd, ck, ydir, ref, f, vk[k1], vk[k]);
        } else {
            ef[k] = cb_build_line(&bd, vf[k], vf[k1]);
            ek[k] = cb_build_line(&bd, vk[k], vk[k1]);
        }
        el[k] = cb_build_line(&bd, vf[k], vk[k]);
    }
    if (bd.st)
        return cb_build_finish(out, &bd, "bracket");
    /* The holes: through the vertical leg along +x, through the horizontal one along +z. */
    cb_build_tube hole[2];
    const double xdir[3] = {1, 0, 0}, zdir[3] = {0, 0, 1}, down[3] = {0, 0, -1};
    const double ov[3] = {0, 0, s->hole_z}, oh[3] = {s->hole_x, 0, 0};
    cb_build_tube_edges(&bd, &hole[0], ov, xdir, down, s->hole_radius, t);
    cb_build_tube_edges(&bd, &hole[1], oh, zdir, xdir, s->hole_radius, t);
    for (int k = 0; k < n; k++) {
        int k1 = (k + 1) % n;
        const int es[4][2] = {{ef[k], fwd[k]}, {el[k1], 1}, {ek[k], !fwd[k]}, {el[k], 0}};
        if (k == fillet) {
            const double o[3] = {centre[0], -hw, centre[1]};
            cb_build_fillet_face(&bd, o, ydir, ref, f, s->width);
            cb_build_loop(&bd, 4, es);
            continue;
        }
        double pts[4][3] = {{pt[k][0], -hw, pt[k][1]},
                            {pt[k1][0], -hw, pt[k1][1]},
                            {pt[k1][0], hw, pt[k1][1]},
                            {pt[k][0], hw, pt[k][1]}};
        double d[3] = {pt[k1][0] - pt[k][0], 0, pt[k1][1] - pt[k][1]}, nrm[3];
        cb_vec3_normalize(d);
        cb_vec3_cross(nrm, d, ydir);
        cb_build_polygon_face(&bd, pts[0], nrm, d, 4, (const double(*)[3])pts);
        cb_build_loop(&bd, 4, es);
        /* Holes, clockwise about the face normal (a hole's circle runs counter-clockwise
         * about its direction): start circles on the outer faces, end circles on the inner. */
        if (k == 0) {
            const int h[1][2] = {{hole[0].c0, 1}};
            cb_build_loop(&bd, 1, h);
        } else if (k == 2) {
            const int h[1][2] = {{hole[0].c1, 0}};
            cb_build_loop(&bd, 1, h);
        } else if (k == 6) {
            const int h[1][2] = {{hole[1].c0, 1}};
            cb_build_loop(&bd, 1, h);
        } else if (k == 4) {
            const int h[1][2] = {{hole[1].c1, 0}};
            cb_build_loop(&bd, 1, h);
        }
    }
    cb_build_profile_ends(&bd, n, pt, hw, ef, ek, fwd);
    for (int m = 0; m < 2; m++)
        cb_build_tube_face(&bd, &hole[m], 0);
    return cb_build_finish(out, &bd, "bracket");
}
