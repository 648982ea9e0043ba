/* Edge tolerances from measured deviations (the method and the cap are described in step.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/step_internal.h"

/* Samples per edge: 64 intervals, so the 9, 17 and 33 uniform samples of validation are among
 * them (SAMPLES - 1 must be a multiple of 4: see surface_deviation). */
enum { SAMPLES = 65 };

static double edge_param(const cb_topo_edge *ed, int k)
{
    return ed->t0 + (ed->t1 - ed->t0) * k / (SAMPLES - 1);
}

/* Distance from sample k of coedge c's edge to the surface: the smaller of two distances to
 * surface points, the projector's and that of the pcurve image at the matching parameter
 * (range: the part of the pcurve the coedge uses). Both bound the true distance from above;
 * the second stands in where the projector's Newton search stalls (on the creases of a
 * degree-1 B-spline surface: trj5_k1-al-214.stp gives 0.167 for an edge lying on its face). */
static double sample_distance(const cb_topo_body *b, int c, const cb_topo_inverter *inv,
                              const double range[2], int k)
{
    const cb_topo_coedge *co = &b->coedges[c];
    const cb_topo_edge *ed = &b->edges[co->edge];
    double p[3];
    cb_topo_curve_eval(p, &b->curves[ed->curve], edge_param(ed, k));
    double d = cb_topo_projector_distance(&inv->pr, p);
    if (d > ed->tol && co->pcurve >= 0) {
        double x = (double)k / (SAMPLES - 1), w[3], q[3];
        if (co->sense != ed->same_sense)
            x = 1.0 - x;
        cb_topo_pcurve_eval(w, &b->pcurves[co->pcurve], range[0] + (range[1] - range[0]) * x);
        cb_topo_inverter_eval(q, inv, w[0], w[1]);
        d = fmin(d, cb_vec3_dist(p, q));
    }
    return d;
}

/* Edge samples against the surfaces of the faces using the edge. Every fourth sample first
 * (17 of them); the others only where those come within half of the edge's tolerance: an edge
 * that far inside is taken to stay inside between them (the maximum over 1025 samples exceeds
 * that over 33 by 5.4% at most on linkrods.step), and most edges of a good file are, so import
 * time grows less. */
static cb_status surface_deviation(double *dev, const cb_topo_body *b, cb_error *err)
{
    cb_status st = CB_OK;
    for (int f = 0; f < b->n_faces && !st; f++) {
        const cb_topo_face *fc = &b->faces[f];
        cb_topo_inverter inv;
        if ((st = cb_topo_inverter_init(&inv, &b->surfaces[fc->surface], b->tol, err)))
            break;
        for (int l = fc->first; l < fc->first + fc->count; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
                const cb_topo_coedge *co = &b->coedges[c];
                double range[2] = {0, 0}, worst = 0;
                if (co->pcurve >= 0)
                    cb_topo_coedge_pcurve_range(&range[0], &range[1], b, c, &inv,
                                                b->edges[co->edge].tol);
                for (int k = 0; k < SAMPLES; k += 4)
                    worst = fmax(worst, sample_distance(b, c, &inv, range, k));
                if (2 * worst > b->edges[co->edge].tol)
                    for (int k = 1; k < SAMPLES; k++)
                        if (k % 4)
                            worst = fmax(worst, sample_distance(b, c, &inv, range, k));
                dev[co->edge] = fmax(dev[co->edge], worst);
            }
        cb_topo_inverter_clear(&inv);
    }
    return st;
}

/* Distance from the curve end of edge e at its vertex v[j]. */
static double vertex_gap(const cb_topo_body *b, int e, int j)
{
    const cb_topo_edge *ed = &b->edges[e];
    double p[3];
    cb_topo_curve_eval(p, &b->curves[ed->curve], (j == 0) == (ed->same_sense != 0) ? ed->t0
                                                                                    : ed->t1);
    return cb_vec3_dist(p, b->vertices[ed->v[j]].p);
}

/* Pcurves mapped through their surfaces against their edges, each measured as validation
 * does at the edge's current tolerance (which decides how a pcurve's range is found); only
 * the pcurves of the edges marked in pending. */
static cb_status pcurve_deviation(double *dev, const cb_topo_body *b, const char *pending,
                                  cb_error *err)
{
    for (int f = 0; f < b->n_faces; f++) {
        const cb_topo_face *fc = &b->faces[f];
        int with = 0;
        for (int l = fc->first; l < fc->first + fc->count; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++)
                with += b->coedges[c].pcurve >= 0 && pending[b->coedges[c].edge];
        if (!with)
            continue;
        cb_topo_inverter inv;
        cb_status st = cb_topo_inverter_init(&inv, &b->surfaces[fc->surface], b->tol, err);
        if (st)
            return st;
        for (int l = fc->first; l < fc->first + fc->count; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
                if (b->coedges[c].pcurve < 0 || !pending[b->coedges[c].edge])
                    continue;
                double range[2];
                int e = b->coedges[c].edge;
                dev[e] = fmax(dev[e],
                              cb_topo_coedge_pcurve_error(range, b, c, &inv, b->tol, SAMPLES));
            }
        cb_topo_inverter_clear(&inv);
    }
    return CB_OK;
}

/* A gap at a loop joint is charged to the edge whose end lies farther from the shared vertex,
 * when neither edge's deviation covers it already. */
static void joint_gaps(double *dev, const cb_topo_body *b)
{
    for (int l = 0; l < b->n_loops; l++) {
        const cb_topo_loop *lp = &b->loops[l];
        for (int k = 0; k < lp->count; k++) {
            int c = lp->first + k, n = lp->first + (k + 1) % lp->count;
            int ec = b->coedges[c].edge, en = b->coedges[n].edge;
            double s0[3], e0[3], s1[3], e1[3];
            cb_topo_coedge_ends(s0, e0, b, c);
            cb_topo_coedge_ends(s1, e1, b, n);
            double gap = cb_vec3_dist(e0, s1);
            if (!(gap > fmax(dev[ec], dev[en])))
                continue;
            double gc = vertex_gap(b, ec, b->coedges[c].sense ? 1 : 0);
            double gn = vertex_gap(b, en, b->coedges[n].sense ? 0 : 1);
            dev[gc >= gn ? ec : en] = gap;
        }
    }
}

/* Sets the tolerance of each edge whose deviation with the margin exceeds its file tolerance
 * base[e] (the deviation itself within the cap) to that; the others get base[e] back. */
static void apply(cb_topo_body *b, const double *dev, const double *base, double cap)
{
    for (int e = 0; e < b->n_edges; e++) {
        double need = CB_STEP_EDGE_TOL_MARGIN * dev[e];
        b->edges[e].tol = need > base[e] && dev[e] <= cap ? fmin(need, cap) : base[e];
    }
}

/* Rounds of pcurve measurement: a raised tolerance can change how validation finds a pcurve's
 * range, so the pcurves are measured again at the new tolerances until nothing grows. */
enum { PCURVE_ROUNDS = 3 };

cb_status step_fit_edge_tols(cb_topo_body *b, double max_rel, cb_step_stats *stats,
                             cb_error *err)
{
    memset(stats, 0, sizeof *stats);
    for (int e = 0; e < b->n_edges; e++)
        stats->max_edge_tol = fmax(stats->max_edge_tol, b->edges[e].tol);
    if (!(max_rel > 0) || b->n_edges == 0)
        return CB_OK;
    cb_aabb box;
    cb_topo_body_edge_box(&box, b);
    double d[3] = {box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]};
    double cap = max_rel * cb_vec3_norm(d);
    if (!isfinite(cap))
        return CB_OK;
    stats->edge_tol_cap = cap;
    double *dev = calloc((size_t)b->n_edges, sizeof *dev);
    double *base = malloc((size_t)b->n_edges * sizeof *base);
    double *old = malloc((size_t)b->n_edges * sizeof *old);
    char *pending = malloc((size_t)b->n_edges);
    cb_status st = CB_OK;
    if (!dev || !base || !old || !pending)
        st = cb_error_set(err, CB_ERR_NOMEM, "edge tolerances: out of memory");
    for (int e = 0; e < b->n_edges && !st; e++)
        base[e] = b->edges[e].tol;
    if (!st)
        st = surface_deviation(dev, b, err);
    if (!st) {
        for (int e = 0; e < b->n_edges; e++)
            for (int j = 0; j < 2; j++)
                dev[e] = fmax(dev[e], vertex_gap(b, e, j));
        joint_gaps(dev, b);
        apply(b, dev, base, cap);
    }
    if (!st)
        memset(pending, 1, (size_t)b->n_edges);
    for (int round = 0; round < PCURVE_ROUNDS && !st; round++) {
        memcpy(old, dev, (size_t)b->n_edges * sizeof *old);
        if ((st = pcurve_deviation(dev, b, pending, err)))
            break;
        int grew = 0;
        for (int e = 0; e < b->n_edges; e++)
            grew |= (pending[e] = dev[e] > old[e]);
        if (!grew)
            break;
        apply(b, dev, base, cap);
    }
    for (int e = 0; e < b->n_edges && !st; e++) {
        cb_topo_edge *ed = &b->edges[e];
        /* Not covered after the last round: the file's tolerance, and validation says so. */
        if (dev[e] > ed->tol) {
            ed->tol = base[e];
            stats->edges_over_cap++;
        } else if (ed->tol > base[e]) {
            stats->edges_tol_raised++;
        }
        stats->max_edge_tol = fmax(stats->max_edge_tol, ed->tol);
    }
    if (st && base)
        for (int e = 0; e < b->n_edges; e++)
            b->edges[e].tol = base[e];
    free(dev);
    free(base);
    free(old);
    free(pending);
    /* A surface that cannot be prepared for inversion leaves the file's tolerances: the body
     * is still whole, and validation reports what does not meet them. */
    if (st && st != CB_ERR_NOMEM) {
        memset(stats, 0, sizeof *stats);
        for (int e = 0; e < b->n_edges; e++)
            stats->max_edge_tol = fmax(stats->max_edge_tol, b->edges[e].tol);
        return CB_OK;
    }
    return st;
}
