/* revolved.h — test helper: analytic faces rewritten as surfaces of revolution or linear
 * extrusion with the same parameterisation, so that edges and pcurves stay valid and every
 * result has the analytic body's closed form. */
#ifndef CB_TEST_REVOLVED_H
#define CB_TEST_REVOLVED_H

#include <math.h>

#include "brep/topo.h"

/* Each cylinder, cone, sphere and torus surface of b becomes a revolution about its axis of
 * the profile v -> S(0, v) (analytic.h: (rho(v), h(v)) in the frame's x'z' half-plane): a line
 * for the cylinder and cone, a circle for the sphere and torus. With extrude = 1 a cylinder
 * becomes instead the extrusion of its circle v = 0 along z' (S(u, v) = circle(u) + v z').
 * Both keep S(u, v) of the analytic surface, to rounding. Returns the number of surfaces
 * changed, -1 if a frame cannot be made. */
static inline int test_revolve_surfaces(cb_topo_body *b, int extrude)
{
    int changed = 0;
    for (int k = 0; k < b->n_surfaces; k++) {
        cb_topo_surface *s = b->surfaces + k;
        if (s->kind != CB_SURFACE_ANALYTIC)
            continue;
        const cb_analytic_surface a = s->analytic;
        const cb_frame *f = &a.frame;
        cb_topo_curve *c = &s->profile;
        cb_topo_curve_clear(c);
        cb_topo_curve_init(c);
        double o[3], d[3];
        switch (a.kind) {
        case CB_ANALYTIC_CYLINDER:
        case CB_ANALYTIC_CONE: {
            if (a.kind == CB_ANALYTIC_CYLINDER && extrude) {
                s->kind = CB_SURFACE_EXTRUSION;
                c->kind = CB_CURVE_CIRCLE;
                c->frame = *f;
                c->r1 = c->r2 = a.r1;
                for (int i = 0; i < 3; i++)
                    s->dir[i] = f->z[i];
                changed++;
                continue;
            }
            /* C(t) = o + r x' + t (tan a x' + z'): the line through S(0, 0) along S_v (a
             * cylinder is a cone of angle 0) */
            double ta = a.kind == CB_ANALYTIC_CONE ? tan(a.angle) : 0.0;
            for (int i = 0; i < 3; i++) {
                o[i] = f->o[i] + a.r1 * f->x[i];
                d[i] = ta * f->x[i] + f->z[i];
            }
            c->kind = CB_CURVE_LINE;
            c->r1 = cb_vec3_norm(d);
            if (cb_frame_make(&c->frame, o, d, f->y, NULL))
                return -1;
            break;
        }
        case CB_ANALYTIC_SPHERE:
        case CB_ANALYTIC_TORUS: {
            /* C(t) = o + R x' + r (cos t x' + sin t z') (R = 0 for the sphere) */
            double R = a.kind == CB_ANALYTIC_TORUS ? a.r1 : 0.0;
            double r = a.kind == CB_ANALYTIC_TORUS ? a.r2 : a.r1;
            for (int i = 0; i < 3; i++)
                o[i] = f->o[i] + R * f->x[i];
            c->kind = CB_CURVE_CIRCLE;
            c->r1 = c->r2 = r;
            double ny[3] = {-f->y[0], -f->y[1], -f->y[2]};
            if (cb_frame_make(&c->frame, o, ny, f->x, NULL))
                return -1;
            break;
        }
        default: continue;
        }
        s->kind = CB_SURFACE_REVOLUTION;
        s->frame = *f;
        changed++;
    }
    return changed;
}

#endif
