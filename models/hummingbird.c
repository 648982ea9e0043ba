/* hummingbird.c — a freeform bird-shaped solid of 312 bicubic B-spline faces, the model of the
 * paper's Fig. 12 (Yang, Jia, Yan, ACM TOG 2023: two overlapping birds of 312 patches).
 *
 * Construction, in the model's own frame (x to the beak, y to the left wing, z up):
 *   1. Layout. The surface of the box [-5,5] x [-3,3] x [-3,3] cut into unit squares:
 *      2 (10 * 6 + 6 * 6 + 10 * 6) = 312 quads with sphere topology. Each of the six box sides
 *      is parametrised by lattice coordinates (s, t) along two positive axes e1, e2 chosen with
 *      e1 x e2 pointing out of the box.
 *   2. Guide surface. A box point q goes to the direction d = (q / D) / |q / D| (D stretches the
 *      box so that the wings, thin in z, get more parameter room), then to the star-shaped
 *      point rho(d) d — an ellipsoid radius plus Gaussian lobes for head, beak, wings and tail —
 *      and last through the shear Phi(x, y, z) = (x - SWEEP y^2, y, z + BEND y^2), which sweeps
 *      the wings back and curls them up. Phi has Jacobian determinant 1 and an explicit inverse,
 *      so the guide surface is embedded and the no-fold check can pull the result back.
 *   3. Fitting. Each box edge is a C2 cubic spline with SPANS uniform spans per unit, fitted by
 *      least squares to guide samples with its ends pinned to the images of the box corners.
 *      Each box side is a C2 bicubic spline on the same spans whose four boundary rows are
 *      those edge splines; its interior control points are the separable least-squares fit to
 *      a grid of guide samples (SAMPLES per span).
 *   4. Cutting. The integer knots are raised to multiplicity 3, which cuts every side into
 *      unit pieces of 6 x 6 control points. All pieces of a side are read from one refined
 *      array, whose boundary rows are overwritten by the refined edge splines, so two faces
 *      sharing an edge hold bit-identical rows there: the rows are the edge curves and the
 *      corners are the vertices. The pose is applied to these arrays before they are cut, so
 *      it keeps every shared value shared.
 * Continuity: C2 inside a box side, C0 across box edges (G1 up to the fit error, since the guide
 * surface is smooth there and only the parametrisation has a kink). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/models.h"

#define PI 3.14159265358979323846

/* Lattice half sizes of the box and the stretch D of the box-to-sphere map. */
static const int BOX_HALF[3] = {5, 3, 3};
static const double SPHERE_STRETCH[3] = {5.0, 3.0, 3.5};

enum {
    DEG = 3,            /* bicubic */
    SPANS = 3,          /* knot spans per face and direction: 6 control points */
    SAMPLES = 4,        /* least-squares samples per span and direction */
    FACE_CTRL = 6,      /* control points per face and direction */
    CUT = 5,            /* control point stride between faces in a refined side array */
    N_FACES = 312,      /* 2 (10 * 6 + 6 * 6 + 10 * 6) */
    LATTICE = 11 * 7 * 7,
    FOLD_GRID = 12      /* samples per face and direction of the built-in no-fold check */
};

/* Smallest no-fold margin (a cosine) the generator accepts. */
static const double MIN_MARGIN = 0.01;
/* Body tolerance relative to the scale: the construction is exact to round-off. */
static const double REL_TOL = 1e-9;

/* The shear Phi: wings swept back and curled up with the square of the span position. */
static const double SWEEP = 0.12, BEND = 0.05;

/* The sides of the box: outward axis and sign, and the parameter axes e1 (u) and e2 (v). */
static const struct {
    int normal, sign, e1, e2;
} SIDES[6] = {{0, 1, 1, 2}, {0, -1, 2, 1}, {1, 1, 2, 0}, {1, -1, 0, 2}, {2, 1, 0, 1}, {2, -1, 1, 0}};

/* ---------------------------------------------------------------- guide surface ------------ */

/* A bump of the radius: height * exp(-(1 - d.axis) / spread - (d.flat / thin)^2); thin = 0
 * leaves it round. (1 - d.axis) ~ angle^2 / 2, so sqrt(spread) is the angular half-width. */
typedef struct {
    double axis[3], flat[3];
    double height, spread, thin;
} lobe;

typedef struct {
    double semi[3]; /* body ellipsoid semi-axes */
    lobe lobes[5];  /* head, beak, left wing, right wing, tail */
} bird_shape;

/* v = (x, y, z) scaled to unit length. */
static void unit(double v[3], double x, double y, double z)
{
    v[0] = x;
    v[1] = y;
    v[2] = z;
    cb_vec3_normalize(v);
}

/* The shape for a wing dihedral of `wing` radians; the wings sweep back by 10 degrees. */
static void shape_make(bird_shape *s, double wing)
{
    memset(s, 0, sizeof *s);
    s->semi[0] = 0.75;
    s->semi[1] = 0.40;
    s->semi[2] = 0.42;
    lobe *head = &s->lobes[0], *beak = &s->lobes[1], *tail = &s->lobes[4];
    unit(head->axis, 1, 0, 0.45);
    head->height = 0.32;
    head->spread = 0.03;
    unit(beak->axis, 1, 0, 0.28);
    beak->height = 0.75;
    beak->spread = 0.008;
    double sweep = tan(10 * PI / 180);
    for (int side = 0; side < 2; side++) {
        lobe *w = &s->lobes[2 + side];
        double sy = side ? -1 : 1;
        unit(w->axis, -sweep, sy * cos(wing), sin(wing));
        unit(w->flat, 0, -sy * sin(wing), cos(wing));
        w->height = 1.15;
        w->spread = 0.07;
        w->thin = 0.13;
    }
    unit(tail->axis, -1, 0, 0.12);
    unit(tail->flat, 0.12, 0, 1);
    tail->height = 0.55;
    tail->spread = 0.04;
    tail->thin = 0.10;
}

/* The guide point of box point q (lattice units). */
static void guide_point(double out[3], const bird_shape *s, const double q[3])
{
    double d[3] = {q[0] / SPHERE_STRETCH[0], q[1] / SPHERE_STRETCH[1], q[2] / SPHERE_STRETCH[2]};
    cb_vec3_normalize(d);
    double e = 0;
    for (int k = 0; k < 3; k++)
        e += d[k] * d[k] / (s->semi[k] * s->semi[k]);
    double rho = 1 / sqrt(e);
    for (int k = 0; k < 5; k++) {
        const lobe *l = &s->lobes[k];
        double x = (1 - cb_vec3_dot(d, l->axis)) / l->spread;
        if (l->thin > 0) {
            double f = cb_vec3_dot(d, l->flat) / l->thin;
            x += f * f;
        }
        rho += l->height * exp(-x);
    }
    double y = rho * d[1];
    out[0] = rho * d[0] - SWEEP * y * y;
    out[1] = y;
    out[2] = rho * d[2] + BEND * y * y;
}

/* ---------------------------------------------------------------- least squares ------------ */

/* Uniform clamped cubic knots on [0, m] with SPANS spans per unit: n = SPANS m + 3 control
 * points, n + 4 knots. Multiples of 1/3 are formed as k / 3.0, so the integers are exact. */
static void uniform_knots(double *knots, int m)
{
    int n = SPANS * m + DEG;
    for (int k = 0; k < n + DEG + 1; k++) {
        int j = k - DEG;
        knots[k] = j < 0 ? 0 : j > SPANS * m ? m : j / (double)SPANS;
    }
}

/* Dense basis matrix: A[a * n + i] = N_i(t_a) at the ns samples t_a = a / (SPANS SAMPLES). */
static void basis_matrix(double *A, const double *knots, int n, int ns)
{
    memset(A, 0, sizeof *A * (size_t)ns * n);
    for (int a = 0; a < ns; a++) {
        double t = a / (double)(SPANS * SAMPLES), N[DEG + 1];
        int span = cb_bspline_find_span(n, DEG, knots, t);
        cb_bspline_basis(N, span, t, DEG, knots);
        for (int k = 0; k <= DEG; k++)
            A[a * n + span - DEG + k] = N[k];
    }
}

/* Normal matrix of the interior columns 1 .. n - 2 of A (ns x n): M = A_I^T A_I. */
static void normal_matrix(double *M, const double *A, int n, int ns)
{
    int ni = n - 2;
    for (int i = 0; i < ni; i++)
        for (int j = 0; j < ni; j++) {
            double s = 0;
            for (int a = 0; a < ns; a++)
                s += A[a * n + 1 + i] * A[a * n + 1 + j];
            M[i * ni + j] = s;
        }
}

/* Solves M X = B in place of B (ni x nrhs) for symmetric positive definite M, which is
 * overwritten by its Cholesky factor. M is a B-spline normal matrix with at least SAMPLES
 * samples per span, hence well conditioned; a non-positive pivot cannot occur. */
static void cholesky_solve(double *M, int ni, double *B, int nrhs)
{
    for (int j = 0; j < ni; j++) {
        double d = M[j * ni + j];
        for (int k = 0; k < j; k++)
            d -= M[j * ni + k] * M[j * ni + k];
        d = sqrt(d);
        M[j * ni + j] = d;
        for (int i = j + 1; i < ni; i++) {
            double s = M[i * ni + j];
            for (int k = 0; k < j; k++)
                s -= M[i * ni + k] * M[j * ni + k];
            M[i * ni + j] = s / d;
        }
    }
    for (int r = 0; r < nrhs; r++) {
        for (int i = 0; i < ni; i++) {
            double s = B[i * nrhs + r];
            for (int k = 0; k < i; k++)
                s -= M[i * ni + k] * B[k * nrhs + r];
            B[i * nrhs + r] = s / M[i * ni + i];
        }
        for (int i = ni - 1; i >= 0; i--) {
            double s = B[i * nrhs + r];
            for (int k = i + 1; k < ni; k++)
                s -= M[k * ni + i] * B[k * nrhs + r];
            B[i * nrhs + r] = s / M[i * ni + i];
        }
    }
}

/* ---------------------------------------------------------------- splines of the box ------ */

/* A box edge along `axis` of lattice length m: its coarse spline (SPANS m + 3 points, fitted)
 * and the refined one cut at the integers (CUT m + 1 points), both from the low end. */
typedef struct {
    int axis, m;
    double lo[3]; /* low end, lattice units */
    double *coarse, *fine;
} box_edge;

/* Index of the box edge along axis whose other two coordinates have the signs of q. */
static int box_edge_index(int axis, const double q[3])
{
    int b = (axis + 1) % 3, c = (axis + 2) % 3;
    return axis * 4 + (q[b] > 0) * 2 + (q[c] > 0);
}

/* Refines a polynomial spline of n Euclidean points on uniform_knots(m) at the integers
 * 1 .. m - 1 (each twice more: multiplicity 3) into CUT m + 1 Euclidean points. `dir` says
 * which direction of the surface `s` to refine; for a curve pass s = NULL and c. */
static cb_status cut_at_integers(cb_nurbs_surface_t s, cb_dir dir, cb_nurbs_curve_t c, int m,
                                 cb_error *err)
{
    double x[2 * 10]; /* m <= 10, the longest box edge */
    int nx = 0;
    for (int j = 1; j < m; j++) {
        x[nx++] = j;
        x[nx++] = j;
    }
    return s ? cb_nurbs_surface_refine_knots(s, s, dir, x, nx, err)
             : cb_nurbs_curve_refine_knots(c, c, x, nx, err);
}

/* Fits the box edge to the guide: ends pinned, interior by least squares. */
static cb_status edge_fit(box_edge *e, const bird_shape *shape, cb_error *err)
{
    int m = e->m, n = SPANS * m + DEG, ns = SPANS * SAMPLES * m + 1, ni = n - 2;
    double *knots = malloc(sizeof *knots * (size_t)(n + DEG + 1));
    double *A = malloc(sizeof *A * (size_t)ns * n), *M = malloc(sizeof *M * (size_t)ni * ni);
    double *Q = malloc(sizeof *Q * 3 * (size_t)ns), *rhs = calloc((size_t)ni * 3, sizeof *rhs);
    e->coarse = malloc(sizeof *e->coarse * 3 * (size_t)n);
    e->fine = malloc(sizeof *e->fine * 3 * (size_t)(CUT * m + 1));
    cb_status st = CB_OK;
    if (!knots || !A || !M || !Q || !rhs || !e->coarse || !e->fine) {
        st = cb_error_set(err, CB_ERR_NOMEM, "hummingbird: out of memory");
        goto done;
    }
    uniform_knots(knots, m);
    basis_matrix(A, knots, n, ns);
    normal_matrix(M, A, n, ns);
    for (int a = 0; a < ns; a++) {
        double q[3] = {e->lo[0], e->lo[1], e->lo[2]};
        q[e->axis] += a / (double)(SPANS * SAMPLES);
        guide_point(Q + 3 * a, shape, q);
    }
    memcpy(e->coarse, Q, sizeof *Q * 3);
    memcpy(e->coarse + 3 * (n - 1), Q + 3 * (ns - 1), sizeof *Q * 3);
    for (int a = 0; a < ns; a++)
        for (int k = 0; k < 3; k++) {
            double r = Q[3 * a + k] - A[a * n] * e->coarse[k] -
                       A[a * n + n - 1] * e->coarse[3 * (n - 1) + k];
            for (int i = 0; i < ni; i++)
                rhs[i * 3 + k] += A[a * n + 1 + i] * r;
        }
    cholesky_solve(M, ni, rhs, 3);
    memcpy(e->coarse + 3, rhs, sizeof *rhs * 3 * (size_t)ni);

    cb_nurbs_curve_t c;
    cb_nurbs_curve_init(c);
    st = cb_nurbs_curve_make(c, DEG, knots, n + DEG + 1, e->coarse, NULL, n, err);
    if (!st)
        st = cut_at_integers(NULL, CB_DIR_U, c, m, err);
    if (!st)
        for (int i = 0; i < c->n; i++)
            for (int k = 0; k < 3; k++)
                e->fine[3 * i + k] = c->cw[4 * i + k] / c->cw[4 * i + 3];
    cb_nurbs_curve_clear(c);
done:
    free(knots);
    free(A);
    free(M);
    free(Q);
    free(rhs);
    return st;
}

/* A box side: its lattice origin (the corner at the low end of e1 and e2), sizes, and the
 * refined control array F of (CUT nu + 1) x (CUT nv + 1) points, u outer. */
typedef struct {
    double origin[3];
    int nu, nv;
    double *F;
} box_side;

/* Fits side k: boundary rows from the edges' coarse splines, interior by the separable least
 * squares X = (A^T A)^-1 A^T R B (B^T B)^-1 on the interior columns, R being the samples minus
 * the boundary rows' contribution; then refines and writes the edges' fine rows over F's
 * boundary so that neighbours share them bit for bit. */
static cb_status side_fit(box_side *sd, int k, const box_edge *edges, const bird_shape *shape,
                          cb_error *err)
{
    int e1 = SIDES[k].e1, e2 = SIDES[k].e2, nu = sd->nu, nv = sd->nv;
    int n = SPANS * nu + DEG, m = SPANS * nv + DEG, ni = n - 2, mi = m - 2;
    int ns = SPANS * SAMPLES * nu + 1, nt = SPANS * SAMPLES * nv + 1;
    size_t big = (size_t)(ns > n ? ns : n) * (nt > m ? nt : m) * 3;
    double *ku = malloc(sizeof *ku * (size_t)(n + DEG + 1));
    double *kv = malloc(sizeof *kv * (size_t)(m + DEG + 1));
    double *A = malloc(sizeof *A * (size_t)ns * n), *B = malloc(sizeof *B * (size_t)nt * m);
    double *MA = malloc(sizeof *MA * (size_t)ni * ni), *MB = malloc(sizeof *MB * (size_t)mi * mi);
    double *P = calloc((size_t)n * m * 3, sizeof *P), *Q = malloc(sizeof *Q * big);
    double *T = malloc(sizeof *T * big), *U = malloc(sizeof *U * big);
    sd->F = malloc(sizeof *sd->F * 3 * (size_t)(CUT * nu + 1) * (CUT * nv + 1));
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    cb_status st = CB_OK;
    if (!ku || !kv || !A || !B || !MA || !MB || !P || !Q || !T || !U || !sd->F) {
        st = cb_error_set(err, CB_ERR_NOMEM, "hummingbird: out of memory");
        goto done;
    }
    uniform_knots(ku, nu);
    uniform_knots(kv, nv);
    basis_matrix(A, ku, n, ns);
    basis_matrix(B, kv, m, nt);
    normal_matrix(MA, A, n, ns);
    normal_matrix(MB, B, m, nt);

    /* The four boundary rows, each the coarse spline of a box edge run from its low end. */
    const box_edge *row[2], *col[2];
    for (int side = 0; side < 2; side++) {
        double q[3] = {sd->origin[0], sd->origin[1], sd->origin[2]};
        q[e2] += side * nv;
        row[side] = &edges[box_edge_index(e1, q)];
        q[e2] = sd->origin[e2];
        q[e1] += side * nu;
        col[side] = &edges[box_edge_index(e2, q)];
    }
    for (int i = 0; i < n; i++) {
        memcpy(P + 3 * ((size_t)i * m), row[0]->coarse + 3 * i, sizeof *P * 3);
        memcpy(P + 3 * ((size_t)i * m + m - 1), row[1]->coarse + 3 * i, sizeof *P * 3);
    }
    for (int j = 0; j < m; j++) {
        memcpy(P + 3 * j, col[0]->coarse + 3 * j, sizeof *P * 3);
        memcpy(P + 3 * ((size_t)(n - 1) * m + j), col[1]->coarse + 3 * j, sizeof *P * 3);
    }

    /* Q = samples; T = P_boundary B^T (n x nt); Q -= A T. */
    for (int a = 0; a < ns; a++)
        for (int b = 0; b < nt; b++) {
            double q[3] = {sd->origin[0], sd->origin[1], sd->origin[2]};
            q[e1] += a / (double)(SPANS * SAMPLES);
            q[e2] += b / (double)(SPANS * SAMPLES);
            guide_point(Q + 3 * ((size_t)a * nt + b), shape, q);
        }
    for (int i = 0; i < n; i++)
        for (int b = 0; b < nt; b++)
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                for (int j = 0; j < m; j++)
                    if (i == 0 || i == n - 1 || j == 0 || j == m - 1)
                        sum += P[3 * ((size_t)i * m + j) + c] * B[b * m + j];
                T[3 * ((size_t)i * nt + b) + c] = sum;
            }
    for (int a = 0; a < ns; a++)
        for (int b = 0; b < nt; b++)
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                for (int i = 0; i < n; i++)
                    sum += A[a * n + i] * T[3 * ((size_t)i * nt + b) + c];
                Q[3 * ((size_t)a * nt + b) + c] -= sum;
            }
    /* U = A_I^T Q (ni x nt x 3), solved by MA; T = U B_I (ni x mi x 3); T^T solved by MB. */
    for (int i = 0; i < ni; i++)
        for (int b = 0; b < nt * 3; b++) {
            double sum = 0;
            for (int a = 0; a < ns; a++)
                sum += A[a * n + 1 + i] * Q[(size_t)a * nt * 3 + b];
            U[(size_t)i * nt * 3 + b] = sum;
        }
    cholesky_solve(MA, ni, U, nt * 3);
    for (int j = 0; j < mi; j++)
        for (int i = 0; i < ni; i++)
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                for (int b = 0; b < nt; b++)
                    sum += U[3 * ((size_t)i * nt + b) + c] * B[b * m + 1 + j];
                T[3 * ((size_t)j * ni + i) + c] = sum;
            }
    cholesky_solve(MB, mi, T, ni * 3);
    for (int i = 0; i < ni; i++)
        for (int j = 0; j < mi; j++)
            memcpy(P + 3 * ((size_t)(i + 1) * m + j + 1), T + 3 * ((size_t)j * ni + i),
                   sizeof *P * 3);

    if ((st = cb_nurbs_surface_make(s, DEG, DEG, ku, n + DEG + 1, kv, m + DEG + 1, P, NULL, n, m,
                                    err)) ||
        (st = cut_at_integers(s, CB_DIR_U, NULL, nu, err)) ||
        (st = cut_at_integers(s, CB_DIR_V, NULL, nv, err)))
        goto done;
    int fu = CUT * nu + 1, fv = CUT * nv + 1;
    for (int i = 0; i < fu; i++)
        for (int j = 0; j < fv; j++) {
            const double *w = cb_nurbs_surface_cw(s, i, j);
            for (int c = 0; c < 3; c++)
                sd->F[3 * ((size_t)i * fv + j) + c] = w[c] / w[3];
        }
    for (int i = 0; i < fu; i++) {
        memcpy(sd->F + 3 * ((size_t)i * fv), row[0]->fine + 3 * i, sizeof *P * 3);
        memcpy(sd->F + 3 * ((size_t)i * fv + fv - 1), row[1]->fine + 3 * i, sizeof *P * 3);
    }
    for (int j = 0; j < fv; j++) {
        memcpy(sd->F + 3 * j, col[0]->fine + 3 * j, sizeof *P * 3);
        memcpy(sd->F + 3 * ((size_t)(fu - 1) * fv + j), col[1]->fine + 3 * j, sizeof *P * 3);
    }
done:
    cb_nurbs_surface_clear(s);
    free(ku);
    free(kv);
    free(A);
    free(B);
    free(MA);
    free(MB);
    free(P);
    free(Q);
    free(T);
    free(U);
    return st;
}

/* ---------------------------------------------------------------- topology ----------------- */

static const double FACE_KNOTS[FACE_CTRL + DEG + 1] = {0, 0, 0, 0, 1 / 3.0, 2 / 3.0, 1, 1, 1, 1};

/* Lattice point index of box point q (integer coordinates). */
static int lattice_index(const int q[3])
{
    return ((q[0] + BOX_HALF[0]) * (2 * BOX_HALF[1] + 1) + q[1] + BOX_HALF[1]) *
               (2 * BOX_HALF[2] + 1) +
           q[2] + BOX_HALF[2];
}

typedef struct {
    cb_topo_body *b;
    int vertex_of[LATTICE];
    int edge_of[LATTICE * 3]; /* by low end and axis */
    double tol;
} builder;

/* The vertex at lattice point q, created at p on first use; -1 when out of memory. */
static int vertex_at(builder *bd, const int q[3], const double p[3])
{
    int *v = &bd->vertex_of[lattice_index(q)];
    if (*v < 0 && (*v = cb_topo_body_add_vertex(bd->b)) >= 0)
        memcpy(bd->b->vertices[*v].p, p, sizeof(double) * 3);
    return *v;
}

/* The edge from lattice point lo one unit along axis; on first use it is created with the
 * control row `row` (6 points, from lo) as its curve. -1 when out of memory. */
static int edge_at(builder *bd, const int lo[3], int axis, const double *row)
{
    int *e = &bd->edge_of[lattice_index(lo) * 3 + axis];
    if (*e >= 0)
        return *e;
    int hi[3] = {lo[0], lo[1], lo[2]};
    hi[axis]++;
    int v0 = vertex_at(bd, lo, row), v1 = vertex_at(bd, hi, row + 3 * (FACE_CTRL - 1));
    int c = cb_topo_body_add_curve(bd->b), id = cb_topo_body_add_edge(bd->b);
    if (v0 < 0 || v1 < 0 || c < 0 || id < 0)
        return -1;
    cb_topo_curve *cv = &bd->b->curves[c];
    cv->kind = CB_CURVE_NURBS;
    if (cb_nurbs_curve_make(cv->nurbs, DEG, FACE_KNOTS, FACE_CTRL + DEG + 1, row, NULL, FACE_CTRL,
                            NULL))
        return -1;
    cb_topo_edge *ed = &bd->b->edges[id];
    ed->curve = c;
    ed->t0 = 0;
    ed->t1 = 1;
    ed->same_sense = 1;
    ed->v[0] = v0;
    ed->v[1] = v1;
    ed->tol = bd->tol;
    return *e = id;
}

/* Adds the face of side k at piece (a, b): its surface, one loop of four coedges running
 * (0,0) -> (1,0) -> (1,1) -> (0,1) in its parameters, counterclockwise about the outward
 * normal. */
static cb_status add_face(builder *bd, const box_side *sd, int k, int a, int b, cb_error *err)
{
    int e1 = SIDES[k].e1, e2 = SIDES[k].e2, fv = CUT * sd->nv + 1;
    double pts[FACE_CTRL * FACE_CTRL * 3], rows[4][FACE_CTRL * 3];
    for (int i = 0; i < FACE_CTRL; i++)
        for (int j = 0; j < FACE_CTRL; j++)
            memcpy(pts + 3 * (i * FACE_CTRL + j),
                   sd->F + 3 * ((size_t)(CUT * a + i) * fv + CUT * b + j), sizeof(double) * 3);
    for (int i = 0; i < FACE_CTRL; i++) {
        memcpy(rows[0] + 3 * i, pts + 3 * (i * FACE_CTRL), sizeof(double) * 3);
        memcpy(rows[1] + 3 * i, pts + 3 * ((FACE_CTRL - 1) * FACE_CTRL + i), sizeof(double) * 3);
        memcpy(rows[2] + 3 * i, pts + 3 * (i * FACE_CTRL + FACE_CTRL - 1), sizeof(double) * 3);
        memcpy(rows[3] + 3 * i, pts + 3 * i, sizeof(double) * 3);
    }
    /* Low lattice ends, axes and senses of the four sides of the loop. */
    int c00[3], lo[4][3];
    for (int c = 0; c < 3; c++)
        c00[c] = (int)sd->origin[c];
    c00[e1] += a;
    c00[e2] += b;
    memcpy(lo[0], c00, sizeof c00);
    memcpy(lo[1], c00, sizeof c00);
    lo[1][e1]++;
    memcpy(lo[2], c00, sizeof c00);
    lo[2][e2]++;
    memcpy(lo[3], c00, sizeof c00);
    const int axis[4] = {e1, e2, e1, e2}, sense[4] = {1, 1, 0, 0};

    int sf = cb_topo_body_add_surface(bd->b), f = cb_topo_body_add_face(bd->b);
    int l = cb_topo_body_add_loop(bd->b);
    if (sf < 0 || f < 0 || l < 0)
        return cb_error_set(err, CB_ERR_NOMEM, "hummingbird: out of memory");
    cb_topo_surface *s = &bd->b->surfaces[sf];
    s->kind = CB_SURFACE_NURBS;
    cb_status st = cb_nurbs_surface_make(s->nurbs, DEG, DEG, FACE_KNOTS, FACE_CTRL + DEG + 1,
                                         FACE_KNOTS, FACE_CTRL + DEG + 1, pts, NULL, FACE_CTRL,
                                         FACE_CTRL, err);
    if (st)
        return st;
    bd->b->faces[f] = (cb_topo_face){.surface = sf, .same_sense = 1, .first = l, .count = 1};
    bd->b->loops[l] = (cb_topo_loop){.first = bd->b->n_coedges, .count = 4, .outer = 1, .face = f};
    for (int side = 0; side < 4; side++) {
        int e = edge_at(bd, lo[side], axis[side], rows[side]);
        int c = cb_topo_body_add_coedge(bd->b);
        if (e < 0 || c < 0)
            return cb_error_set(err, CB_ERR_NOMEM, "hummingbird: out of memory");
        bd->b->coedges[c] = (cb_topo_coedge){.edge = e, .sense = sense[side], .pcurve = -1,
                                             .loop = l};
    }
    return CB_OK;
}

/* ---------------------------------------------------------------- pose --------------------- */

/* The scale and rigid motion of p; CB_ERR_INVALID names the first bad parameter. */
static cb_status pose_make(cb_xform *x, const cb_hummingbird_params *p, cb_error *err)
{
    if (!(p->scale > 0) || !isfinite(p->scale))
        return cb_error_set(err, CB_ERR_INVALID, "hummingbird: scale %g is not positive",
                            p->scale);
    if (!(p->wing_angle_deg >= -30 && p->wing_angle_deg <= 50))
        return cb_error_set(err, CB_ERR_INVALID,
                            "hummingbird: wing angle %g is outside [-30, 50] degrees",
                            p->wing_angle_deg);
    for (int k = 0; k < 3; k++)
        if (!isfinite(p->axis[k]) || !isfinite(p->translate[k]))
            return cb_error_set(err, CB_ERR_INVALID,
                                "hummingbird: rotation axis or translation is not finite");
    if (!isfinite(p->angle_deg))
        return cb_error_set(err, CB_ERR_INVALID, "hummingbird: rotation angle is not finite");
    cb_xform_identity(x);
    if (p->angle_deg != 0) {
        if (!(cb_vec3_norm(p->axis) > 0))
            return cb_error_set(err, CB_ERR_INVALID, "hummingbird: rotation axis is zero");
        const double o[3] = {0, 0, 0};
        cb_xform_rotation(x, o, p->axis, p->angle_deg * PI / 180);
    }
    memcpy(x->t, p->translate, sizeof x->t);
    return CB_OK;
}

void cb_hummingbird_params_default(cb_hummingbird_params *p)
{
    memset(p, 0, sizeof *p);
    p->scale = 1;
    p->wing_angle_deg = 20;
    p->axis[2] = 1;
}

/* ---------------------------------------------------------------- generator ---------------- */

cb_status cb_model_hummingbird(cb_topo_body **out, const cb_hummingbird_params *p, cb_error *err)
{
    *out = NULL;
    cb_xform pose;
    cb_status st = pose_make(&pose, p, err);
    if (st)
        return st;
    bird_shape shape;
    shape_make(&shape, p->wing_angle_deg * PI / 180);

    box_edge edges[12];
    box_side sides[6];
    memset(edges, 0, sizeof edges);
    memset(sides, 0, sizeof sides);
    for (int axis = 0; axis < 3 && !st; axis++)
        for (int k = 0; k < 4 && !st; k++) {
            box_edge *e = &edges[axis * 4 + k];
            int b = (axis + 1) % 3, c = (axis + 2) % 3;
            e->axis = axis;
            e->m = 2 * BOX_HALF[axis];
            e->lo[axis] = -BOX_HALF[axis];
            e->lo[b] = (k & 2) ? BOX_HALF[b] : -BOX_HALF[b];
            e->lo[c] = (k & 1) ? BOX_HALF[c] : -BOX_HALF[c];
            st = edge_fit(e, &shape, err);
        }
    for (int k = 0; k < 6 && !st; k++) {
        box_side *sd = &sides[k];
        for (int c = 0; c < 3; c++)
            sd->origin[c] = -BOX_HALF[c];
        sd->origin[SIDES[k].normal] = SIDES[k].sign * BOX_HALF[SIDES[k].normal];
        sd->nu = 2 * BOX_HALF[SIDES[k].e1];
        sd->nv = 2 * BOX_HALF[SIDES[k].e2];
        if (!(st = side_fit(sd, k, edges, &shape, err))) {
            size_t np = (size_t)(CUT * sd->nu + 1) * (CUT * sd->nv + 1);
            for (size_t i = 0; i < np; i++) {
                double q[3];
                for (int c = 0; c < 3; c++)
                    q[c] = p->scale * sd->F[3 * i + c];
                cb_xform_apply_point(sd->F + 3 * i, &pose, q);
            }
        }
    }

    builder *bd = NULL;
    if (!st && (!(bd = malloc(sizeof *bd)) || !(bd->b = cb_topo_body_new())))
        st = cb_error_set(err, CB_ERR_NOMEM, "hummingbird: out of memory");
    if (!st) {
        memset(bd->vertex_of, -1, sizeof bd->vertex_of);
        memset(bd->edge_of, -1, sizeof bd->edge_of);
        bd->tol = REL_TOL * p->scale;
        bd->b->tol = bd->tol;
        int sh = cb_topo_body_add_shell(bd->b), so = cb_topo_body_add_solid(bd->b);
        if (sh < 0 || so < 0)
            st = cb_error_set(err, CB_ERR_NOMEM, "hummingbird: out of memory");
        for (int k = 0; k < 6 && !st; k++)
            for (int a = 0; a < sides[k].nu && !st; a++)
                for (int b = 0; b < sides[k].nv && !st; b++)
                    st = add_face(bd, &sides[k], k, a, b, err);
        if (!st) {
            bd->b->shells[0] = (cb_topo_shell){.first = 0, .count = bd->b->n_faces, .closed = 1,
                                               .solid = 0};
            bd->b->solids[0] = (cb_topo_solid){.first = 0, .count = 1};
            st = cb_topo_body_index(bd->b, err);
        }
    }
    double margin = 0;
    if (!st && !(st = cb_model_hummingbird_margin(&margin, bd->b, p, FOLD_GRID, err)) &&
        margin < MIN_MARGIN)
        st = cb_error_set(err, CB_ERR_NUMERIC,
                          "hummingbird: the fitted surface may fold (no-fold margin %.3g < %g); "
                          "try a wing angle nearer 20 degrees",
                          margin, MIN_MARGIN);
    if (!st) {
        *out = bd->b;
        bd->b = NULL;
    }
    if (bd)
        cb_topo_body_free(bd->b);
    free(bd);
    for (int k = 0; k < 12; k++) {
        free(edges[k].coarse);
        free(edges[k].fine);
    }
    for (int k = 0; k < 6; k++)
        free(sides[k].F);
    return st;
}

cb_status cb_model_hummingbird_margin(double *margin, const cb_topo_body *b,
                                      const cb_hummingbird_params *p, int n, cb_error *err)
{
    cb_xform pose;
    cb_status st = pose_make(&pose, p, err);
    if (st)
        return st;
    if (n < 2)
        return cb_error_set(err, CB_ERR_INVALID, "hummingbird margin: grid %d < 2", n);
    if (b->n_faces != N_FACES)
        return cb_error_set(err, CB_ERR_INVALID, "hummingbird margin: %d faces, %d expected",
                            b->n_faces, N_FACES);
    double worst = 1;
    for (int f = 0; f < b->n_faces; f++) {
        const cb_topo_surface *s = &b->surfaces[b->faces[f].surface];
        if (s->kind != CB_SURFACE_NURBS)
            return cb_error_set(err, CB_ERR_INVALID, "hummingbird margin: face %d: not a B-spline",
                                f);
        double box[4];
        cb_nurbs_surface_domain(s->nurbs, box);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double d[6][3], x[3], nrm[3], q[3], nq[3];
                cb_nurbs_surface_eval_derivs(d, s->nurbs, box[0] + (box[1] - box[0]) * i / (n - 1),
                                             box[2] + (box[3] - box[2]) * j / (n - 1));
                cb_vec3_cross(nrm, d[1], d[2]);
                if (!b->faces[f].same_sense)
                    for (int c = 0; c < 3; c++)
                        nrm[c] = -nrm[c];
                /* Undo the pose: x = R^T (p - t) / scale, the normal by R^T. */
                for (int c = 0; c < 3; c++) {
                    x[c] = 0;
                    q[c] = 0;
                    for (int r = 0; r < 3; r++) {
                        x[c] += pose.r[r][c] * (d[0][r] - pose.t[r]);
                        q[c] += pose.r[r][c] * nrm[r];
                    }
                    x[c] /= p->scale;
                }
                /* Undo the shear; the normal pulls back by DPhi^T (det DPhi = 1). */
                double y = x[1];
                x[0] += SWEEP * y * y;
                x[2] -= BEND * y * y;
                nq[0] = q[0];
                nq[1] = q[1] - 2 * SWEEP * y * q[0] + 2 * BEND * y * q[2];
                nq[2] = q[2];
                double den = cb_vec3_norm(x) * cb_vec3_norm(nq);
                double cosine = den > 0 ? cb_vec3_dot(x, nq) / den : -1;
                worst = fmin(worst, cosine);
            }
    }
    *margin = worst;
    return CB_OK;
}
