/* The arrangement of polylines in a face's (u,v) domain (boolean/arrange.h): a square cut by
 * chords, curves entering and leaving, loops inside (hole and island) and touching the
 * boundary, cuts ending on a vertex, near (snapped) and off (dangling) the boundary, a cut
 * along a side (one piece, two sources), crossing cuts, random chords against the count
 * 1 + chords + crossings, the area sum and Euler's formula, chords through shared points,
 * a cut wandering within 2 snap_tol of a side (down to points 0.3 snap_tol apart), a timed
 * 20k-segment input, an anisotropic domain, bad input. Every arrangement is checked for
 * consistency: cycles closed and oriented, areas against the test's own shoelace, inner points
 * inside their region and outside every other (winding numbers computed here), positions mapping
 * back onto the sources. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "boolean/arrange.h"
#include "check.h"

static const double PI = 3.14159265358979323846;

static const double UNIT[2] = {1, 1};

/* The closed square [x0, x1] x [y0, y1], counterclockwise from (x0, y0): 5 points. */
static void square(double *uv, double x0, double y0, double x1, double y1)
{
    double p[10] = {x0, y0, x1, y0, x1, y1, x0, y1, x0, y0};
    memcpy(uv, p, sizeof p);
}

/* n + 1 points of the closed circle, the first at angle a0. */
static void circle(double *uv, double cx, double cy, double r, int n, double a0)
{
    for (int k = 0; k <= n; k++) {
        double a = a0 + 2 * PI * (k % n) / n;
        uv[2 * k] = cx + r * cos(a);
        uv[2 * k + 1] = cy + r * sin(a);
    }
}

/* Area of the regular n-gon of circumradius r. */
static double ngon_area(int n, double r) { return 0.5 * n * r * r * sin(2 * PI / n); }

/* ---------------------------------------------------------------- checks ------------------- */

/* Contribution of the directed segment xy to the winding number around p. */
static int crossing(const double *x, const double *y, const double *p)
{
    double o = (y[0] - x[0]) * (p[1] - x[1]) - (y[1] - x[1]) * (p[0] - x[0]);
    if (x[1] <= p[1])
        return y[1] > p[1] && o > 0;
    return -(y[1] <= p[1] && o < 0);
}

/* Winding number around p of region r's cycles, walked the way the region lists them. */
static int region_winding(const cb_arr *a, int r, const double *p)
{
    const cb_arr_region *R = &a->region[r];
    int wn = 0;
    for (int k = 0; k < R->cycle[R->n_cycles]; k++) {
        const cb_arr_piece *pc = &a->piece[R->use[k].piece];
        for (int i = 0; i + 1 < pc->n; i++) {
            const double *x = pc->uv + 2 * i, *y = x + 2;
            wn += R->use[k].dir > 0 ? crossing(x, y, p) : crossing(y, x, p);
        }
    }
    return wn;
}

/* Signed area of cycle c, the test's own shoelace. */
static double cycle_area_signed(const cb_arr *a, const cb_arr_region *R, int c)
{
    double s = 0;
    for (int k = R->cycle[c]; k < R->cycle[c + 1]; k++) {
        const cb_arr_piece *p = &a->piece[R->use[k].piece];
        double t = 0;
        for (int i = 0; i + 1 < p->n; i++)
            t += p->uv[2 * i] * p->uv[2 * i + 3] - p->uv[2 * i + 2] * p->uv[2 * i + 1];
        s += R->use[k].dir * t;
    }
    return 0.5 * s;
}

static double poly_dist(const cb_arr_polyline *in, double pos, const double *uv, const double *sc)
{
    int k = (int)floor(pos);
    double f = pos - k, q[2];
    if (k >= in->n - 1) {
        k = in->n - 2;
        f = 1;
    }
    for (int i = 0; i < 2; i++)
        q[i] = in->uv[2 * k + i] + f * (in->uv[2 * k + 2 + i] - in->uv[2 * k + i]);
    return hypot((q[0] - uv[0]) * sc[0], (q[1] - uv[1]) * sc[1]);
}

/* How far, in snap_tol, a piece's end may be from the point its position gives along a source:
 * the span of a vertex's merged points, plus one for a vertex found on a run afterwards. */
static double pos_slack = CB_ARR_CLUSTER_SPAN + 1;

/* Everything that must hold for any arrangement. */
static void check_arr(const cb_arr *a, const cb_arr_polyline *in, int n_in, const double *sc,
                      double tol, const char *what)
{
    double span = pos_slack * tol;
    for (int k = 0; k < a->n_pieces; k++) {
        const cb_arr_piece *p = &a->piece[k];
        const double *e0 = a->vertex_uv + 2 * p->v0, *e1 = a->vertex_uv + 2 * p->v1;
        CHECK(p->n >= 2 && p->n_src >= 1, "%s: piece %d: %d points, %d sources", what, k, p->n,
              p->n_src);
        CHECK(p->uv[0] == e0[0] && p->uv[1] == e0[1] && p->uv[2 * p->n - 2] == e1[0] &&
                  p->uv[2 * p->n - 1] == e1[1],
              "%s: piece %d does not end at its vertices", what, k);
        CHECK(p->pos0[0] <= p->pos1[0], "%s: piece %d runs against src[0]: %g -> %g", what, k,
              p->pos0[0], p->pos1[0]);
        for (int s = 0; s < p->n_src; s++) {
            CHECK(p->src[s] >= 0 && p->src[s] < n_in && (s == 0 || p->src[s] >= p->src[s - 1]),
                  "%s: piece %d source %d = %d", what, k, s, p->src[s]);
            if (p->src[s] < 0 || p->src[s] >= n_in)
                continue;
            const cb_arr_polyline *q = &in[p->src[s]];
            CHECK(p->src_id[s] == q->id, "%s: piece %d source id", what, k);
            double d0 = poly_dist(q, p->pos0[s], e0, sc), d1 = poly_dist(q, p->pos1[s], e1, sc);
            CHECK(d0 <= span && d1 <= span,
                  "%s: piece %d source %d (polyline %d) at %g, %g is %g, %g off its ends", what, k,
                  s, p->src[s], p->pos0[s], p->pos1[s], d0, d1);
        }
    }
    int *used = calloc((size_t)a->n_pieces * 2 + 1, sizeof *used);
    for (int r = 0; r < a->n_regions; r++) {
        const cb_arr_region *R = &a->region[r];
        double area = 0;
        for (int c = 0; c < R->n_cycles; c++) {
            int n = R->cycle[c + 1] - R->cycle[c];
            CHECK(n >= 1, "%s: region %d cycle %d is empty", what, r, c);
            for (int i = 0; i < n; i++) {
                cb_arr_use u = R->use[R->cycle[c] + i], v = R->use[R->cycle[c] + (i + 1) % n];
                const cb_arr_piece *pu = &a->piece[u.piece], *pv = &a->piece[v.piece];
                int end = u.dir > 0 ? pu->v1 : pu->v0, start = v.dir > 0 ? pv->v0 : pv->v1;
                CHECK(end == start, "%s: region %d cycle %d open after use %d", what, r, c, i);
                CHECK(!pu->dangling, "%s: region %d uses dangling piece %d", what, r, u.piece);
                used[2 * u.piece + (u.dir < 0)]++;
            }
            double ca = cycle_area_signed(a, R, c);
            CHECK(c == 0 ? ca > 0 : ca < 0, "%s: region %d cycle %d area %g", what, r, c, ca);
            area += ca;
        }
        CHECK(fabs(area - R->area) <= 1e-12 * (1 + fabs(area)),
              "%s: region %d area %.17g, shoelace %.17g", what, r, R->area, area);
        /* The inner point: inside this region, outside all others. */
        int wn = region_winding(a, r, R->inner);
        CHECK(wn == 1, "%s: region %d inner point (%g, %g) has winding %d", what, r, R->inner[0],
              R->inner[1], wn);
        for (int s = 0; s < a->n_regions; s++)
            if (s != r) {
                int ws = region_winding(a, s, R->inner);
                CHECK(ws == 0, "%s: region %d inner point in region %d (winding %d)", what, r, s,
                      ws);
            }
    }
    for (int k = 0; k < 2 * a->n_pieces; k++)
        CHECK(used[k] <= 1, "%s: piece %d used %d times one way", what, k / 2, used[k]);
    for (int k = 0; k < a->n_pieces; k++)
        CHECK(a->piece[k].dangling || used[2 * k] + used[2 * k + 1] >= 1,
              "%s: piece %d is in no region and not dangling", what, k);
    free(used);
}

static int vfind(int *parent, int x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

/* V - E + F = 1 + C over the pieces that are not dangling, F counting the unbounded face. */
static void check_euler(const cb_arr *a, const char *what)
{
    int *parent = malloc((size_t)a->n_vertices * sizeof *parent + 1);
    int *seen = calloc((size_t)a->n_vertices + 1, sizeof *seen);
    for (int v = 0; v < a->n_vertices; v++)
        parent[v] = v;
    int V = 0, E = 0, C = 0;
    for (int k = 0; k < a->n_pieces; k++) {
        const cb_arr_piece *p = &a->piece[k];
        if (p->dangling)
            continue;
        E++;
        V += !seen[p->v0]++;
        V += !seen[p->v1]++;
        parent[vfind(parent, p->v0)] = vfind(parent, p->v1);
    }
    for (int v = 0; v < a->n_vertices; v++)
        C += seen[v] && vfind(parent, v) == v;
    CHECK(V - E + a->n_regions + 1 == 1 + C, "%s: V %d - E %d + F %d != 1 + C %d", what, V, E,
          a->n_regions + 1, C);
    free(parent);
    free(seen);
}

static double area_sum(const cb_arr *a)
{
    double s = 0;
    for (int r = 0; r < a->n_regions; r++)
        s += a->region[r].area;
    return s;
}

static int count_dangling(const cb_arr *a)
{
    int n = 0;
    for (int k = 0; k < a->n_pieces; k++)
        n += a->piece[k].dangling;
    return n;
}

/* Builds and checks; CHECKs the status. */
static cb_status build(cb_arr *a, const cb_arr_polyline *in, int n, const double *sc, double tol,
                       const char *what)
{
    cb_error err;
    cb_status st = cb_arr_build(a, in, n, sc, tol, &err);
    CHECK(st == CB_OK, "%s: %s", what, err.msg);
    if (st == CB_OK) {
        check_arr(a, in, n, sc, tol, what);
        check_euler(a, what);
    }
    return st;
}

/* The region whose inner point is in the box, or -1. */
static int region_at(const cb_arr *a, double x0, double y0, double x1, double y1)
{
    for (int r = 0; r < a->n_regions; r++) {
        const double *p = a->region[r].inner;
        if (p[0] > x0 && p[0] < x1 && p[1] > y0 && p[1] < y1)
            return r;
    }
    return -1;
}

/* ---------------------------------------------------------------- cases -------------------- */

static void test_chord(void)
{
    double sq[10], ch[4] = {0.25, 0, 0.75, 1};
    square(sq, 0, 0, 1, 1);
    cb_arr_polyline in[2] = {{5, sq, 10}, {2, ch, 11}};
    cb_arr a;
    cb_arr_init(&a);
    build(&a, in, 2, UNIT, 1e-9, "chord");
    CHECK(a.n_regions == 2, "chord: %d regions", a.n_regions);
    for (int r = 0; r < a.n_regions; r++)
        CHECK(a.region[r].area == 0.5 && a.region[r].n_cycles == 1,
              "chord: region %d area %.17g, %d cycles", r, a.region[r].area, a.region[r].n_cycles);
    /* The square's closing point is a vertex too: positions along it restart there. */
    CHECK(a.n_pieces == 4 && a.n_vertices == 3 && count_dangling(&a) == 0,
          "chord: %d pieces, %d vertices, %d dangling", a.n_pieces, a.n_vertices,
          count_dangling(&a));
    for (int k = 0; k < a.n_pieces; k++)
        if (a.piece[k].src[0] == 1)
            CHECK(a.piece[k].n_src == 1 && a.piece[k].pos0[0] == 0 && a.piece[k].pos1[0] == 1 &&
                      a.piece[k].src_id[0] == 11,
                  "chord: the chord's piece runs %g -> %g", a.piece[k].pos0[0], a.piece[k].pos1[0]);
    /* The split points of the square are exact: a quarter into side 0, three quarters into
     * side 2 (from (1,1) to (0,1)). */
    int found = 0;
    for (int k = 0; k < a.n_pieces; k++)
        if (a.piece[k].src[0] == 0)
            found += (a.piece[k].pos0[0] == 0.25 && a.piece[k].pos1[0] == 2.25) ||
                     (a.piece[k].pos0[0] == 0 && a.piece[k].pos1[0] == 4) ||
                     (a.piece[k].pos0[0] == 2.25 && a.piece[k].pos1[0] == 4) ||
                     (a.piece[k].pos0[0] == 0 && a.piece[k].pos1[0] == 0.25);
    CHECK(found == 3, "chord: square pieces split at 0.25 and 2.25: %d of 3", found);
    cb_arr_clear(&a);
}

static void test_enter_leave(void)
{
    double sq[10], cv[6] = {-0.5, 0.5, 0.5, 0.5, 0.5, 1.5};
    square(sq, 0, 0, 1, 1);
    cb_arr_polyline in[2] = {{5, sq, 0}, {3, cv, 1}};
    cb_arr a;
    cb_arr_init(&a);
    build(&a, in, 2, UNIT, 1e-9, "enter-leave");
    CHECK(a.n_regions == 2 && count_dangling(&a) == 2, "enter-leave: %d regions, %d dangling",
          a.n_regions, count_dangling(&a));
    int c = region_at(&a, 0, 0.5, 0.5, 1);
    CHECK(c >= 0 && fabs(a.region[c].area - 0.25) < 1e-15, "enter-leave: corner region %d", c);
    CHECK(fabs(area_sum(&a) - 1) < 1e-15, "enter-leave: area sum %.17g", area_sum(&a));
    cb_arr_clear(&a);
}

static void test_loops_inside(void)
{
    double sq[10], c1[2 * 65], c2[2 * 65];
    square(sq, 0, 0, 1, 1);
    circle(c1, 0.5, 0.5, 0.3, 64, 0.1);
    circle(c2, 0.5, 0.5, 0.1, 48, 0.2);
    cb_arr_polyline in[3] = {{5, sq, 0}, {65, c1, 1}, {49, c2, 2}};
    cb_arr a;
    cb_arr_init(&a);
    build(&a, in, 2, UNIT, 1e-9, "disc");
    double A1 = ngon_area(64, 0.3), A2 = ngon_area(48, 0.1);
    CHECK(a.n_regions == 2, "disc: %d regions", a.n_regions);
    int outer = a.n_regions == 2 ? a.region[0].n_cycles == 1 : -1, disc = 1 - outer;
    CHECK(outer >= 0 && a.region[outer].n_cycles == 2 &&
              fabs(a.region[outer].area - (1 - A1)) < 1e-14,
          "disc: square with a hole: region %d", outer);
    CHECK(disc >= 0 && disc != outer && a.region[disc].n_cycles == 1 &&
              fabs(a.region[disc].area - A1) < 1e-14,
          "disc: island: region %d", disc);
    /* The hole cycle is the disc's boundary, clockwise. */
    if (outer >= 0 && a.region[outer].n_cycles == 2) {
        const cb_arr_region *R = &a.region[outer];
        CHECK(fabs(cycle_area_signed(&a, R, 1) + A1) < 1e-14, "disc: hole area %g",
              cycle_area_signed(&a, R, 1));
    }
    build(&a, in, 3, UNIT, 1e-9, "annulus");
    CHECK(a.n_regions == 3, "annulus: %d regions", a.n_regions);
    int ring = region_at(&a, 0.5 - 0.3, 0.5 - 0.3, 0.5 + 0.3, 0.5 + 0.3);
    int core = region_at(&a, 0.4, 0.4, 0.6, 0.6);
    CHECK(core >= 0 && fabs(a.region[core].area - A2) < 1e-14, "annulus: core %d", core);
    int ring_ok = 0;
    for (int r = 0; r < a.n_regions; r++)
        ring_ok += a.region[r].n_cycles == 2 && fabs(a.region[r].area - (A1 - A2)) < 1e-14;
    CHECK(ring_ok == 1 && ring >= 0, "annulus: one ring region, %d", ring_ok);
    CHECK(fabs(area_sum(&a) - 1) < 1e-14, "annulus: area sum %.17g", area_sum(&a));
    cb_arr_clear(&a);
}

static void test_end_on_vertex(void)
{
    double sq[10], ch[4] = {0, 0, 1, 0.5};
    square(sq, 0, 0, 1, 1);
    cb_arr_polyline in[2] = {{5, sq, 0}, {2, ch, 1}};
    cb_arr a;
    cb_arr_init(&a);
    build(&a, in, 2, UNIT, 1e-9, "on vertex");
    CHECK(a.n_regions == 2 && a.n_vertices == 2 && count_dangling(&a) == 0,
          "on vertex: %d regions, %d vertices, %d dangling", a.n_regions, a.n_vertices,
          count_dangling(&a));
    int corner = 0;
    for (int v = 0; v < a.n_vertices; v++)
        corner += a.vertex_uv[2 * v] == 0 && a.vertex_uv[2 * v + 1] == 0;
    CHECK(corner == 1, "on vertex: corner vertex found %d times", corner);
    int t = region_at(&a, 0.5, 0, 1, 0.5);
    CHECK(t >= 0 && a.region[t].area == 0.25, "on vertex: triangle region %d", t);
    cb_arr_clear(&a);
}

static void test_snap_and_dangle(void)
{
    double tol = 1e-6, sq[10];
    square(sq, 0, 0, 1, 1);
    cb_arr a;
    cb_arr_init(&a);
    /* 0.3 tol: one end outside, one inside: both snapped onto the sides. */
    double c1[4] = {0.5, -0.3 * tol, 0.5, 1 - 0.3 * tol};
    cb_arr_polyline in[2] = {{5, sq, 0}, {2, c1, 1}};
    build(&a, in, 2, UNIT, tol, "snap");
    CHECK(a.n_regions == 2 && count_dangling(&a) == 0, "snap: %d regions, %d dangling", a.n_regions,
          count_dangling(&a));
    for (int r = 0; r < a.n_regions; r++)
        CHECK(a.region[r].area == 0.5, "snap: region %d area %.17g", r, a.region[r].area);
    int on = 0;
    for (int v = 0; v < a.n_vertices; v++)
        on += a.vertex_uv[2 * v] == 0.5 &&
              (a.vertex_uv[2 * v + 1] == 0 || a.vertex_uv[2 * v + 1] == 1);
    CHECK(on == 2 && a.n_vertices == 3, "snap: %d of 2 vertices on the sides (%d vertices)", on,
          a.n_vertices);
    /* 3 tol inside: the cut hangs in the square, dangling. */
    double c2[4] = {0.5, 3 * tol, 0.5, 1 - 3 * tol};
    in[1].uv = c2;
    build(&a, in, 2, UNIT, tol, "dangle inside");
    CHECK(a.n_regions == 1 && count_dangling(&a) == 1 && a.region[0].area == 1,
          "dangle inside: %d regions, %d dangling", a.n_regions, count_dangling(&a));
    /* 3 tol outside: crosses both sides, the stubs dangle. */
    double c3[4] = {0.5, -3 * tol, 0.5, 1 + 3 * tol};
    in[1].uv = c3;
    build(&a, in, 2, UNIT, tol, "dangle outside");
    CHECK(a.n_regions == 2 && count_dangling(&a) == 2, "dangle outside: %d regions, %d dangling",
          a.n_regions, count_dangling(&a));
    for (int r = 0; r < a.n_regions; r++)
        CHECK(fabs(a.region[r].area - 0.5) < 1e-15, "dangle outside: region %d area %.17g", r,
              a.region[r].area);
    /* A tree hanging off the boundary: a cut from the side with a branch, all dangling. */
    double c4[6] = {0.2, 0, 0.4, 0.5, 0.2, 0.7}, c5[4] = {0.4, 0.5, 0.7, 0.5};
    cb_arr_polyline in2[3] = {{5, sq, 0}, {3, c4, 1}, {2, c5, 2}};
    build(&a, in2, 3, UNIT, tol, "tree");
    CHECK(a.n_regions == 1 && count_dangling(&a) == 3 && a.region[0].area == 1,
          "tree: %d regions, %d dangling", a.n_regions, count_dangling(&a));
    cb_arr_clear(&a);
}

static void test_overlap(void)
{
    double tol = 1e-6, sq[10], c1[4] = {0.2, 0, 0.8, 0};
    square(sq, 0, 0, 1, 1);
    cb_arr_polyline in[2] = {{5, sq, 0}, {2, c1, 1}};
    cb_arr a;
    cb_arr_init(&a);
    build(&a, in, 2, UNIT, tol, "overlap");
    int shared = -1;
    for (int k = 0; k < a.n_pieces; k++)
        if (a.piece[k].n_src == 2)
            shared = shared < 0 ? k : -2;
    CHECK(shared >= 0, "overlap: one shared piece (%d)", shared);
    if (shared >= 0) {
        const cb_arr_piece *p = &a.piece[shared];
        CHECK(p->src[0] == 0 && p->src[1] == 1 && p->pos0[0] == 0.2 && p->pos1[0] == 0.8 &&
                  p->pos0[1] == 0 && p->pos1[1] == 1,
              "overlap: sources %d %d at %g-%g, %g-%g", p->src[0], p->src[1], p->pos0[0],
              p->pos1[0], p->pos0[1], p->pos1[1]);
    }
    CHECK(a.n_regions == 1 && a.region[0].area == 1 && count_dangling(&a) == 0,
          "overlap: %d regions, %d dangling", a.n_regions, count_dangling(&a));
    /* Resampled and off by up to 0.4 tol, then turning into the square up to the top side. */
    double c2[2 * 10];
    for (int k = 0; k < 9; k++) {
        c2[2 * k] = 0.1 + 0.1 * k;
        c2[2 * k + 1] = (k % 2 ? -0.4 : 0.4) * tol;
    }
    c2[18] = 0.9;
    c2[19] = 1;
    in[1] = (cb_arr_polyline){10, c2, 7};
    build(&a, in, 2, UNIT, tol, "overlap resampled");
    shared = -1;
    for (int k = 0; k < a.n_pieces; k++)
        if (a.piece[k].n_src == 2)
            shared = shared < 0 ? k : -2;
    CHECK(shared >= 0, "overlap resampled: one shared piece (%d)", shared);
    if (shared >= 0) {
        const cb_arr_piece *p = &a.piece[shared];
        /* 9 points of the cut and its 8 crossings of the side */
        CHECK(p->n == 17 && fabs(p->pos0[0] - 0.1) < 1e-15 && fabs(p->pos1[0] - 0.9) < 1e-15 &&
                  p->pos0[1] == 0 && p->pos1[1] == 8 && p->src_id[1] == 7,
              "overlap resampled: %d points, %g-%g, %g-%g", p->n, p->pos0[0], p->pos1[0],
              p->pos0[1], p->pos1[1]);
    }
    int strip = region_at(&a, 0.9, 0, 1, 1);
    CHECK(a.n_regions == 2 && strip >= 0 && fabs(a.region[strip].area - 0.1) < 1e-12,
          "overlap resampled: %d regions, strip %d", a.n_regions, strip);
    cb_arr_clear(&a);
}

static void test_crossing_cuts(void)
{
    double sq[10], c1[4] = {0.5, 0, 0.5, 1}, c2[4] = {0, 0.5, 1, 0.5};
    square(sq, 0, 0, 1, 1);
    cb_arr_polyline in[3] = {{5, sq, 0}, {2, c1, 1}, {2, c2, 2}};
    cb_arr a;
    cb_arr_init(&a);
    build(&a, in, 3, UNIT, 1e-9, "cross");
    CHECK(a.n_regions == 4, "cross: %d regions", a.n_regions);
    for (int r = 0; r < a.n_regions; r++)
        CHECK(a.region[r].area == 0.25, "cross: region %d area %.17g", r, a.region[r].area);
    int centre = 0;
    for (int v = 0; v < a.n_vertices; v++)
        centre += a.vertex_uv[2 * v] == 0.5 && a.vertex_uv[2 * v + 1] == 0.5;
    CHECK(centre == 1 && a.n_vertices == 6, "cross: centre vertex %d, %d vertices", centre,
          a.n_vertices);
    cb_arr_clear(&a);
}

static void test_touching_loop(void)
{
    double sq[10], c[2 * 65];
    square(sq, 0, 0, 1, 1);
    cb_arr a;
    cb_arr_init(&a);
    /* Touching at the loop's closing point, then at a point inside the loop's run. */
    for (int variant = 0; variant < 2; variant++) {
        circle(c, 0.5, 0.25, 0.25, 64, variant ? 0 : -PI / 2);
        cb_arr_polyline in[2] = {{5, sq, 0}, {65, c, 1}};
        const char *what = variant ? "touch (inside the run)" : "touch (closing point)";
        build(&a, in, 2, UNIT, 1e-9, what);
        double A = ngon_area(64, 0.25);
        int disc = region_at(&a, 0.3, 0.05, 0.7, 0.45), rest = region_at(&a, 0, 0.55, 1, 1);
        CHECK(a.n_regions == 2 && disc >= 0 && rest >= 0 && count_dangling(&a) == 0,
              "%s: %d regions", what, a.n_regions);
        if (disc >= 0 && rest >= 0) {
            CHECK(fabs(a.region[disc].area - A) < 1e-14 && a.region[disc].n_cycles == 1,
                  "%s: disc area %.17g", what, a.region[disc].area);
            /* Pinched at the touching point: one cycle, no hole. */
            CHECK(fabs(a.region[rest].area - (1 - A)) < 1e-14 && a.region[rest].n_cycles == 1,
                  "%s: rest area %.17g, %d cycles", what, a.region[rest].area,
                  a.region[rest].n_cycles);
        }
    }
    cb_arr_clear(&a);
}

/* A point on side s (0 bottom, 1 right, 2 top, 3 left) of the unit square. */
static void side_point(double *p, int s, double f)
{
    double q[4][2] = {{f, 0}, {1, f}, {1 - f, 1}, {0, 1 - f}};
    p[0] = q[s][0];
    p[1] = q[s][1];
}

static int seg_cross(const double *a, const double *b, const double *c, const double *d)
{
    double d1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    double d2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
    double d3 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
    double d4 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
    return d1 * d2 < 0 && d3 * d4 < 0;
}

static void test_random_chords(void)
{
    check_rng rng = {2024};
    cb_arr a;
    cb_arr_init(&a);
    for (int trial = 0; trial < 40; trial++) {
        int nc = check_rng_int(&rng, 1, 40);
        double sq[10], *ch = malloc((size_t)nc * 4 * sizeof *ch);
        cb_arr_polyline *in = malloc((size_t)(nc + 1) * sizeof *in);
        square(sq, 0, 0, 1, 1);
        in[0] = (cb_arr_polyline){5, sq, -1};
        for (int k = 0; k < nc; k++) {
            int s0 = check_rng_int(&rng, 0, 3), s1 = (s0 + check_rng_int(&rng, 1, 3)) % 4;
            side_point(ch + 4 * k, s0, check_rng_uniform(&rng, 0.01, 0.99));
            side_point(ch + 4 * k + 2, s1, check_rng_uniform(&rng, 0.01, 0.99));
            in[k + 1] = (cb_arr_polyline){2, ch + 4 * k, k};
        }
        int crossings = 0;
        for (int i = 0; i < nc; i++)
            for (int j = i + 1; j < nc; j++)
                crossings += seg_cross(ch + 4 * i, ch + 4 * i + 2, ch + 4 * j, ch + 4 * j + 2);
        char what[64];
        snprintf(what, sizeof what, "random chords trial %d (%d chords)", trial, nc);
        build(&a, in, nc + 1, UNIT, 1e-10, what);
        CHECK(fabs(area_sum(&a) - 1) <= 1e-12, "%s: area sum 1 %+.3g", what, area_sum(&a) - 1);
        CHECK(a.n_regions == 1 + nc + crossings, "%s: %d regions, expected 1 + %d + %d", what,
              a.n_regions, nc, crossings);
        for (int r = 0; r < a.n_regions; r++)
            CHECK(a.region[r].area > 0 && a.region[r].n_cycles == 1, "%s: region %d area %g", what,
                  r, a.region[r].area);
        free(ch);
        free(in);
    }
    cb_arr_clear(&a);
}

static double now(void);

/* Chords between the points k/8 of the sides: shared ends, chords along each other, three or
 * more through one point. The vertices all come from exact input points and crossings. */
static void test_concurrent(void)
{
    cb_arr a;
    cb_arr_init(&a);
    for (int trial = 0; trial < 300; trial++) {
        check_rng rng = {(uint64_t)trial};
        int nc = 1 + trial % 30;
        double sq[10], *ch = malloc((size_t)nc * 4 * sizeof *ch);
        cb_arr_polyline *in = malloc((size_t)(nc + 1) * sizeof *in);
        square(sq, 0, 0, 1, 1);
        in[0] = (cb_arr_polyline){5, sq, 0};
        for (int k = 0; k < nc; k++) {
            int s0 = check_rng_int(&rng, 0, 3), s1 = (s0 + check_rng_int(&rng, 1, 3)) % 4;
            side_point(ch + 4 * k, s0, check_rng_int(&rng, 1, 7) / 8.0);
            side_point(ch + 4 * k + 2, s1, check_rng_int(&rng, 1, 7) / 8.0);
            in[k + 1] = (cb_arr_polyline){2, ch + 4 * k, k + 1};
        }
        char what[64];
        snprintf(what, sizeof what, "concurrent trial %d (%d chords)", trial, nc);
        build(&a, in, nc + 1, UNIT, 1e-9, what);
        CHECK(fabs(area_sum(&a) - 1) <= 1e-12, "%s: area sum 1 %+.3g", what, area_sum(&a) - 1);
        for (int r = 0; r < a.n_regions; r++)
            CHECK(a.region[r].area > 0, "%s: region %d area %g", what, r, a.region[r].area);
        CHECK(count_dangling(&a) == 0, "%s: %d dangling", what, count_dangling(&a));
        free(ch);
        free(in);
    }
    cb_arr_clear(&a);
}

/* A straight cut sampled at irregular points, and again with other points: its segments are
 * collinear up to rounding, which the crossing tests must not take for crossings. */
static void test_collinear(void)
{
    check_rng rng = {5};
    double sq[10], c[2][2 * 40];
    square(sq, 0, 0, 1, 1);
    cb_arr a;
    cb_arr_init(&a);
    for (int trial = 0; trial < 20; trial++) {
        double y0 = check_rng_uniform(&rng, 0.1, 0.4), y1 = check_rng_uniform(&rng, 0.6, 0.9);
        for (int k = 0; k < 2; k++)
            for (int i = 0; i < 40; i++) {
                double t = i == 0 ? 0 : i == 39 ? 1 : (i + check_rng_uniform(&rng, -0.4, 0.4)) / 39;
                c[k][2 * i] = t;
                c[k][2 * i + 1] = y0 + t * (y1 - y0);
            }
        cb_arr_polyline in[3] = {{5, sq, 0}, {40, c[0], 1}, {40, c[1], 2}};
        char what[64];
        snprintf(what, sizeof what, "collinear trial %d", trial);
        build(&a, in, 3, UNIT, 1e-9, what);
        int shared = 0;
        for (int k = 0; k < a.n_pieces; k++)
            shared += a.piece[k].n_src == 2;
        CHECK(a.n_regions == 2 && count_dangling(&a) == 0 && shared == 1,
              "%s: %d regions, %d dangling, %d shared pieces", what, a.n_regions,
              count_dangling(&a), shared);
        /* No vertex but those of the two samplings (a false crossing adds two). */
        for (int k = 0; k < a.n_pieces; k++)
            CHECK(a.piece[k].n_src < 2 || a.piece[k].n <= 78, "%s: shared piece has %d points",
                  what, a.piece[k].n);
        double below[2] = {0.5, 0.05};
        int low = -1;
        for (int r = 0; r < a.n_regions; r++)
            if (region_winding(&a, r, below) == 1)
                low = r;
        CHECK(low >= 0 && fabs(a.region[low].area - 0.5 * (y0 + y1)) < 1e-12, "%s: lower region",
              what);
    }
    cb_arr_clear(&a);
}

/* A cut along the bottom side, wandering within 2 tol of it with points sp tol apart, then up to
 * the top: near-tangent curves, and below sp = 1 points closer than snap_tol over the whole run,
 * where merging stops at the span cap and the edges are split afterwards. */
static void test_along(void)
{
    double tol = 1e-4, sps[] = {0.3, 1, 3, 20}, sq[10];
    square(sq, 0, 0, 1, 1);
    cb_arr a;
    cb_arr_init(&a);
    pos_slack = 10;
    for (int trial = 0; trial < 8; trial++) {
        check_rng rng = {(uint64_t)trial};
        double sp = sps[trial % 4];
        int n = (int)(0.8 / (sp * tol)) + 2;
        double *c = malloc((size_t)(n + 1) * 2 * sizeof *c);
        for (int k = 0; k < n; k++) {
            c[2 * k] = 0.1 + 0.8 * k / (n - 1);
            c[2 * k + 1] = check_rng_uniform(&rng, -2, 2) * tol;
        }
        c[2 * n] = 0.9;
        c[2 * n + 1] = 1;
        cb_arr_polyline in[2] = {{5, sq, 0}, {n + 1, c, 1}};
        char what[96];
        snprintf(what, sizeof what, "along trial %d (%d points %g tol apart)", trial, n, sp);
        cb_error err;
        double t0 = now();
        cb_status st = cb_arr_build(&a, in, 2, UNIT, tol, &err);
        if (trial < 4)
            printf("%s: %.3f s\n", what, now() - t0);
        CHECK(st == CB_OK, "%s: %s", what, err.msg);
        check_arr(&a, in, 2, UNIT, tol, what);
        check_euler(&a, what);
        /* Snapping moves the boundary by up to about 2 tol along the cut. */
        int strip = region_at(&a, 0.9, 0, 1, 1);
        CHECK(fabs(area_sum(&a) - 1) < 0.8 * 4 * tol, "%s: area sum 1 %+.3g", what,
              area_sum(&a) - 1);
        CHECK(strip >= 0 && fabs(a.region[strip].area - 0.1) < 4 * tol, "%s: strip %d", what,
              strip);
        free(c);
    }
    pos_slack = CB_ARR_CLUSTER_SPAN + 1;
    cb_arr_clear(&a);
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* Square sampled with 4000 segments and 16 wavy curves of 1000 segments across it. */
static void test_big(void)
{
    enum { SIDE = 1000, CURVES = 16, CN = 1000 };
    double *sq = malloc((4 * SIDE + 1) * 2 * sizeof *sq);
    double *cv = malloc((size_t)CURVES * (CN + 1) * 2 * sizeof *cv);
    for (int k = 0; k <= 4 * SIDE; k++) {
        double f = (double)(k % SIDE) / SIDE;
        side_point(sq + 2 * k, (k / SIDE) % 4, f);
    }
    cb_arr_polyline in[1 + CURVES];
    in[0] = (cb_arr_polyline){4 * SIDE + 1, sq, 0};
    for (int c = 0; c < CURVES; c++) {
        double *p = cv + (size_t)c * (CN + 1) * 2;
        for (int k = 0; k <= CN; k++) {
            double u = -0.01 + 1.02 * k / CN;
            p[2 * k] = u;
            p[2 * k + 1] = 0.5 + 0.45 * sin(2 * PI * ((1 + c % 5) * u + 0.13 * c));
        }
        if (c % 2) /* half of them run in v: crossings between the families */
            for (int k = 0; k <= CN; k++) {
                double t = p[2 * k];
                p[2 * k] = p[2 * k + 1];
                p[2 * k + 1] = t;
            }
        in[1 + c] = (cb_arr_polyline){CN + 1, p, c + 1};
    }
    cb_arr a;
    cb_arr_init(&a);
    double t0 = now();
    cb_error err;
    cb_status st = cb_arr_build(&a, in, 1 + CURVES, UNIT, 1e-9, &err);
    double t1 = now();
    CHECK(st == CB_OK, "big: %s", err.msg);
    printf("big: %d segments: %d vertices, %d pieces (%d dangling), %d regions in %.3f s\n",
           4 * SIDE + CURVES * CN, a.n_vertices, a.n_pieces, count_dangling(&a), a.n_regions,
           t1 - t0);
    /* Curves crossing outside the square bound regions there too: sum those inside. */
    double inside = 0;
    for (int r = 0; r < a.n_regions; r++) {
        const double *p = a.region[r].inner;
        if (p[0] > 0 && p[0] < 1 && p[1] > 0 && p[1] < 1)
            inside += a.region[r].area;
    }
    CHECK(fabs(inside - 1) <= 1e-12, "big: area sum 1 %+.3g", inside - 1);
    CHECK(a.n_regions > 100, "big: %d regions", a.n_regions);
    check_arr(&a, in, 1 + CURVES, UNIT, 1e-9, "big");
    check_euler(&a, "big");
    cb_arr_clear(&a);
    free(sq);
    free(cv);
}

/* u over 1e-3, v over 1e3: snapping measures (du su, dv sv). */
static void test_anisotropic(void)
{
    double sc[2] = {1e3, 1e-3}, tol = 1e-6, sq[10];
    square(sq, 0, 0, 1e-3, 1e3);
    /* Off the bottom and top by 3e-4 in v: 0.3 tol scaled, snapped. */
    double c1[4] = {0.5e-3, -3e-4, 0.5e-3, 1e3 + 3e-4};
    /* Off the left side by 3e-9 in u: 3 tol scaled, dangling (ending on the first cut, it
     * would split the left half if snapped). */
    double c2[4] = {3e-9, 250, 0.5e-3, 250};
    cb_arr_polyline in[3] = {{5, sq, 0}, {2, c1, 1}, {2, c2, 2}};
    cb_arr a;
    cb_arr_init(&a);
    build(&a, in, 3, sc, tol, "anisotropic");
    CHECK(a.n_regions == 2 && count_dangling(&a) == 1, "anisotropic: %d regions, %d dangling",
          a.n_regions, count_dangling(&a));
    for (int r = 0; r < a.n_regions; r++) {
        CHECK(fabs(a.region[r].area - 0.5) < 1e-15, "anisotropic: region %d area %.17g", r,
              a.region[r].area);
        CHECK(a.region[r].clearance > 0.1, "anisotropic: region %d clearance %g", r,
              a.region[r].clearance);
    }
    cb_arr_clear(&a);
}

static void test_bad_input(void)
{
    double sq[10], one[2] = {0, 0}, nan3[8] = {0, 0, 1, 0, 1, 1, 0, 0};
    square(sq, 0, 0, 1, 1);
    nan3[7] = NAN;
    cb_arr a;
    cb_arr_init(&a);
    cb_arr_polyline ok[1] = {{5, sq, 0}};
    cb_error err;
    CHECK(cb_arr_build(&a, ok, 1, UNIT, 1e-9, &err) == CB_OK && a.n_regions == 1, "bad: setup");
    cb_arr_polyline in1[3] = {{5, sq, 0}, {5, sq, 1}, {1, one, 2}};
    cb_status st = cb_arr_build(&a, in1, 3, UNIT, 1e-9, &err);
    const char *m1[] = {"polyline 2", "1 points", NULL};
    CHECK(st == CB_ERR_INVALID && check_msg_has(err.msg, m1), "bad: 1 point: %d %s", st, err.msg);
    CHECK(a.n_regions == 0 && a.n_pieces == 0 && !a.piece && !a.region,
          "bad: out not cleared on failure");
    cb_arr_polyline in2[2] = {{5, sq, 0}, {4, nan3, 1}};
    st = cb_arr_build(&a, in2, 2, UNIT, 1e-9, &err);
    const char *m2[] = {"polyline 1", "point 3", NULL};
    CHECK(st == CB_ERR_INVALID && check_msg_has(err.msg, m2), "bad: NaN: %d %s", st, err.msg);
    cb_arr_polyline in3[2] = {{5, sq, 0}, {3, NULL, 1}};
    st = cb_arr_build(&a, in3, 2, UNIT, 1e-9, &err);
    const char *m3[] = {"polyline 1", NULL};
    CHECK(st == CB_ERR_INVALID && check_msg_has(err.msg, m3), "bad: NULL: %d %s", st, err.msg);
    double s0[2] = {0, 1}, sinf_[2] = {1, INFINITY};
    CHECK(cb_arr_build(&a, ok, 1, s0, 1e-9, &err) == CB_ERR_INVALID, "bad: scale 0");
    CHECK(cb_arr_build(&a, ok, 1, sinf_, 1e-9, &err) == CB_ERR_INVALID, "bad: scale inf");
    CHECK(cb_arr_build(&a, ok, 1, UNIT, 0, &err) == CB_ERR_INVALID, "bad: tol 0");
    CHECK(cb_arr_build(&a, ok, 1, UNIT, NAN, &err) == CB_ERR_INVALID, "bad: tol NaN");
    CHECK(cb_arr_build(&a, ok, -1, UNIT, 1e-9, NULL) == CB_ERR_INVALID, "bad: n -1");
    /* Overflow once scaled. */
    double big[2] = {1e300, 1e300};
    CHECK(cb_arr_build(&a, ok, 1, big, 1e-9, &err) == CB_OK, "bad: scale 1e300 on a unit square");
    double far[4] = {0, 0, 1e10, 0};
    cb_arr_polyline in4[1] = {{2, far, 0}};
    st = cb_arr_build(&a, in4, 1, big, 1e-9, &err);
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "polyline 0"), "bad: overflow: %d %s", st,
          err.msg);
    /* Nothing, or only open cuts: no regions, everything dangling. */
    CHECK(cb_arr_build(&a, NULL, 0, UNIT, 1e-9, &err) == CB_OK && a.n_regions == 0 &&
              a.n_pieces == 0,
          "empty input");
    double ch[4] = {0, 0, 1, 1};
    cb_arr_polyline in5[1] = {{2, ch, 0}};
    CHECK(cb_arr_build(&a, in5, 1, UNIT, 1e-9, &err) == CB_OK && a.n_regions == 0 &&
              a.n_pieces == 1 && a.piece[0].dangling,
          "open cut alone");
    cb_arr_clear(&a);
}

int main(void)
{
    test_chord();
    test_enter_leave();
    test_loops_inside();
    test_end_on_vertex();
    test_snap_and_dangle();
    test_overlap();
    test_crossing_cuts();
    test_touching_loop();
    test_random_chords();
    test_concurrent();
    test_collinear();
    test_along();
    test_big();
    test_anisotropic();
    test_bad_input();
    return check_report("test_bool_arrange");
}
