/* tess_internal.h — the pieces of tessellation shared by brep/tess*.c: planar predicates and
 * the constrained Delaunay triangulation of a face's parameter domain. Not a public header. */
#ifndef CB_TESS_INTERNAL_H
#define CB_TESS_INTERNAL_H

#include "brep/status.h"
#include "brep/tess.h"

/* Sign of the orientation of (a, b, c): > 0 counter-clockwise, < 0 clockwise, 0 collinear.
 * Exact for any finite input: a floating-point filter, then an exact expansion sum of the
 * determinant (Shewchuk's arithmetic) when the filter cannot decide. */
int cb_tess_orient2d(const double a[2], const double b[2], const double c[2]);

/* > 0 when d lies inside the circle through the counter-clockwise a, b, c, < 0 outside, and
 * 0 when floating point cannot tell (Shewchuk's error bound): a nonzero sign is certain, so
 * Lawson flips made only on > 0 terminate, and near-cocircular points (grids, arcs) never
 * flip back and forth. */
double cb_tess_incircle(const double a[2], const double b[2], const double c[2],
                        const double d[2]);

/* qsort order of triples of ints, lexicographic. */
int cb_tess_cmp_int3(const void *a, const void *b);

/* ---------------------------------------------------------------- triangulation ------------ */

/* Edge i of a triangle is the one opposite v[i]: (v[i + 1], v[i + 2]) mod 3; n[i] is the
 * triangle across it (-1 on the hull of the enclosing triangle) and c[i] marks it
 * constrained. Triangles are counter-clockwise. */
typedef struct {
    int v[3];
    int n[3];
    unsigned char c[3];
    unsigned char in; /* inside the domain, after cb_tess_cdt_classify */
    unsigned char settled; /* for the refiner: tested and kept; cleared whenever the corners
                              or the constraints change */
} cb_tess_tri;

/* Points 0..2 are the corners of an enclosing triangle; the caller's points follow. */
typedef struct {
    double *p; /* 2 per point */
    int np, cap_p;
    int *vt; /* one triangle holding each point */
    cb_tess_tri *t;
    int nt, cap_t;
    int hint; /* where the next point location starts */
    int *stack;
    int cap_stack;
} cb_tess_cdt;

/* An enclosing triangle of the box {x0, x1, y0, y1} (x0 < x1, y0 < y1) with a wide margin. */
cb_status cb_tess_cdt_init(cb_tess_cdt *d, const double box[4], cb_error *err);
void cb_tess_cdt_clear(cb_tess_cdt *d);

/* Inserts (x, y) and restores the Delaunay property around it. *index receives the point's
 * index, or that of an existing point at exactly (x, y). With avoid_constrained set, a point
 * exactly on a constrained edge is not inserted (*index = -1, CB_OK). CB_ERR_INVALID for a
 * point outside the enclosing triangle, CB_ERR_NOMEM. */
cb_status cb_tess_cdt_insert(cb_tess_cdt *d, double x, double y, int avoid_constrained,
                             int *index, cb_error *err);

/* Makes the segment between points a and b an edge of the triangulation and marks it
 * constrained (Sloan's flips of the edges it crosses). A point lying exactly on the segment
 * splits it in two. CB_ERR_NUMERIC when recovery stalls, CB_ERR_NOMEM. */
cb_status cb_tess_cdt_constrain(cb_tess_cdt *d, int a, int b, cb_error *err);

/* Flips the edge opposite v[i] of triangle t, when it is unconstrained, its neighbour lies on
 * the same side of the domain boundary and the quad is strictly convex (both new triangles
 * counter-clockwise): t = (p, a, b) and its neighbour (q, b, a) become t = (p, a, q) and
 * (p, q, b). Returns 1 when flipped, else 0 and nothing changes. The triangulation stays valid
 * but need not stay Delaunay. */
int cb_tess_cdt_flip(cb_tess_cdt *d, int t, int i);

/* Flips every unconstrained edge that is not locally Delaunay until none is left (or a pass
 * limit is reached: the result is a valid triangulation either way). */
void cb_tess_cdt_delaunay(cb_tess_cdt *d);

/* Sets t[k].in: a triangle is inside when a path from the enclosing triangle's corners to it
 * crosses an odd number of constrained edges (nested loops alternate, whatever their
 * direction). CB_ERR_NOMEM. */
cb_status cb_tess_cdt_classify(cb_tess_cdt *d, cb_error *err);

/* ---------------------------------------------------------------- contact zones ------------ */

/* A place where face `face`'s mesh must follow its surface more closely than the body's
 * chordal tolerance: its triangles, and the pieces of its edges, within r of c are refined
 * until their chordal error is at most chord_tol. cb_tess_body sets them where the meshes of
 * two faces cross although the faces only touch (a void touching its wall): there a chord
 * of one surface, within the tolerance of it, can reach past the other. */
typedef struct {
    double c[3], r, chord_tol;
    int face;
} cb_tess_zone;

/* cb_tess_edges_sample with zones[0 .. n_zones) (NULL, 0: none): an edge is refined in the
 * zones of the faces that use it. */
cb_status cb_tess_edges_sample_zoned(cb_tess_edges *es, const cb_topo_body *b,
                                     const cb_tess_opts *o, const cb_tess_zone *zones,
                                     int n_zones, cb_context *ctx, cb_error *err);

/* What cb_tess_body asks of a face beyond the options: its zones among zones[0 .. n_zones),
 * and segments no face may keep as a triangle side, splits[2k], splits[2k + 1] (shared
 * sample ids, either order; a face whose boundary joins them keeps that side). */
typedef struct {
    const cb_tess_zone *zones;
    int n_zones;
    const int *splits;
    int n_splits;
} cb_tess_hints;

/* cb_tess_face with hints h (NULL: none). */
cb_status cb_tess_face_hinted(cb_tess_face_mesh *fm, const cb_topo_body *b, int face,
                              const cb_tess_edges *es, const cb_tess_opts *o,
                              const cb_tess_hints *h, cb_context *ctx, cb_error *err);

#endif
