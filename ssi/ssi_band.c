/* ssi_band.c — the curves of a contact band: a region where the subdivision route proved two
 * B-spline surfaces within tol of each other (slab and graph, tolerance-certificates.md
 * section 2) over more than WT_MAX_TOL tol. The curve reported there is the valley of the
 * distance between the surfaces (section 2's "minimum of the distance"), traced on the whole
 * surfaces; see _cb_ssi_band_trace in ssi/spline.h for the rule and what is checked. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "ssi/spline.h"

/* Newton iterations of the valley corrector. */
#define VALLEY_ITERS 40
/* Largest number of points of one traced curve, and of curves in one band. */
#define MAX_POINTS 100000
#define MAX_CURVES 16

/* A side of P lying on a side of Q (_cb_ssi_coside), as one of its pieces gives it: P's
 * parameter k held at c, the other over [lo, hi] (P's domain). */
typedef struct {
    int k;
    double c, lo, hi;
} sline;

typedef struct {
    const cb_nurbs_surface_struct *P, *Q;
    double dp[4], dq[4]; /* parameter domains */
    double tol, chord, max_seg;
    sline *sl; /* the sides lying on Q, from the pieces */
    slong nsl;
    double lo[3], hi[3]; /* the box of the members (_cb_ssi_band_node) */
} band;

/* A point of P, its foot on Q and the distance's derivatives there. */
typedef struct {
    double uv[2], st[2];
    double X[3], Y[3]; /* P(uv), Q(st) */
    double D;          /* signed distance (X - Y) . N, N Q's unit normal at st */
    double g[2];       /* dD/du, dD/dv */
    double H[2][2];    /* its Hessian */
    unsigned fixed;    /* bit 0: u held on P's domain side, bit 1: v */
} vpt;

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* The foot of p->X on Q from p->st (_cb_ssi_nurbs_project, warm). 1 when it lies inside Q's
 * domain or on a side with X not beyond it, -1 when it lies on a side with X beyond it (P goes
 * on past Q's end there), 0 when no distance was found. d receives Q's derivatives there. */
static int foot(const band *b, vpt *p, double d[6][3])
{
    if (!isfinite(_cb_ssi_nurbs_project(p->st, b->Q, p->X, 1)))
        return 0;
    cb_nurbs_surface_eval_derivs(d, b->Q, p->st[0], p->st[1]);
    double r[3] = {p->X[0] - d[0][0], p->X[1] - d[0][1], p->X[2] - d[0][2]};
    for (int k = 0; k < 2; k++) {
        double g = cb_vec3_dot(d[1 + k], r);
        if ((p->st[k] <= b->dq[2 * k] && g < 0) || (p->st[k] >= b->dq[2 * k + 1] && g > 0))
            return -1;
    }
    return 1;
}

/* p at p->uv (st: the foot's start): X, foot, D, g and H. 1 on success, -1 when the foot lies
 * on a side of Q's domain, 0 otherwise. */
static int vpt_eval(const band *b, vpt *p)
{
    double dp[6][3], dq[6][3];
    cb_nurbs_surface_eval_derivs(dp, b->P, p->uv[0], p->uv[1]);
    memcpy(p->X, dp[0], sizeof p->X);
    int f = foot(b, p, dq);
    if (f != 1)
        return f;
    memcpy(p->Y, dq[0], sizeof p->Y);
    double n[3];
    cb_vec3_cross(n, dq[1], dq[2]);
    double ln = cb_vec3_norm(n);
    if (!(ln > 0))
        return 0;
    double N[3] = {n[0] / ln, n[1] / ln, n[2] / ln};
    double r[3] = {p->X[0] - p->Y[0], p->X[1] - p->Y[1], p->X[2] - p->Y[2]};
    p->D = cb_vec3_dot(r, N);
    /* dD/du_i = N . X_i: the foot's motion is tangent to Q and N's is normal to X - Y. */
    p->g[0] = cb_vec3_dot(N, dp[1]);
    p->g[1] = cb_vec3_dot(N, dp[2]);
    /* N's derivatives in s, t (the unit normal's, from n's), and the foot's in u, v (the foot
     * condition Q_s . r = Q_t . r = 0 differentiated). */
    double Nst[2][3];
    for (int k = 0; k < 2; k++) {
        double a[3], c[3], ns[3];
        cb_vec3_cross(a, dq[3 + k], dq[2]);
        cb_vec3_cross(c, dq[1], dq[4 + k]);
        for (int q = 0; q < 3; q++)
            ns[q] = a[q] + c[q];
        double along = cb_vec3_dot(N, ns);
        for (int q = 0; q < 3; q++)
            Nst[k][q] = (ns[q] - along * N[q]) / ln;
    }
    double a11 = cb_vec3_dot(dq[1], dq[1]) - cb_vec3_dot(r, dq[3]);
    double a12 = cb_vec3_dot(dq[1], dq[2]) - cb_vec3_dot(r, dq[4]);
    double a22 = cb_vec3_dot(dq[2], dq[2]) - cb_vec3_dot(r, dq[5]);
    double det = a11 * a22 - a12 * a12;
    if (!(det > 0))
        return 0;
    double Ni[2][3];
    for (int i = 0; i < 2; i++) {
        double f1 = cb_vec3_dot(dq[1], dp[1 + i]), f2 = cb_vec3_dot(dq[2], dp[1 + i]);
        double ds = (a22 * f1 - a12 * f2) / det, dt = (a11 * f2 - a12 * f1) / det;
        for (int q = 0; q < 3; q++)
            Ni[i][q] = Nst[0][q] * ds + Nst[1][q] * dt;
    }
    /* X_uu, X_uv, X_vv are dp[3], dp[4], dp[5]. */
    p->H[0][0] = cb_vec3_dot(N, dp[3]) + cb_vec3_dot(dp[1], Ni[0]);
    p->H[1][1] = cb_vec3_dot(N, dp[5]) + cb_vec3_dot(dp[2], Ni[1]);
    p->H[0][1] = p->H[1][0] =
        cb_vec3_dot(N, dp[4]) + 0.5 * (cb_vec3_dot(dp[1], Ni[1]) + cb_vec3_dot(dp[2], Ni[0]));
    return isfinite(p->D) && isfinite(p->H[0][0] + p->H[0][1] + p->H[1][1]);
}

/* The unit eigenvector e of the symmetric H for its eigenvalue of largest modulus lam. */
static void across(double e[2], double *lam, const double H[2][2])
{
    double a = H[0][0], c = H[1][1], bb = H[0][1];
    double m = 0.5 * (a + c), dd = sqrt(0.25 * (a - c) * (a - c) + bb * bb);
    double l1 = m + dd, l2 = m - dd;
    double l = fabs(l1) >= fabs(l2) ? l1 : l2;
    /* (H - l) e = 0: from the row with the larger entries. */
    double x, y;
    if (fabs(a - l) + fabs(bb) >= fabs(bb) + fabs(c - l)) {
        x = -bb;
        y = a - l;
    } else {
        x = c - l;
        y = -bb;
    }
    double n = hypot(x, y);
    if (!(n > 0)) {
        x = 1;
        y = 0;
        n = 1;
    }
    e[0] = x / n;
    e[1] = y / n;
    *lam = l;
}

/* 1 when p is held on a side of P's domain where a side of P lies on Q (the side's own
 * pieces are the curve there). */
static int on_coside(const band *b, const vpt *p)
{
    for (slong i = 0; i < b->nsl; i++) {
        const sline *l = b->sl + i;
        int k = l->k;
        double w = b->dp[2 * k + 1] - b->dp[2 * k], eps = 1e-12 * w;
        if ((p->fixed >> k & 1u) && fabs(p->uv[k] - l->c) <= eps && p->uv[!k] >= l->lo - eps &&
            p->uv[!k] <= l->hi + eps)
            return 1;
    }
    return 0;
}

/* p on a side of P lying on Q: its point X, the foot Y on Q (on Q's side, where X may lie just
 * beyond it) and D = |X - Y|. 1 when D <= tol, 0 otherwise. */
static int side_eval(const band *b, vpt *p)
{
    cb_nurbs_surface_eval(p->X, b->P, p->uv[0], p->uv[1]);
    if (!isfinite(_cb_ssi_nurbs_project(p->st, b->Q, p->X, 1)))
        return 0;
    cb_nurbs_surface_eval(p->Y, b->Q, p->st[0], p->st[1]);
    p->D = cb_vec3_dist(p->X, p->Y);
    return p->D <= b->tol;
}

/* Moves p onto the valley of D: Newton on dD/de = 0 along the direction e across the valley
 * (Hessian's eigenvector of largest eigenvalue), or along P's free parameter when the other is
 * held on a side of P's domain (p->fixed; a step past a side lands on it and holds it). 1 when
 * it converged with |D| <= tol; 2 when a step landed on a side of P lying on Q (on_coside),
 * held there, within tol of Q (side_eval); -1 when the foot left Q's domain; 0 otherwise (no
 * valley, no convergence, not within tol). */
static int settle(const band *b, vpt *p)
{
    const double wp[2] = {b->dp[1] - b->dp[0], b->dp[3] - b->dp[2]};
    for (int it = 0; it < VALLEY_ITERS; it++) {
        int ev = vpt_eval(b, p);
        if (ev != 1)
            return ev;
        double e[2], lam;
        if (p->fixed & 1u) {
            e[0] = 0;
            e[1] = 1;
            lam = p->H[1][1];
        } else if (p->fixed & 2u) {
            e[0] = 1;
            e[1] = 0;
            lam = p->H[0][0];
        } else {
            across(e, &lam, (const double(*)[2])p->H);
        }
        if (!(fabs(lam) > 0))
            return 0;
        double tau = -(p->g[0] * e[0] + p->g[1] * e[1]) / lam;
        double n[2] = {p->uv[0] + tau * e[0], p->uv[1] + tau * e[1]};
        /* Past a side of P's domain: onto it, that parameter held from then on (the valley
         * ends on that side; along it, D's minimum). */
        for (int k = 0; k < 2; k++)
            if (!(n[k] >= b->dp[2 * k] && n[k] <= b->dp[2 * k + 1])) {
                if (!isfinite(n[k]))
                    return 0;
                n[k] = clampd(n[k], b->dp[2 * k], b->dp[2 * k + 1]);
                p->fixed |= 1u << k;
            }
        if (p->fixed) {
            /* A side of P lying on Q: D vanishes along it, the valley ends where it meets it. */
            vpt q = *p;
            q.uv[0] = n[0];
            q.uv[1] = n[1];
            if (on_coside(b, &q)) {
                *p = q;
                return side_eval(b, p) ? 2 : 0;
            }
        }
        if (p->fixed == 3u) {
            p->uv[0] = n[0];
            p->uv[1] = n[1];
            int ev = vpt_eval(b, p);
            return ev != 1 ? ev : fabs(p->D) <= b->tol;
        }
        double moved = fmax(fabs(tau * e[0]) / wp[0], fabs(tau * e[1]) / wp[1]);
        p->uv[0] = n[0];
        p->uv[1] = n[1];
        if (moved <= 1e-12) {
            int ev = vpt_eval(b, p);
            if (ev != 1)
                return ev;
            return fabs(p->D) <= b->tol;
        }
    }
    return 0;
}

static void mid3(double m[3], const vpt *p)
{
    for (int q = 0; q < 3; q++)
        m[q] = 0.5 * (p->X[q] + p->Y[q]);
}

/* The 3D speed of P at uv along the parameter direction t. */
static double param_speed(const band *b, const double uv[2], const double t[2])
{
    double dp[6][3], v3[3];
    cb_nurbs_surface_eval_derivs(dp, b->P, uv[0], uv[1]);
    for (int q = 0; q < 3; q++)
        v3[q] = dp[1][q] * t[0] + dp[2][q] * t[1];
    return cb_vec3_norm(v3);
}

/* A growing polyline of valley points. */
typedef struct {
    slong n, alloc;
    vpt *p;
} vline;

/* 0, 1 when the line has MAX_POINTS points already (a walk that does not end), -1 when out of
 * memory. */
static int vline_push(vline *l, const vpt *p)
{
    if (l->n == l->alloc) {
        slong na = l->alloc ? 2 * l->alloc : 64;
        if (na > MAX_POINTS)
            return 1;
        vpt *q = realloc(l->p, (size_t)na * sizeof *q);
        if (!q)
            return -1;
        l->p = q;
        l->alloc = na;
    }
    l->p[l->n++] = *p;
    return 0;
}

/* 1 when X lies in a member's 3D box grown by tol. */
static int in_members(const double X[3], const _cb_ssi_tiny *const *m, slong nm, double tol)
{
    for (slong i = 0; i < nm; i++) {
        int in = 1;
        for (int q = 0; q < 3 && in; q++)
            in = X[q] >= m[i]->lo[q] - tol && X[q] <= m[i]->hi[q] + tol;
        if (in)
            return 1;
    }
    return 0;
}

/* band's setup on P, Q (B-spline) with the box of the members m. */
static void band_setup(band *b, const cb_ssi_surface *P, const cb_ssi_surface *Q,
                       const _cb_ssi_tiny *const *m, slong nm, double tol, double chord,
                       double max_seg)
{
    memset(b, 0, sizeof *b);
    b->P = P->nurbs;
    b->Q = Q->nurbs;
    cb_nurbs_surface_domain(P->nurbs, b->dp);
    cb_nurbs_surface_domain(Q->nurbs, b->dq);
    b->tol = tol;
    b->chord = chord;
    b->max_seg = max_seg;
    for (int c = 0; c < 3; c++) {
        b->lo[c] = HUGE_VAL;
        b->hi[c] = -HUGE_VAL;
    }
    for (slong i = 0; i < nm; i++)
        for (int c = 0; c < 3; c++) {
            b->lo[c] = fmin(b->lo[c], m[i]->lo[c]);
            b->hi[c] = fmax(b->hi[c], m[i]->hi[c]);
        }
}

/* Traces the valley from the settled point s in direction sgn (+1, -1 along the valley's
 * tangent turned to s's) into l (s first). Returns 2 when it came back to s (closed; s is
 * appended again), 1 when it ended on a side of P's domain or where Q ends, 0 when it failed,
 * -1 out of memory. On a side of P lying on Q, where D vanishes along the side and the valley
 * meets it, the last point is where the step or Newton's method put it on the side, within tol
 * of Q there (side_eval; its chord's midpoint checked as it is, within tol). */
static int walk(vline *l, const band *b, const vpt *s, int sgn, const _cb_ssi_tiny *const *m,
                slong nm, double *trav)
{
    l->n = 0;
    int pr = vline_push(l, s);
    if (pr)
        return pr < 0 ? -1 : 0;
    double len = fmin(b->max_seg, 64 * b->chord), prev_dir[2] = {0, 0}, S[3];
    mid3(S, s);
    *trav = 0;
    for (;;) {
        const vpt *cur = l->p + l->n - 1;
        if (cur->fixed && l->n > 1)
            return 1;
        double e[2], lam;
        across(e, &lam, (const double(*)[2])cur->H);
        double t[2] = {-e[1], e[0]};
        if (l->n == 1) {
            t[0] *= sgn;
            t[1] *= sgn;
        } else if (t[0] * prev_dir[0] + t[1] * prev_dir[1] < 0) {
            t[0] = -t[0];
            t[1] = -t[1];
        }
        double speed = param_speed(b, cur->uv, t);
        if (!(speed > 0))
            return 0;
        vpt nx;
        double dev = 0;
        int qside = 0;
        for (;;) {
            /* Steps shrunk to nothing: an end where Q's domain ends, a failure otherwise. */
            if (len < 4 * b->tol)
                return qside ? 1 : 0;
            double h = len / speed;
            nx = *cur;
            nx.fixed = 0;
            double a = 1;
            int hit = -1;
            for (int k = 0; k < 2; k++) {
                double to = cur->uv[k] + h * t[k];
                double lo = b->dp[2 * k], hi = b->dp[2 * k + 1];
                if (to < lo || to > hi) {
                    double ak = ((to < lo ? lo : hi) - cur->uv[k]) / (h * t[k]);
                    if (ak < a) {
                        a = ak;
                        hit = k;
                    }
                }
            }
            nx.uv[0] = cur->uv[0] + a * h * t[0];
            nx.uv[1] = cur->uv[1] + a * h * t[1];
            if (hit >= 0) {
                nx.uv[hit] = t[hit] < 0 ? b->dp[2 * hit] : b->dp[2 * hit + 1];
                nx.fixed = 1u << hit;
                nx.uv[!hit] = clampd(nx.uv[!hit], b->dp[2 * !hit], b->dp[2 * !hit + 1]);
            }
            /* Onto a side of P lying on Q (by the step, or by Newton's method across the
             * valley): the curve ends there. */
            int side = hit >= 0 && on_coside(b, &nx), sn;
            if (side) {
                sn = side_eval(b, &nx);
            } else {
                sn = settle(b, &nx);
                side = sn == 2;
                sn = side ? 1 : sn;
            }
            if (sn != 1) {
                qside = sn == -1;
                len *= 0.5;
                continue;
            }
            /* The sagitta: the valley point between them against the chord's midpoint (on the
             * way to such a side, or where the midpoint settles on one, the chord's midpoint as
             * it is, if within tol). */
            vpt md = *cur;
            md.fixed = cur->fixed & nx.fixed;
            md.uv[0] = 0.5 * (cur->uv[0] + nx.uv[0]);
            md.uv[1] = 0.5 * (cur->uv[1] + nx.uv[1]);
            int sm = settle(b, &md);
            if (sm == 2 || (sm != 1 && side)) {
                md = *cur;
                md.fixed = 0;
                md.uv[0] = 0.5 * (cur->uv[0] + nx.uv[0]);
                md.uv[1] = 0.5 * (cur->uv[1] + nx.uv[1]);
                sm = side_eval(b, &md);
            }
            if (sm != 1) {
                qside = sm == -1;
                len *= 0.5;
                continue;
            }
            double A[3], B[3], M[3], C[3];
            mid3(A, cur);
            mid3(B, &nx);
            mid3(M, &md);
            for (int q = 0; q < 3; q++)
                C[q] = 0.5 * (A[q] + B[q]);
            dev = cb_vec3_dist(M, C);
            if (dev > b->chord || cb_vec3_dist(A, B) > b->max_seg) {
                len *= 0.5;
                continue;
            }
            break;
        }
        double A[3], B[3];
        mid3(A, cur);
        mid3(B, &nx);
        if (!in_members(B, m, nm, b->tol))
            return 0;
        prev_dir[0] = nx.uv[0] - cur->uv[0];
        prev_dir[1] = nx.uv[1] - cur->uv[1];
        *trav += cb_vec3_dist(A, B);
        /* Back at the start: the last chord passes s within the sagitta bound. */
        double at;
        double ds = cb_seg3_nearest(&at, A, B, S);
        if (l->n >= 3 && *trav > 4 * len && ds <= 2 * b->chord + 10 * b->tol) {
            pr = vline_push(l, s);
            return pr ? (pr < 0 ? -1 : 0) : 2;
        }
        pr = vline_push(l, &nx);
        if (pr)
            return pr < 0 ? -1 : 0;
        if (dev < 0.25 * b->chord)
            len = fmin(1.5 * len, b->max_seg);
    }
}

/* Distance from X to the polyline l. */
static double line_dist(const vline *l, const double X[3])
{
    double best = HUGE_VAL, A[3], B[3], lam;
    for (slong i = 0; i < l->n; i++) {
        mid3(A, l->p + i);
        if (i + 1 < l->n) {
            mid3(B, l->p + i + 1);
            best = fmin(best, cb_seg3_nearest(&lam, A, B, X));
        } else {
            best = fmin(best, cb_vec3_dist(A, X));
        }
    }
    return best;
}

/* 1 when the polyline l meets member t's 3D box grown by slack. */
static int line_meets_box(const vline *l, const _cb_ssi_tiny *t, double slack)
{
    double A[3], B[3];
    for (slong i = 0; i < l->n; i++) {
        mid3(A, l->p + i);
        mid3(B, l->p + (i + 1 < l->n ? i + 1 : i));
        if (cb_seg3_meets_box(A, B, t->lo, t->hi, slack))
            return 1;
    }
    return 0;
}

static int emit(_cb_ssi_piece_set *out, const vline *l, int closed)
{
    _cb_ssi_piece *pc = _cb_ssi_piece_set_add(out);
    if (!pc)
        return -1;
    pc->tangential = 1;
    pc->within = 1;
    pc->closed = closed;
    for (slong i = 0; i < l->n; i++) {
        _cb_ssi_pq q;
        memset(&q, 0, sizeof q);
        memcpy(q.uv, l->p[i].uv, sizeof q.uv);
        memcpy(q.st, l->p[i].st, sizeof q.st);
        q.fixed = l->p[i].fixed;
        double X[3];
        mid3(X, l->p + i);
        if (_cb_ssi_piece_push(pc, &q, X) != CB_OK)
            return -1;
        pc->gap = fmax(pc->gap, cb_vec3_dist(l->p[i].X, l->p[i].Y));
    }
    return 0;
}

/* The sides lying on Q from the side pieces of sets into b (b->sl malloc'd); -1 when out of
 * memory. */
static int side_lines(band *b, const _cb_ssi_piece_set *sets, slong nsets)
{
    b->sl = NULL;
    b->nsl = 0;
    slong n = 0;
    for (slong k = 0; k < nsets; k++)
        for (slong q = 0; q < sets[k].n; q++)
            n += sets[k].p[q].side && sets[k].p[q].n >= 2;
    if (n == 0)
        return 0;
    b->sl = malloc((size_t)n * sizeof *b->sl);
    if (!b->sl)
        return -1;
    for (slong k = 0; k < nsets; k++)
        for (slong q = 0; q < sets[k].n; q++) {
            const _cb_ssi_piece *pc = sets[k].p + q;
            if (!pc->side || pc->n < 2)
                continue;
            const double *a = pc->pt[0].uv, *z = pc->pt[pc->n - 1].uv;
            /* Along a side one of P's parameters is the side's value at every point. */
            int dir = a[0] == z[0] ? 0 : a[1] == z[1] ? 1 : -1;
            if (dir < 0 || a[!dir] == z[!dir])
                continue;
            sline *l = b->sl + b->nsl++;
            l->k = dir;
            l->c = a[dir];
            l->lo = fmin(a[!dir], z[!dir]);
            l->hi = fmax(a[!dir], z[!dir]);
        }
    return 0;
}

/* 1 when a side piece of sets meets member t's 3D box grown by slack. */
static int side_meets_box(const _cb_ssi_piece_set *sets, slong nsets, const _cb_ssi_tiny *t,
                          double slack)
{
    for (slong k = 0; k < nsets; k++)
        for (slong q = 0; q < sets[k].n; q++) {
            const _cb_ssi_piece *pc = sets[k].p + q;
            if (!pc->side)
                continue;
            for (slong i = 0; i + 1 < pc->n; i++)
                if (cb_seg3_meets_box(pc->xyz + 3 * i, pc->xyz + 3 * (i + 1), t->lo, t->hi, slack))
                    return 1;
        }
    return 0;
}

int _cb_ssi_band_trace(_cb_ssi_piece_set *out, const _cb_ssi_piece_set *sets, slong nsets,
                       const cb_ssi_surface *P, const cb_ssi_surface *Q,
                       const _cb_ssi_tiny *const *m, slong nm, double tol, double chord,
                       double max_seg)
{
    if (P->kind != CB_SSI_NURBS || Q->kind != CB_SSI_NURBS || nm == 0)
        return 0;
    band b;
    band_setup(&b, P, Q, m, nm, tol, chord, max_seg);
    if (side_lines(&b, sets, nsets))
        return -1;
    vline lines[MAX_CURVES], fw = {0, 0, NULL}, bw = {0, 0, NULL};
    double near = 2 * chord + 10 * tol; /* a point on a traced curve */
    int closed[MAX_CURVES], nl = 0, st = 1;
    /* done[i]: 1 on a curve, 2 valley point past Q's domain, 3 no valley point. crossed[i]: a
     * side's piece crosses member i, or (once traced) a curve. */
    char *done = calloc((size_t)nm, 1), *crossed = calloc((size_t)nm, 1);
    if (!done || !crossed) {
        free(done);
        free(crossed);
        free(b.sl);
        return -1;
    }
    for (slong i = 0; i < nm && b.nsl > 0; i++)
        crossed[i] = side_meets_box(sets, nsets, m[i], near);
    for (slong i = 0; i < nm && st == 1; i++) {
        /* Crossed by a side lying on Q: that side's pieces are the curve there (where the
         * surfaces stay within tol beside it, as around a corner where two such sides cross,
         * or where a band along a tangential curve meets the side). */
        if (done[i] || crossed[i])
            continue;
        /* The member's valley point: on a traced curve already, or the seed of a new one. */
        vpt s;
        memset(&s, 0, sizeof s);
        memcpy(s.uv, m[i]->uv, sizeof s.uv);
        memcpy(s.st, m[i]->st, sizeof s.st);
        int sr = settle(&b, &s);
        if (sr == -1) {
            /* Its valley point lies past Q's domain: checked once the curves are traced. */
            done[i] = 2;
            continue;
        }
        double S[3];
        mid3(S, &s);
        if (sr == 2) {
            /* On a side of P lying on Q: that side's pieces are the curve there. */
            done[i] = 1;
            continue;
        }
        if (sr != 1 && b.nsl == 0) {
            st = 0;
            break;
        }
        if (sr != 1) {
            /* No valley point (Newton not converging where the valley is not defined: beside
             * the node where the band meets a side lying on Q): checked once the curves are
             * traced. Only there: elsewhere, as around an isolated contact (a bowl of D, whose
             * valley is any line through its bottom), a band with such members is no curve. */
            done[i] = 3;
            continue;
        }
        int on = 0;
        for (int c = 0; c < nl && !on; c++)
            on = line_dist(lines + c, S) <= near;
        if (on) {
            done[i] = 1;
            continue;
        }
        if (nl == MAX_CURVES) {
            st = 0;
            break;
        }
        double trav;
        int w = walk(&fw, &b, &s, 1, m, nm, &trav);
        if (w == 1) {
            /* Open: the other way from the seed too, the two joined at it. */
            int w2 = walk(&bw, &b, &s, -1, m, nm, &trav);
            w = w2 < 0 ? -1 : w2 == 1 ? 1 : 0;
        }
        if (w < 0 || (w == 0 && b.nsl == 0)) {
            st = w;
            break;
        }
        if (w == 0) {
            /* No valley followed from it (beside a side's node, as above): as a member without
             * a valley point. */
            done[i] = 3;
            continue;
        }
        vline *L = lines + nl;
        L->n = L->alloc = 0;
        L->p = NULL;
        closed[nl] = w == 2;
        nl++;
        /* The backward walk reversed, then the forward one; a walk whose first step stayed on
         * the side the seed lies on repeats it (not kept twice). */
        for (slong k = w == 1 ? -(bw.n - 1) : 0; k < fw.n && st == 1; k++) {
            const vpt *q = k < 0 ? bw.p - k : fw.p + k;
            double A[3], B[3];
            mid3(B, q);
            if (L->n > 0) {
                mid3(A, L->p + L->n - 1);
                if (cb_vec3_dist(A, B) <= 0.0625 * tol)
                    continue;
            }
            int pr = vline_push(L, q);
            if (pr)
                st = pr < 0 ? -1 : 0;
        }
        done[i] = 1;
    }
    /* Members whose valley point lies past a side of Q's domain: settled with the roles of P
     * and Q exchanged (onto Q's side, held there; where P ends too, as far as it got), on a
     * traced curve. */
    band sw = b;
    sw.sl = NULL; /* the sides are P's, not those of the roles exchanged */
    sw.nsl = 0;
    sw.P = b.Q;
    sw.Q = b.P;
    memcpy(sw.dp, b.dq, sizeof sw.dp);
    memcpy(sw.dq, b.dp, sizeof sw.dq);
    for (slong i = 0; i < nm && st == 1; i++) {
        if (done[i] != 2)
            continue;
        vpt s;
        memset(&s, 0, sizeof s);
        memcpy(s.uv, m[i]->st, sizeof s.uv);
        memcpy(s.st, m[i]->uv, sizeof s.st);
        double S[3];
        int on = 0;
        int q2 = settle(&sw, &s);
        /* -1: its foot past P's side as well (a corner where both end); its point on Q is
         * the one compared (the foot was not found). */
        if (q2 != 0) {
            memcpy(S, s.X, sizeof S);
            for (int c = 0; c < nl && !on; c++)
                on = line_dist(lines + c, S) <= near;
        }
        if (!on)
            st = 0;
    }
    /* Members without a valley point (beside a node, where the valley is not defined): a
     * curve crosses them (a traced one, or a side's piece), or they lie beside a member one
     * crosses (boxes meeting within tol): the node's region is at most one member wide
     * around the curves meeting there. */
    int deferred = 0;
    for (slong i = 0; i < nm; i++)
        deferred |= done[i] == 3;
    for (slong i = 0; i < nm && deferred && st == 1; i++)
        for (int c = 0; c < nl && !crossed[i]; c++)
            crossed[i] = line_meets_box(lines + c, m[i], near);
    for (slong i = 0; i < nm && st == 1; i++) {
        if (done[i] != 3 || crossed[i])
            continue;
        int on = 0;
        for (slong j = 0; j < nm && !on; j++)
            on = crossed[j] && _cb_ssi_tiny_meet(m[i], m[j], tol);
        if (!on)
            st = 0;
    }
    for (int c = 0; c < nl && st == 1; c++)
        if (emit(out, lines + c, closed[c]))
            st = -1;
    for (int c = 0; c < nl; c++)
        free(lines[c].p);
    free(fw.p);
    free(bw.p);
    free(done);
    free(crossed);
    free(b.sl);
    return st;
}

/* ---------------------------------------------------------------- a band as one point ----- */

/* Deepest halving of a spoke's chord; Newton iterations onto D = 0 and most steps of a trace
 * of D's zero set. */
#define SPOKE_DEPTH 24
#define ZERO_ITERS 20
#define ZERO_STEPS 4000

/* 1 when X lies in the box of the band's members grown by tol. */
static int in_band_box(const band *b, const double X[3])
{
    for (int q = 0; q < 3; q++)
        if (!(X[q] >= b->lo[q] - b->tol && X[q] <= b->hi[q] + b->tol))
            return 0;
    return 1;
}

/* p at p->uv (p->st: the foot's start): X = P(uv) and its foot Y on Q. 1 when Y lies inside
 * Q's domain (or on a side, X not beyond it), |X - Y| <= tol (an intersection point within tol)
 * and the middle of X and Y in the members' box grown by tol; 0 otherwise. */
static int spoke_eval(const band *b, vpt *p)
{
    double d[6][3], M[3];
    cb_nurbs_surface_eval(p->X, b->P, p->uv[0], p->uv[1]);
    if (foot(b, p, d) != 1)
        return 0;
    memcpy(p->Y, d[0], sizeof p->Y);
    mid3(M, p);
    return cb_vec3_dist(p->X, p->Y) <= b->tol && in_band_box(b, M);
}

/* The points strictly between a and z of the straight line from a to z in P's parameters
 * (feet on Q from the line between their feet), into l in order: each chord halved while
 * longer than max_seg or while the point at its middle parameters lies farther than chord from
 * its middle. 1, 0 when a point is not inside the band (spoke_eval) or the line has too many
 * points, -1 out of memory. */
static int spoke_fill(vline *l, const band *b, const vpt *a, const vpt *z, int depth)
{
    vpt h;
    memset(&h, 0, sizeof h);
    for (int k = 0; k < 2; k++) {
        h.uv[k] = 0.5 * (a->uv[k] + z->uv[k]);
        h.st[k] = 0.5 * (a->st[k] + z->st[k]);
    }
    if (!spoke_eval(b, &h))
        return 0;
    double A[3], Z[3], H[3], C[3];
    mid3(A, a);
    mid3(Z, z);
    mid3(H, &h);
    for (int q = 0; q < 3; q++)
        C[q] = 0.5 * (A[q] + Z[q]);
    if (cb_vec3_dist(A, Z) <= b->max_seg && cb_vec3_dist(H, C) <= b->chord)
        return 1;
    if (depth >= SPOKE_DEPTH)
        return 0;
    int r = spoke_fill(l, b, a, &h, depth + 1);
    if (r == 1) {
        r = vline_push(l, &h);
        r = r == 0 ? 1 : r < 0 ? -1 : 0;
    }
    if (r == 1)
        r = spoke_fill(l, b, &h, z, depth + 1);
    return r;
}

/* Breadth-first over the members from member r, two members neighbours when their boxes meet
 * within tol / 10 (as they were clustered): par[i] the next member from i towards r (-1 for r
 * and for a member not reached). -1 when out of memory, else 0. */
static int member_tree(slong *par, const _cb_ssi_tiny *const *m, slong nm, slong r, double tol)
{
    slong *queue = malloc((size_t)nm * sizeof *queue);
    char *seen = calloc((size_t)nm, 1);
    if (!queue || !seen) {
        free(queue);
        free(seen);
        return -1;
    }
    for (slong i = 0; i < nm; i++)
        par[i] = -1;
    slong head = 0, tail = 0;
    queue[tail++] = r;
    seen[r] = 1;
    while (head < tail) {
        slong i = queue[head++];
        for (slong j = 0; j < nm; j++)
            if (!seen[j] && _cb_ssi_tiny_meet(m[i], m[j], 0.1 * tol)) {
                seen[j] = 1;
                par[j] = i;
                queue[tail++] = j;
            }
    }
    free(queue);
    free(seen);
    return 0;
}

/* The spoke from a to the band's point nd (member r, par from member_tree) into l: the straight
 * line in P's parameters (spoke_fill), or where a point of it is not within tol of Q (the band
 * bends, or is porous: sub-pairs certified apart lie inside it), the line through the points of
 * the members on the way from the member holding a's point to r (spoke_eval; one that fails it
 * is passed by). 1, 0 not within tol, -1 out of memory. */
static int spoke_make(vline *l, const band *b, const vpt *a, const vpt *nd,
                      const _cb_ssi_tiny *const *m, slong nm, slong r, const slong *par)
{
    l->n = 0;
    int st = spoke_fill(l, b, a, nd, 0);
    if (st != 0)
        return st;
    l->n = 0;
    double A[3];
    mid3(A, a);
    slong j = -1;
    for (slong i = 0; i < nm && j < 0; i++)
        if ((par[i] >= 0 || i == r) && in_members(A, m + i, 1, b->tol))
            j = i;
    if (j < 0)
        return 0;
    vpt from = *a;
    for (; j >= 0 && st >= 0; j = par[j]) {
        vpt w;
        memset(&w, 0, sizeof w);
        memcpy(w.uv, m[j]->uv, sizeof w.uv);
        memcpy(w.st, m[j]->st, sizeof w.st);
        if (j == r || !spoke_eval(b, &w))
            continue;
        st = spoke_fill(l, b, &from, &w, 0);
        if (st != 1)
            return st;
        st = vline_push(l, &w);
        if (st)
            return st < 0 ? -1 : 0;
        from = w;
    }
    return spoke_fill(l, b, &from, nd, 0);
}

/* Newton's method on D = 0 from p (p->st the foot's start), each step the least change of P's
 * parameters (along D's gradient). 1 when a step moved P's point by at most tol / 1024 (where
 * D's gradient is small, as near a tangency, a small |D| alone leaves the point far from the
 * zero set) and |D| <= tol, inside P's domain; else 0. A step past a side of P's domain fails,
 * or with hold, lands on the side and holds that parameter there (p->fixed; the root along the
 * side: where a curve ends on it). */
static int zero_correct(const band *b, vpt *p, int hold)
{
    double prev[3];
    for (int it = 0; it < ZERO_ITERS; it++) {
        if (vpt_eval(b, p) != 1)
            return 0;
        if (it > 0 && cb_vec3_dist(prev, p->X) <= b->tol / 1024)
            return fabs(p->D) <= b->tol;
        memcpy(prev, p->X, sizeof prev);
        double g[2] = {p->fixed & 1u ? 0 : p->g[0], p->fixed & 2u ? 0 : p->g[1]};
        double g2 = g[0] * g[0] + g[1] * g[1];
        if (!(g2 > 0))
            return 0;
        for (int k = 0; k < 2; k++) {
            p->uv[k] -= p->D * g[k] / g2;
            if (!(p->uv[k] >= b->dp[2 * k] && p->uv[k] <= b->dp[2 * k + 1])) {
                if (!hold || !isfinite(p->uv[k]))
                    return 0;
                p->uv[k] = clampd(p->uv[k], b->dp[2 * k], b->dp[2 * k + 1]);
                p->fixed |= 1u << k;
            }
        }
    }
    return 0;
}

/* The zero set of D followed from the branch end a (on it) into the band, first along dir0
 * (P's parameters), into l (a first): steps along the level line, each corrected onto it
 * (zero_correct) and kept when the correction moved the point at most a quarter of the step,
 * the point at the step's middle lies within chord of the chord's middle and D's gradient
 * keeps its side at both, halved otherwise, starting at chord and never above 2 chord (nor
 * max_seg): short beside the other curves of a band's zero set. It stops where a point leaves
 * the members' box grown by tol (that point not kept), comes within 2 chord + 10 tol of one of
 * the nz points stop[] other than a's own (another end: *met its index, else -1), the step
 * falls below 4 tol, or after ZERO_STEPS steps. 0, -1 out of memory. */
static int zero_trace(vline *l, const band *b, const vpt *a, const double dir0[2],
                      const double (*stop)[3], slong nz, slong self, slong *met)
{
    *met = -1;
    l->n = 0;
    vpt p = *a;
    if (vpt_eval(b, &p) != 1)
        return 0;
    if (vline_push(l, &p) < 0)
        return -1;
    double prev[2] = {dir0[0], dir0[1]}, len = b->chord, near = 2 * b->chord + 10 * b->tol;
    for (int n = 0; n < ZERO_STEPS; n++) {
        double g = hypot(p.g[0], p.g[1]);
        if (!(g > 0))
            return 0;
        double t[2] = {-p.g[1] / g, p.g[0] / g};
        if (t[0] * prev[0] + t[1] * prev[1] < 0) {
            t[0] = -t[0];
            t[1] = -t[1];
        }
        double speed = param_speed(b, p.uv, t);
        if (!(speed > 0))
            return 0;
        vpt nx, h;
        int ok = 0;
        for (; len >= 4 * b->tol && !ok; len *= 0.5) {
            nx = h = p;
            for (int k = 0; k < 2; k++) {
                nx.uv[k] += len / speed * t[k];
                h.uv[k] += 0.5 * len / speed * t[k];
            }
            double guess[2] = {nx.uv[0], nx.uv[1]};
            if (zero_correct(b, &nx, 0) != 1 || zero_correct(b, &h, 0) != 1)
                continue;
            double moved = hypot(nx.uv[0] - guess[0], nx.uv[1] - guess[1]) * speed;
            double A[3], B[3], H[3], C[3];
            mid3(A, &p);
            mid3(B, &nx);
            mid3(H, &h);
            for (int q = 0; q < 3; q++)
                C[q] = 0.5 * (A[q] + B[q]);
            /* D's gradient keeps its side: where two curves of the zero set come close (two
             * loops touching, two branches crossing) the other one has it the other way. */
            ok = moved <= 0.25 * len && cb_vec3_dist(H, C) <= b->chord &&
                 nx.g[0] * p.g[0] + nx.g[1] * p.g[1] > 0 && h.g[0] * p.g[0] + h.g[1] * p.g[1] > 0;
            if (ok)
                break;
        }
        if (!ok)
            return 0;
        double B[3];
        mid3(B, &nx);
        if (!in_band_box(b, B))
            return 0;
        if (vline_push(l, &nx) < 0)
            return -1;
        prev[0] = nx.uv[0] - p.uv[0];
        prev[1] = nx.uv[1] - p.uv[1];
        p = nx;
        for (slong o = 0; o < nz; o++)
            if (o != self && cb_vec3_dist(B, stop[o]) <= near) {
                *met = o;
                return 0;
            }
        len = fmin(1.5 * len, fmin(2 * b->chord, b->max_seg));
    }
    return 0;
}

/* 1 when the middle of a point of l lies within eps of P. */
static int vline_near(const vline *l, const double P[3], double eps)
{
    double Q[3];
    for (slong i = 0; i < l->n; i++) {
        mid3(Q, l->p + i);
        if (cb_vec3_dist(P, Q) <= eps)
            return 1;
    }
    return 0;
}

/* 1 when the boxes of the middles of a's and b's points meet within eps. */
static int vline_boxes_meet(const vline *a, const vline *b, double eps)
{
    double lo[2][3], hi[2][3], M[3];
    for (int w = 0; w < 2; w++) {
        const vline *l = w ? b : a;
        for (int c = 0; c < 3; c++) {
            lo[w][c] = HUGE_VAL;
            hi[w][c] = -HUGE_VAL;
        }
        for (slong i = 0; i < l->n; i++) {
            mid3(M, l->p + i);
            for (int c = 0; c < 3; c++) {
                lo[w][c] = fmin(lo[w][c], M[c]);
                hi[w][c] = fmax(hi[w][c], M[c]);
            }
        }
    }
    for (int c = 0; c < 3; c++)
        if (lo[0][c] > hi[1][c] + eps || lo[1][c] > hi[0][c] + eps)
            return 0;
    return 1;
}

/* One piece end to be joined to the band's point: set k, piece q, end e; its zero-set trace. */
typedef struct {
    slong k, q;
    int e;
    int frag; /* both ends of its piece lie in the band (a piece of a sub-pair between two
                 members): not traced; 2 once a trace covers it (the piece is dropped) */
    vpt a;      /* the end's point */
    slong met;  /* the end its trace came to, or -1 */
    slong link; /* the end it is joined to along its trace or the other's (-1: the node) */
    slong rec;  /* the record of its link */
    vline spoke, trace;
} band_end;

/* 1 when every point of pc lies in a member's box grown by tol. */
static int piece_inside(const _cb_ssi_piece *pc, const _cb_ssi_tiny *const *m, slong nm,
                        double tol)
{
    for (slong i = 0; i < pc->n; i++)
        if (!in_members(pc->xyz + 3 * i, m, nm, tol))
            return 0;
    return 1;
}

/* Appends the spoke's points and then the band's point nd to pc's end e (e = 0: before its
 * first point, in reverse); CB_OK or CB_ERR_NOMEM (pc as it was). */
static cb_status spoke_join(_cb_ssi_piece *pc, int e, const vline *s, const vpt *nd)
{
    _cb_ssi_piece np;
    _cb_ssi_piece_init(&np);
    _cb_ssi_piece *to = e ? pc : &np;
    slong n0 = pc->n;
    for (slong i = 0; i <= s->n; i++) {
        /* e = 1: the spoke from the end, then the point; e = 0: the point, the spoke back. */
        const vpt *v = e ? (i < s->n ? s->p + i : nd) : (i == 0 ? nd : s->p + s->n - i);
        _cb_ssi_pq q;
        memset(&q, 0, sizeof q);
        memcpy(q.uv, v->uv, sizeof q.uv);
        memcpy(q.st, v->st, sizeof q.st);
        double X[3];
        mid3(X, v);
        if (_cb_ssi_piece_push(to, &q, X) != CB_OK) {
            pc->n = n0;
            free(np.pt);
            free(np.xyz);
            return CB_ERR_NOMEM;
        }
        pc->gap = fmax(pc->gap, cb_vec3_dist(v->X, v->Y));
    }
    if (e)
        return CB_OK;
    for (slong i = 0; i < pc->n; i++)
        if (_cb_ssi_piece_push(&np, pc->pt + i, pc->xyz + 3 * i) != CB_OK) {
            free(np.pt);
            free(np.xyz);
            return CB_ERR_NOMEM;
        }
    free(pc->pt);
    free(pc->xyz);
    pc->pt = np.pt;
    pc->xyz = np.xyz;
    pc->n = np.n;
    pc->alloc = np.alloc;
    return CB_OK;
}

/* The ends of pieces of sets in the members' boxes (grown by tol; pieces lying wholly in them
 * and pieces of sides lying on the other surface left out) into *be (*ne of them, malloc'd),
 * their points evaluated; *touched: a piece passes through a member's box. 0, -1 out of
 * memory. */
static int band_ends(band_end **be, slong *ne, int *touched, const band *b,
                     const _cb_ssi_piece_set *sets, slong nsets, const _cb_ssi_tiny *const *m,
                     slong nm)
{
    slong alloc = 0;
    *be = NULL;
    *ne = 0;
    *touched = 0;
    for (slong k = 0; k < nsets; k++)
        for (slong q = 0; q < sets[k].n; q++) {
            const _cb_ssi_piece *pc = sets[k].p + q;
            if (pc->isolated || pc->n < 2 || (!pc->side && piece_inside(pc, m, nm, b->tol)))
                continue;
            for (slong i = 0; i + 1 < pc->n && !*touched; i++)
                for (slong j = 0; j < nm && !*touched; j++)
                    *touched = cb_seg3_meets_box(pc->xyz + 3 * i, pc->xyz + 3 * (i + 1),
                                                 m[j]->lo, m[j]->hi, b->tol);
            /* A side lying on the other surface runs on through the band (its pieces from the
             * members reaching it): no end of it. */
            if (pc->side)
                continue;
            int in[2] = {0, 0};
            for (int e = 0; e < 2 && !pc->closed; e++)
                in[e] = in_members(pc->xyz + 3 * (e ? pc->n - 1 : 0), m, nm, b->tol);
            for (int e = 0; e < 2; e++) {
                slong j = e ? pc->n - 1 : 0;
                if (!in[e])
                    continue;
                if (*ne == alloc) {
                    slong na = alloc ? 2 * alloc : 16;
                    band_end *nb = realloc(*be, (size_t)na * sizeof *nb);
                    if (!nb)
                        return -1;
                    *be = nb;
                    alloc = na;
                }
                band_end *E = *be + (*ne)++;
                memset(E, 0, sizeof *E);
                E->k = k;
                E->q = q;
                E->e = e;
                E->frag = in[0] && in[1];
                E->met = E->link = -1;
                memcpy(E->a.uv, pc->pt[j].uv, sizeof E->a.uv);
                memcpy(E->a.st, pc->pt[j].st, sizeof E->a.st);
                cb_nurbs_surface_eval(E->a.X, b->P, E->a.uv[0], E->a.uv[1]);
                cb_nurbs_surface_eval(E->a.Y, b->Q, E->a.st[0], E->a.st[1]);
            }
        }
    return 0;
}

/* Each end's trace of D's zero set into the band, from the direction of its piece's last chord
 * (stopping at the other ends); the ends of a piece lying in the band between two members
 * (frag) are neither traced nor stopped at, and such a piece whose every point lies within
 * 2 chord + 10 tol of a trace is covered by it (frag 2). 0, -1 out of memory. */
static int band_traces(band_end *be, slong ne, const band *b, const _cb_ssi_piece_set *sets)
{
    double(*stop)[3] = malloc((size_t)ne * sizeof *stop);
    if (!stop)
        return -1;
    for (slong i = 0; i < ne; i++) {
        mid3(stop[i], &be[i].a);
        if (be[i].frag)
            stop[i][0] = stop[i][1] = stop[i][2] = HUGE_VAL;
    }
    int st = 0;
    for (slong i = 0; i < ne && st == 0; i++) {
        if (be[i].frag)
            continue;
        const _cb_ssi_piece *pc = sets[be[i].k].p + be[i].q;
        slong j = be[i].e ? pc->n - 1 : 0, j1 = be[i].e ? pc->n - 2 : 1;
        double dir[2] = {pc->pt[j].uv[0] - pc->pt[j1].uv[0], pc->pt[j].uv[1] - pc->pt[j1].uv[1]};
        st = zero_trace(&be[i].trace, b, &be[i].a, dir, (const double(*)[3])stop, ne, i,
                        &be[i].met);
    }
    free(stop);
    /* Two ends one trace runs between are one curve through the band (its members left a gap
     * in it): joined there, not at the node; unless the other end's trace came to a third. */
    for (slong i = 0; i < ne; i++)
        be[i].link = -1;
    for (slong i = 0; i < ne; i++) {
        slong j = be[i].met;
        if (j < 0 || be[i].link >= 0 || be[j].link >= 0 || (be[j].met >= 0 && be[j].met != i))
            continue;
        be[i].link = j;
        be[j].link = i;
    }
    double eps = 2 * b->chord + 10 * b->tol;
    for (slong i = 0; i < ne && st == 0; i++) {
        if (be[i].frag != 1)
            continue;
        const _cb_ssi_piece *pc = sets[be[i].k].p + be[i].q;
        int covered = 0;
        for (slong j = 0; j < ne && !covered; j++) {
            covered = be[j].trace.n > 1;
            for (slong v = 0; v < pc->n && covered; v++)
                covered = vline_near(&be[j].trace, pc->xyz + 3 * v, eps);
        }
        /* Both ends of the piece. */
        for (slong j = 0; j < ne && covered; j++)
            if (be[j].k == be[i].k && be[j].q == be[i].q)
                be[j].frag = 2;
    }
    return st;
}

/* The node (see _cb_ssi_band_node): where the traces of the ends not linked meet, the first
 * point of one trace within 2 chord + 10 tol of another that its start is not on (not the
 * same curve the other way), the one where D's gradient is least; with none, where D's
 * gradient is least along those traces (*at: that point's end and index). -1 in at[0] when
 * there is no such trace. */
static void band_meet(vpt *nd, slong at[2], const band_end *be, slong ne, const band *b)
{
    double gmin = HUGE_VAL, eps = 2 * b->chord + 10 * b->tol;
    at[0] = at[1] = -1;
    for (int pass = 0; pass < 2 && at[0] < 0; pass++)
        for (slong i = 0; i < ne; i++) {
            const vline *ti = &be[i].trace;
            if (be[i].link >= 0)
                continue;
            for (slong j = 0; j < ne && pass == 0; j++) {
                const vline *tj = &be[j].trace;
                if (j == i || be[j].link >= 0 || ti->n < 2 || tj->n < 2 ||
                    !vline_boxes_meet(ti, tj, eps))
                    continue;
                double M[3];
                mid3(M, ti->p);
                if (vline_near(tj, M, eps))
                    continue;
                for (slong k = 1; k < ti->n; k++) {
                    mid3(M, ti->p + k);
                    if (vline_near(tj, M, eps)) {
                        double g = hypot(ti->p[k].g[0], ti->p[k].g[1]);
                        if (g < gmin) {
                            gmin = g;
                            *nd = ti->p[k];
                            at[0] = i;
                            at[1] = k;
                        }
                        break;
                    }
                }
            }
            for (slong k = 1; k < ti->n && pass == 1; k++) {
                double g = hypot(ti->p[k].g[0], ti->p[k].g[1]);
                if (g < gmin) {
                    gmin = g;
                    *nd = ti->p[k];
                    at[0] = i;
                    at[1] = k;
                }
            }
        }
}

/* End i's spoke to the node nd (at from band_meet; member r, par from member_tree): its trace
 * as far as its point nearest the node, then on to it by spoke_make (near the node the curves
 * are smooth or the surfaces within tol of each other: a short line). 1, 0 (not within tol),
 * -1 out of memory. */
static int band_spoke(band_end *E, slong i, const slong at[2], const band *b, const vpt *nd,
                      const _cb_ssi_tiny *const *m, slong nm, slong r, const slong *par)
{
    const vline *tr = &E->trace;
    double ND[3], T[3];
    mid3(ND, nd);
    slong jn = -1;
    double dn = HUGE_VAL;
    for (slong j = 0; j < tr->n; j++) {
        mid3(T, tr->p + j);
        if (cb_vec3_dist(T, ND) < dn) {
            dn = cb_vec3_dist(T, ND);
            jn = j;
        }
    }
    if (i == at[0])
        jn = at[1] - 1;
    if (jn < 1)
        return spoke_make(&E->spoke, b, &E->a, nd, m, nm, r, par);
    vline rest = {0, 0, NULL};
    int st = spoke_make(&rest, b, tr->p + jn, nd, m, nm, r, par);
    E->spoke.n = 0;
    for (slong j = 1; j <= jn + rest.n && st == 1; j++) {
        int pr = vline_push(&E->spoke, j <= jn ? tr->p + j : rest.p + j - jn - 1);
        if (pr)
            st = pr < 0 ? -1 : 0;
    }
    free(rest.p);
    return st;
}

_cb_ssi_tiny_region *_cb_ssi_region_slot(_cb_ssi_tiny_region **out, slong n, slong *alloc)
{
    if (n == *alloc) {
        slong na = *alloc ? 2 * *alloc : 8;
        _cb_ssi_tiny_region *q = realloc(*out, (size_t)na * sizeof *q);
        if (!q)
            return NULL;
        *out = q;
        *alloc = na;
    }
    return *out + n;
}

/* A record of the band (box, diameter, job) at the point p into *out (n held, alloc
 * allocated): its index, or -1 when out of memory. */
static slong band_record(_cb_ssi_tiny_region **out, slong *n, slong *alloc, const band *b,
                         slong job, const vpt *p, int ends)
{
    _cb_ssi_tiny_region *rg = _cb_ssi_region_slot(out, *n, alloc);
    if (!rg)
        return -1;
    memset(rg, 0, sizeof *rg);
    memcpy(rg->lo, b->lo, sizeof rg->lo);
    memcpy(rg->hi, b->hi, sizeof rg->hi);
    rg->width = cb_vec3_dist(b->lo, b->hi);
    mid3(rg->X, p);
    memcpy(rg->uv, p->uv, sizeof rg->uv);
    memcpy(rg->st, p->st, sizeof rg->st);
    rg->ends = ends;
    rg->slab = 1;
    rg->job = job;
    return (*n)++;
}

/* Whether end i carries the trace of its link (the one whose trace came to the other; of two
 * that came to each other, the first). */
static int link_carrier(const band_end *be, slong i)
{
    slong j = be[i].link;
    return j >= 0 && be[i].met == j && !(be[j].met == i && j < i);
}

int _cb_ssi_band_node(_cb_ssi_piece_set *sets, slong nsets, const cb_ssi_surface *P,
                      const cb_ssi_surface *Q, const _cb_ssi_tiny *const *m, slong nm,
                      double tol, double chord, double max_seg, slong job,
                      _cb_ssi_tiny_region **out, slong *nout, slong *alloc, char *within)
{
    if (P->kind != CB_SSI_NURBS || Q->kind != CB_SSI_NURBS || nm == 0)
        return 0;
    band b;
    band_setup(&b, P, Q, m, nm, tol, chord, max_seg);
    band_end *be;
    slong ne;
    int touched, st = 1;
    if (band_ends(&be, &ne, &touched, &b, sets, nsets, m, nm) ||
        (ne > 0 && band_traces(be, ne, &b, sets)))
        st = -1;
    /* The node: where the traces meet; with no trace, the candidate of the member nearest the
     * mean of the ends not linked (with none, the centre of the band's box) among those whose
     * two surface points are within tol. */
    vpt nd;
    memset(&nd, 0, sizeof nd);
    slong at[2] = {-1, -1}, nfree = 0;
    double target[3] = {0, 0, 0};
    if (st == 1)
        band_meet(&nd, at, be, ne, &b);
    for (slong i = 0; i < ne; i++)
        nfree += be[i].link < 0 && be[i].frag != 2;
    if (at[0] >= 0) {
        mid3(target, &nd);
    } else {
        for (slong i = 0; i < ne; i++)
            for (int c = 0; c < 3 && be[i].link < 0 && be[i].frag != 2; c++)
                target[c] += (be[i].a.X[c] + be[i].a.Y[c]) / (2.0 * (double)nfree);
        for (int c = 0; c < 3 && nfree == 0; c++)
            target[c] = 0.5 * (b.lo[c] + b.hi[c]);
    }
    slong best = -1;
    double bd = HUGE_VAL;
    for (slong i = 0; i < nm && st == 1; i++) {
        double d = cb_vec3_dist(m[i]->X, target);
        if ((at[0] >= 0 || m[i]->gap <= tol) && d < bd) {
            bd = d;
            best = i;
        }
    }
    if (st == 1 && best < 0)
        st = 0;
    if (st == 1 && at[0] < 0) {
        memcpy(nd.uv, m[best]->uv, sizeof nd.uv);
        memcpy(nd.st, m[best]->st, sizeof nd.st);
        cb_nurbs_surface_eval(nd.X, b.P, nd.uv[0], nd.uv[1]);
        cb_nurbs_surface_eval(nd.Y, b.Q, nd.st[0], nd.st[1]);
    }
    /* Each end's spoke, all checked before any piece changes: a link's carrier has its trace
     * (which ends within 2 chord + 10 tol of the other end, then on to that end's point). */
    slong *par = st == 1 && ne > 0 ? malloc((size_t)nm * sizeof *par) : NULL;
    if (st == 1 && ne > 0 && (!par || member_tree(par, m, nm, best, tol)))
        st = -1;
    for (slong i = 0; i < ne && st == 1; i++) {
        if (be[i].frag == 2 || (be[i].link >= 0 && !link_carrier(be, i)))
            continue;
        if (be[i].link < 0) {
            st = band_spoke(be + i, i, at, &b, &nd, m, nm, best, par);
            continue;
        }
        for (slong j = 1; j < be[i].trace.n && st == 1; j++) {
            int pr = vline_push(&be[i].spoke, be[i].trace.p + j);
            if (pr)
                st = pr < 0 ? -1 : 0;
        }
    }
    /* The records: the node's first, then one per link (at the point of the end its carrier
     * came to). */
    slong rid = st == 1 ? band_record(out, nout, alloc, &b, job, &nd, (int)nfree) : -1;
    if (st == 1 && rid < 0)
        st = -1;
    for (slong i = 0; i < ne && st == 1; i++) {
        _cb_ssi_piece *pc = sets[be[i].k].p + be[i].q;
        if (be[i].frag == 2) {
            /* Covered by a trace: emptied, dropped below. */
            _cb_ssi_piece_clear(pc);
            continue;
        }
        slong to = rid;
        if (be[i].link >= 0 && link_carrier(be, i)) {
            const vpt *z = &be[be[i].link].a;
            to = band_record(out, nout, alloc, &b, job, z, 2);
            be[be[i].link].rec = to; /* the other end's, set below */
            if (to < 0 || spoke_join(pc, be[i].e, &be[i].spoke, z) != CB_OK) {
                st = -1;
                break;
            }
        } else if (be[i].link >= 0) {
            continue;
        } else if (spoke_join(pc, be[i].e, &be[i].spoke, &nd) != CB_OK) {
            st = -1;
            break;
        }
        _cb_ssi_end_clear(pc->end + be[i].e);
        pc->end[be[i].e].region = to;
        within[be[i].k] = 1;
    }
    /* The other ends of links, at their own points, carry their link's record. */
    for (slong i = 0; i < ne && st == 1; i++) {
        if (be[i].frag == 2 || be[i].link < 0 || link_carrier(be, i))
            continue;
        _cb_ssi_piece *pc = sets[be[i].k].p + be[i].q;
        _cb_ssi_end_clear(pc->end + be[i].e);
        pc->end[be[i].e].region = be[i].rec;
        within[be[i].k] = 1;
    }
    /* Pieces lying wholly in the band, or covered by a trace, dropped. */
    for (slong k = 0; k < nsets && st == 1; k++) {
        _cb_ssi_piece_set *ps = sets + k;
        for (slong q = 0; q < ps->n; q++) {
            _cb_ssi_piece *pc = ps->p + q;
            if (pc->n > 0 &&
                (pc->isolated || pc->side || pc->n < 2 || !piece_inside(pc, m, nm, tol)))
                continue;
            _cb_ssi_piece_clear(pc);
            memmove(pc, pc + 1, (size_t)(ps->n - q - 1) * sizeof *pc);
            ps->n--;
            q--;
        }
    }
    if (st == 1)
        (*out)[rid].lone = ne == 0 && !touched;
    for (slong i = 0; i < ne; i++) {
        free(be[i].spoke.p);
        free(be[i].trace.p);
    }
    free(be);
    free(par);
    return st;
}

int _cb_ssi_band_zero_point(const cb_ssi_surface *P, const cb_ssi_surface *Q, double uv[2],
                            double st[2], double X[3], const double lo[3], const double hi[3],
                            double slack, double tol)
{
    if (P->kind != CB_SSI_NURBS || Q->kind != CB_SSI_NURBS)
        return 0;
    band b;
    band_setup(&b, P, Q, NULL, 0, tol, 0, 0);
    for (int c = 0; c < 3; c++) {
        b.lo[c] = lo[c] - slack;
        b.hi[c] = hi[c] + slack;
    }
    vpt p;
    memset(&p, 0, sizeof p);
    memcpy(p.uv, uv, sizeof p.uv);
    memcpy(p.st, st, sizeof p.st);
    double M[3];
    if (zero_correct(&b, &p, 1) != 1)
        return 0;
    mid3(M, &p);
    if (!in_band_box(&b, M) || cb_vec3_dist(p.X, p.Y) > tol)
        return 0;
    memcpy(uv, p.uv, sizeof p.uv);
    memcpy(st, p.st, sizeof p.st);
    memcpy(X, M, sizeof M);
    return 1;
}
