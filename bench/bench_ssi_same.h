/* bench_ssi_same.h — whether two SSI results are the same point for point (the runs on 1 and
 * N threads of one case must be: results are merged in pair order). */
#ifndef CB_BENCH_SSI_SAME_H
#define CB_BENCH_SSI_SAME_H

#include <string.h>

#include "ssi/ssi.h"

/* Same curves (counts, faces, every point bit for bit), isolated points and failure count. */
static inline int bench_ssi_same(const cb_ssi_result_t a, const cb_ssi_result_t b)
{
    if (a->n_curves != b->n_curves || a->n_points != b->n_points || a->n_failed != b->n_failed)
        return 0;
    for (slong c = 0; c < a->n_curves; c++) {
        if (a->curve[c].n != b->curve[c].n || a->curve[c].face_a != b->curve[c].face_a ||
            a->curve[c].face_b != b->curve[c].face_b)
            return 0;
        if (memcmp(a->curve[c].pt, b->curve[c].pt, (size_t)a->curve[c].n * sizeof(cb_ssi_point)))
            return 0;
    }
    for (slong p = 0; p < a->n_points; p++)
        if (memcmp(&a->point[p].p, &b->point[p].p, sizeof(cb_ssi_point)))
            return 0;
    return 1;
}

#endif
