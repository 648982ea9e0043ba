/* arrange.h — the planar arrangement of polylines in a face's (u,v) parameter domain.
 *
 * The Boolean stage splits a trimmed face along the intersection curves that cross it. In the
 * face's parameter plane it samples the trimming loops and the curves (clipped to the face) as
 * polylines; cb_arr_build returns the bounded regions these make, each bounded by cycles of
 * pieces (maximal runs of polyline between vertices), with a point inside each region.
 *
 * Distances are measured in the scaled plane (u su, v sv), scale = (su, sv) given by the caller,
 * because u and v may have very different metric sizes on the surface; snap_tol is a distance
 * in that plane. Points (u,v) in the output are unscaled. */
#ifndef CB_ARRANGE_H
#define CB_ARRANGE_H

#include "brep/status.h"

/* An input polyline. */
typedef struct {
    int n;            /* points, >= 2 */
    const double *uv; /* 2 n coordinates u0 v0 u1 v1 ...; a closed one repeats its first point */
    int id;           /* the caller's, copied into the pieces' src_id */
} cb_arr_polyline;

/* A piece: a run of one or more input polylines (more when they run along each other within
 * snap_tol) between two vertices, with no vertex inside. A position along a polyline is a
 * segment index plus a fraction: 3.25 is a quarter into segment 3 (points 3 to 4). */
typedef struct {
    int v0, v1;          /* end vertices; equal for a closed piece */
    int n;               /* points, >= 2 */
    double *uv;          /* 2 n coordinates from v0 to v1; the ends are the vertices' points */
    int n_src;           /* polylines it lies on, >= 1 */
    int *src;            /* their indices in the input, increasing (a polyline that folds back
                            on itself appears once per pass) */
    int *src_id;         /* their ids */
    double *pos0, *pos1; /* per source: the position of v0 and of v1 along it. The piece runs
                            the way positions grow along src[0] (pos0[0] <= pos1[0]); along the
                            others they may decrease */
    int dangling;        /* on no cycle (a tree hanging off, a cut ending inside a region, a
                            bridge between loops): in no region */
} cb_arr_piece;

/* A piece walked along (dir = +1, v0 to v1) or against (-1) its direction. */
typedef struct {
    int piece, dir;
} cb_arr_use;

/* A bounded region. Regions inside a hole of another (islands) are regions of their own. */
typedef struct {
    int n_cycles;     /* >= 1: the outer cycle (counterclockwise), then the holes (clockwise) */
    const int *cycle; /* n_cycles + 1 offsets: cycle k is use[cycle[k] .. cycle[k + 1]) */
    const cb_arr_use *use; /* the pieces, end to end, region on the left */
    double area;           /* signed (u,v) area: the outer cycle's minus the holes' */
    double inner[2];       /* a point (u,v) strictly inside */
    double clearance;      /* its scaled distance from the region's boundary */
} cb_arr_region;

typedef struct {
    int n_vertices;
    double *vertex_uv; /* 2 n_vertices */
    int n_pieces;
    cb_arr_piece *piece;
    int n_regions;
    cb_arr_region *region;
    int *cycle_pool; /* the storage behind the regions' cycle and use */
    cb_arr_use *use_pool;
} cb_arr;

/* Span cap of merged points, in snap_tol (see cb_arr_build). */
#define CB_ARR_CLUSTER_SPAN 4.0

void cb_arr_init(cb_arr *a);
void cb_arr_clear(cb_arr *a);

/* The arrangement of the n polylines in[] (n >= 0) in the plane, into out (initialised; its old
 * contents are released).
 *
 * Snapping, all distances scaled and "near" meaning within snap_tol > 0:
 * - every point of a polyline near a segment of another polyline (or of a part of its own
 *   that is not adjacent) is joined to that segment: to the segment's end point when near it,
 *   else to its projection on the segment, which splits the segment there;
 * - segments that cross split each other at the crossing;
 * - points near each other become one vertex, shortest distances first, so long as the points
 *   merged into one vertex span at most CB_ARR_CLUSTER_SPAN snap_tol (bounding box diagonal):
 *   this stops chains of close points (densely sampled curves along each other) collapsing;
 * - the edges, straight between their vertices' points, are then split at the vertices near
 *   their insides and at their crossings until none is left: merging moves points, and the
 *   span cap may leave a vertex on an edge it was not joined to (as in iterated snap
 *   rounding). This changes nothing unless points closer than snap_tol spread further than
 *   the cap or merging moved a vertex onto or across an edge;
 * - runs of polylines between the same two vertices become one piece listing every source.
 * A vertex sits at the point of one of its polylines: not a free end of an open polyline where
 * possible, then the one of the lowest polyline index (pass the trimming loops first so that
 * cuts ending on them are moved onto them, not the reverse). A closed polyline's first point
 * is a vertex, positions along it restarting there. Positions of the ends of pieces are those
 * of the split points along the source (exact for projections and crossings); for a vertex
 * found on an edge after merging, the nearest point of the source's segment.
 *
 * Then pieces on no cycle are marked dangling and left out; each bounded face of what remains
 * is a region: its outer cycle, and as holes the outer boundaries of the components directly
 * inside it. The inner point of a region is the midpoint, among chords along lines v = const
 * through the region (the two widest on each of 16 lines, 256 when no chord midpoint is
 * farther than snap_tol from the boundary), of the one farthest from the boundary.
 *
 * Method: a uniform grid (about one cell per segment, cells at least snap_tol wide) finds the
 * near pairs and crossings; face walks of the planar graph, edges ordered by angle at each
 * vertex, give the faces, an edge being dangling when one walk runs along both of its sides.
 * O(N log N) for N segments of bounded length; a segment spanning the domain costs its number
 * of cells.
 *
 * Errors: CB_ERR_INVALID naming the polyline and point for fewer than 2 points, a NULL uv, a
 * non-finite coordinate (or one that overflows once scaled), and for a scale or snap_tol that
 * is not positive and finite; CB_ERR_UNSUPPORTED beyond INT_MAX / 16 points; CB_ERR_NUMERIC
 * when edges still cross after the splitting rounds (a tangle of points closer than snap_tol);
 * CB_ERR_NOMEM. On failure out is left cleared.
 * Limitation: in such tangles a vertex may be up to a few snap_tol from the point its position
 * gives along a source, and faces of zero area may remain. */
cb_status cb_arr_build(cb_arr *out, const cb_arr_polyline *in, int n, const double scale[2],
                       double snap_tol, cb_error *err);

/* ---------------------------------------------------------------- internal ---------------- */

/* Between the two stages of cb_arr_build (arrange.c snaps, arrange_face.c finds the faces):
 * the run of polyline poly from position pos0 at node n0 to pos1 at node n1, straight between
 * the nodes' points. Runs come ordered by polyline then position, consecutive runs of one
 * polyline meeting at a node. */
typedef struct {
    int poly, n0, n1;
    double pos0, pos1;
} _cb_arr_run;

/* Fills out from the nodes (scaled and (u,v) points) and runs, as cb_arr_build. */
cb_status _cb_arr_faces(cb_arr *out, const cb_arr_polyline *in, int n_nodes, const double *node_xy,
                        const double *node_uv, int n_run, const _cb_arr_run *run,
                        const double scale[2], double snap_tol, cb_error *err);

#endif
