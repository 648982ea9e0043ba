/* bench_ssi_pair.h — the input file of the Open CASCADE SSI comparator (occt_ssi.cpp, which
 * documents the format): a B-spline surface as "nurbs DEG_U DEG_V N_U N_V", its knots and its
 * control points "x y z w". Header-only: every bench_*.c is a program of its own. */
#ifndef CB_BENCH_SSI_PAIR_H
#define CB_BENCH_SSI_PAIR_H

#include <stdio.h>

#include "brep/nurbs.h"

static inline void bench_write_nurbs(FILE *f, const cb_nurbs_surface_struct *s)
{
    fprintf(f, "nurbs %d %d %d %d\n", s->deg_u, s->deg_v, s->n_u, s->n_v);
    for (int i = 0; i < s->n_u + s->deg_u + 1; i++)
        fprintf(f, "%.17g ", s->knots_u[i]);
    fputs("\n", f);
    for (int i = 0; i < s->n_v + s->deg_v + 1; i++)
        fprintf(f, "%.17g ", s->knots_v[i]);
    fputs("\n", f);
    for (long k = 0; k < (long)s->n_u * s->n_v; k++) {
        const double *h = s->cw + 4 * k;
        fprintf(f, "%.17g %.17g %.17g %.17g\n", h[0] / h[3], h[1] / h[3], h[2] / h[3], h[3]);
    }
}

#endif
