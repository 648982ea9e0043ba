/* Orientation of closed shells: the signed enclosed volume by the divergence theorem,
 * integrated over each face's trimmed parameter domain. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/topo.h"

enum { N_PER_CURVE = 24 /* polygon points per curved pcurve */ };

/* The polygons of one face's loops in (u, v): pts[2 k], pts[2 k + 1]; loop l covers
 * [start[l], start[l + 1]) and is closed by the segment from its last point to its first point
 * moved by wrap[l] periods. */
typedef struct {
    double *pts;
    int n, cap;
    int *start, (*wrap)[2];
    int n_loops;
} polygons;

static void polygons_clear(polygons *pg)
{
    free(pg->pts);
    free(pg->start);
    free(pg->wrap);
    memset(pg, 0, sizeof *pg);
}

static cb_status push_point(polygons *pg, const double uv[2], cb_error *err)
{
    if (pg->n == pg->cap) {
        int c = pg->cap ? 2 * pg->cap : 256;
        double *p = realloc(pg->pts, (size_t)c * 2 * sizeof *p);
        if (!p)
            return cb_error_set(err, CB_ERR_NOMEM, "shell volume: out of memory");
        pg->pts = p;
        pg->cap = c;
    }
    pg->pts[2 * pg->n] = uv[0];
    pg->pts[2 * pg->n + 1] = uv[1];
    pg->n++;
    return CB_OK;
}

/* Whole periods k[i] that move b nearest a; zero when the segment a -> b already closes on the
 * surface (equal points, a pole line). */
static void periods_between(int k[2], const cb_topo_inverter *inv, const double a[2],
                            const double b[2], double tol)
{
    k[0] = k[1] = 0;
    if (cb_topo_inverter_spread(inv, a, b) <= tol)
        return;
    for (int i = 0; i < 2; i++)
        if (inv->lift[i] > 0)
            k[i] = (int)round((a[i] - b[i]) / inv->lift[i]);
}

/* Samples the pcurves of face f's loops into polygons, each pcurve lifted to continue from
 * the previous one. */
static cb_status face_polygons(polygons *pg, const cb_topo_body *b, int f,
                               const cb_topo_inverter *inv, double tol, cb_error *err)
{
    const cb_topo_face *fc = &b->faces[f];
    pg->start = malloc(((size_t)fc->count + 1) * sizeof *pg->start);
    pg->wrap = malloc(((size_t)fc->count + 1) * sizeof *pg->wrap);
    if (!pg->start || !pg->wrap)
        return cb_error_set(err, CB_ERR_NOMEM, "shell volume: out of memory");
    cb_status st = CB_OK;
    for (int l = fc->first; l < fc->first + fc->count && !st; l++) {
        const cb_topo_loop *lp = &b->loops[l];
        int first = pg->n;
        double prev_end[2];
        pg->start[pg->n_loops] = first;
        for (int c = lp->first; c < lp->first + lp->count && !st; c++) {
            const cb_topo_coedge *co = &b->coedges[c];
            if (co->pcurve < 0)
                return cb_error_set(err, CB_ERR_INVALID, "shell volume: coedge %d has no pcurve",
                                    c);
            const cb_topo_curve *pc = &b->pcurves[co->pcurve];
            double s0, s1, e_tol = fmax(tol, b->edges[co->edge].tol);
            cb_topo_coedge_pcurve_range(&s0, &s1, b, c, inv, e_tol);
            int m = pc->kind == CB_CURVE_LINE ? 1 : N_PER_CURVE, k[2] = {0, 0};
            double w[3];
            cb_topo_pcurve_eval(w, pc, s0);
            if (c > lp->first)
                periods_between(k, inv, prev_end, w, tol);
            for (int j = 0; j < m && !st; j++) {
                double uv[2];
                cb_topo_pcurve_eval(w, pc, s0 + (s1 - s0) * j / m);
                uv[0] = w[0] + k[0] * inv->lift[0];
                uv[1] = w[1] + k[1] * inv->lift[1];
                st = push_point(pg, uv, err);
            }
            /* The end too: the next pcurve may start elsewhere on a collapsed line (a pole). */
            cb_topo_pcurve_eval(w, pc, s1);
            prev_end[0] = w[0] + k[0] * inv->lift[0];
            prev_end[1] = w[1] + k[1] * inv->lift[1];
            if (!st)
                st = push_point(pg, prev_end, err);
        }
        if (st)
            break;
        int k[2];
        periods_between(k, inv, pg->pts + 2 * (pg->n - 1), pg->pts + 2 * first, tol);
        pg->wrap[pg->n_loops][0] = k[0];
        pg->wrap[pg->n_loops][1] = k[1];
        pg->n_loops++;
    }
    pg->start[pg->n_loops] = pg->n;
    return st;
}

/* Point k of the polygons and the closing point of loop l after the last one. */
static void point_of(double p[2], const polygons *pg, const cb_topo_inverter *inv, int l, int k)
{
    if (k < pg->start[l + 1]) {
        p[0] = pg->pts[2 * k];
        p[1] = pg->pts[2 * k + 1];
        return;
    }
    int f = pg->start[l];
    p[0] = pg->pts[2 * f] + pg->wrap[l][0] * inv->lift[0];
    p[1] = pg->pts[2 * f + 1] + pg->wrap[l][1] * inv->lift[1];
}

static int dbl_cmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* (1/3) (S - c) . (S_u x S_v) at (u, v). */
static double integrand(const cb_topo_inverter *inv, const double c[3], double u, double v)
{
    double d[6][3], n[3], x[3];
    cb_topo_inverter_eval_derivs(d, inv, u, v);
    cb_vec3_cross(n, d[1], d[2]);
    for (int i = 0; i < 3; i++)
        x[i] = d[0][i] - c[i];
    return cb_vec3_dot(x, n) / 3.0;
}

static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834},
                    gw[3] = {0.5555555555555556, 0.8888888888888888, 0.5555555555555556};

/* 1 when the line b = y of the surface collapses to a point (a pole). */
static int pole_at(const cb_topo_inverter *inv, int a, double y, double tol)
{
    if (!isfinite(y) || !(inv->period[a] > 0))
        return 0;
    double p[2], q[2];
    p[1 - a] = q[1 - a] = y;
    p[a] = 0;
    q[a] = 0.5 * inv->period[a];
    return cb_topo_inverter_spread(inv, p, q) <= tol;
}

/* The flux over the whole band [a0, a0 + period] x [b0, b1] (between two poles), by columns
 * as face_flux integrates. */
static double band_flux(const cb_topo_inverter *inv, const double centre[3], int a, double a0,
                        double b0, double b1, int n_columns)
{
    double width = inv->period[a] / n_columns, piece = (b1 - b0) / 8, sum = 0;
    for (int col = 0; col < n_columns; col++)
        for (int i = 0; i < 8; i++)
            for (int g = 0; g < 3; g++) {
                double uv[2];
                uv[a] = a0 + (col + 0.5) * width;
                uv[1 - a] = b0 + piece * (i + 0.5 + 0.5 * gx[g]);
                sum += width * 0.5 * piece * gw[g] * integrand(inv, centre, uv[0], uv[1]);
            }
    return sum;
}

/* The flux integral over face f's domain (without its sense). Columns run across coordinate
 * a, rays and quadrature along b = 1 - a. */
static cb_status face_flux(double *flux, const cb_topo_body *b, int f, const cb_topo_inverter *inv,
                           const double centre[3], int n_columns, double tol, cb_error *err)
{
    polygons pg;
    memset(&pg, 0, sizeof pg);
    cb_status st = face_polygons(&pg, b, f, inv, tol, err);
    double *cut = NULL;
    *flux = 0;
    if (st || pg.n < 2)
        goto done;
    int wraps[2] = {0, 0};
    for (int l = 0; l < pg.n_loops; l++)
        for (int i = 0; i < 2; i++)
            wraps[i] += pg.wrap[l][i];
    int any[2] = {0, 0};
    for (int l = 0; l < pg.n_loops; l++)
        for (int i = 0; i < 2; i++)
            any[i] |= pg.wrap[l][i] != 0;
    if (any[0] && any[1]) {
        st = cb_error_set(err, CB_ERR_UNSUPPORTED,
                          "shell volume: face %d has loops around both periods of its surface", f);
        goto done;
    }
    int a = any[1] ? 1 : 0, bb = 1 - a;
    double Pa = inv->period[a], Pb = inv->period[bb];
    /* Loops not around the b period: lift each next to the first so they share a b range. */
    if (Pb > 0)
        for (int l = 1; l < pg.n_loops; l++) {
            double d = pg.pts[2 * pg.start[0] + bb] - pg.pts[2 * pg.start[l] + bb];
            double sh = Pb * round(d / Pb);
            for (int k = pg.start[l]; k < pg.start[l + 1]; k++)
                pg.pts[2 * k + bb] += sh;
        }
    double lo_a = HUGE_VAL, hi_a = -HUGE_VAL, lo_b = HUGE_VAL, hi_b = -HUGE_VAL;
    for (int k = 0; k < pg.n; k++) {
        lo_a = fmin(lo_a, pg.pts[2 * k + a]);
        hi_a = fmax(hi_a, pg.pts[2 * k + a]);
        lo_b = fmin(lo_b, pg.pts[2 * k + bb]);
        hi_b = fmax(hi_b, pg.pts[2 * k + bb]);
    }
    if (Pa > 0)
        hi_a = fmin(hi_a, lo_a + Pa);
    /* Odd crossings: the column is closed at the pole the wrapping loops keep to their left,
     * left of +a being +b for a = u and -b for a = v. */
    int up = (wraps[a] > 0) == (b->faces[f].same_sense != 0);
    if (a == 1)
        up = !up;
    double edge_b = up ? inv->box[2 * bb + 1] : inv->box[2 * bb];
    int cap = 16;
    cut = malloc((size_t)cap * sizeof *cut);
    if (!cut) {
        st = cb_error_set(err, CB_ERR_NOMEM, "shell volume: out of memory");
        goto done;
    }
    double width = (hi_a - lo_a) / n_columns, piece = (hi_b - lo_b) / 8;
    for (int col = 0; col < n_columns && !st && width > 0; col++) {
        double x = lo_a + (col + 0.5) * width;
        int m = 0;
        for (int l = 0; l < pg.n_loops && !st; l++)
            for (int k = pg.start[l]; k < pg.start[l + 1] && !st; k++) {
                double p[2], q[2];
                point_of(p, &pg, inv, l, k);
                point_of(q, &pg, inv, l, k + 1);
                double mn = fmin(p[a], q[a]), mx = fmax(p[a], q[a]);
                int k0 = 0, k1 = 0;
                if (Pa > 0) {
                    k0 = (int)floor((mn - x) / Pa);
                    k1 = (int)ceil((mx - x) / Pa);
                }
                for (int j = k0; j <= k1; j++) {
                    double X = x + j * Pa;
                    if ((p[a] <= X) == (q[a] <= X))
                        continue;
                    if (m + 1 >= cap) { /* room for a pole bound too */
                        double *nc = realloc(cut, (size_t)(2 * cap) * sizeof *nc);
                        if (!nc) {
                            st = cb_error_set(err, CB_ERR_NOMEM, "shell volume: out of memory");
                            break;
                        }
                        cut = nc;
                        cap *= 2;
                    }
                    cut[m++] = p[bb] + (X - p[a]) / (q[a] - p[a]) * (q[bb] - p[bb]);
                }
            }
        if (st || m == 0)
            continue;
        qsort(cut, (size_t)m, sizeof *cut, dbl_cmp);
        int k = 0;
        double from = 0;
        if (m % 2) {
            if (!isfinite(edge_b))
                continue; /* no pole to close at: the loops do not bound this column */
            if (up) {
                cut[m++] = edge_b;
            } else {
                from = edge_b;
                k = -1;
            }
        }
        for (; k + 1 < m || k == -1; k += 2) {
            double lo = k < 0 ? from : cut[k], hi = cut[k + 1];
            int np = piece > 0 ? (int)ceil((hi - lo) / piece) : 1;
            if (np < 1)
                np = 1;
            double h = (hi - lo) / np;
            for (int i = 0; i < np; i++)
                for (int g = 0; g < 3; g++) {
                    double y = lo + h * (i + 0.5 + 0.5 * gx[g]), uv[2];
                    uv[a] = x;
                    uv[bb] = y;
                    *flux += width * 0.5 * h * gw[g] * integrand(inv, centre, uv[0], uv[1]);
                }
        }
    }
    /* The columns take the region inside the loops by crossing parity, which ignores which
     * way the loops run. On a surface closed in a with a pole at both ends in b (a sphere) a
     * loop that does not wind bounds two regions, and the face is the one its loops run
     * round counter-clockwise (clockwise where same_sense is 0): where their signed area in
     * (u, v) says the other, the face is the complement of the parity region. */
    if (!st && !any[0] && !any[1] && Pa > 0 && pole_at(inv, a, inv->box[2 * bb], tol) &&
        pole_at(inv, a, inv->box[2 * bb + 1], tol)) {
        double area = 0;
        for (int l = 0; l < pg.n_loops; l++)
            for (int k = pg.start[l]; k < pg.start[l + 1]; k++) {
                double p[2], q[2];
                point_of(p, &pg, inv, l, k);
                point_of(q, &pg, inv, l, k + 1);
                area += p[0] * q[1] - q[0] * p[1];
            }
        if (a == 1)
            area = -area; /* columns across v: the roles of u and v swap */
        if ((area < 0) == (b->faces[f].same_sense != 0))
            *flux = band_flux(inv, centre, a, lo_a, inv->box[2 * bb], inv->box[2 * bb + 1],
                              n_columns) -
                    *flux;
    }
done:
    free(cut);
    polygons_clear(&pg);
    return st;
}

cb_status cb_topo_shell_volume(double *volume, const cb_topo_body *b, int shell, int n_columns,
                               double tol, cb_error *err)
{
    cb_aabb box;
    cb_topo_body_edge_box(&box, b);
    double centre[3];
    for (int i = 0; i < 3; i++)
        centre[i] = 0.5 * (box.lo[i] + box.hi[i]);
    if (n_columns < 1)
        n_columns = 1;
    const cb_topo_shell *sh = &b->shells[shell];
    cb_status st = CB_OK;
    *volume = 0;
    for (int f = sh->first; f < sh->first + sh->count && !st; f++) {
        cb_topo_inverter inv;
        if ((st = cb_topo_inverter_init(&inv, &b->surfaces[b->faces[f].surface], tol, err)))
            break;
        double flux;
        st = face_flux(&flux, b, f, &inv, centre, n_columns, tol, err);
        cb_topo_inverter_clear(&inv);
        *volume += b->faces[f].same_sense ? flux : -flux;
    }
    return st;
}

void cb_topo_shell_reverse(cb_topo_body *b, int k)
{
    const cb_topo_shell *sh = &b->shells[k];
    for (int f = sh->first; f < sh->first + sh->count; f++) {
        cb_topo_face *fc = &b->faces[f];
        fc->same_sense ^= 1;
        for (int l = fc->first; l < fc->first + fc->count; l++) {
            cb_topo_coedge *c = b->coedges + b->loops[l].first;
            for (int i = 0, j = b->loops[l].count - 1; i < j; i++, j--) {
                cb_topo_coedge t = c[i];
                c[i] = c[j];
                c[j] = t;
            }
            for (int i = 0; i < b->loops[l].count; i++)
                c[i].sense ^= 1;
        }
    }
}
