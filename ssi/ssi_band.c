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
        double dp[6][3];
        cb_nurbs_surface_eval_derivs(dp, b->P, cur->uv[0], cur->uv[1]);
        double v3[3];
        for (int q = 0; q < 3; q++)
            v3[q] = dp[1][q] * t[0] + dp[2][q] * t[1];
        double speed = cb_vec3_norm(v3);
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
    if (side_lines(&b, sets, nsets))
        return -1;
    b.P = P->nurbs;
    b.Q = Q->nurbs;
    cb_nurbs_surface_domain(P->nurbs, b.dp);
    cb_nurbs_surface_domain(Q->nurbs, b.dq);
    b.tol = tol;
    b.chord = chord;
    b.max_seg = max_seg;
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
