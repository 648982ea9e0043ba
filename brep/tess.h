/* tess.h — watertight triangle meshes of B-rep bodies.
 *
 * Method. Every edge is sampled once (cb_tess_edges_sample) by chordal and angular tolerance;
 * the faces on both sides use the same samples, so neighbouring faces meet vertex for vertex
 * and the mesh is closed by construction, not by welding. Each face is then triangulated in
 * its parameter domain (cb_tess_face): the edge samples are placed in (u, v) through the
 * coedges' pcurves (refined by point inversion on the surface), the loops become the
 * constrained edges of a constrained Delaunay triangulation (exact orientation predicates) in
 * a per-face scaled metric (u and v weighted by the mean |S_u| and |S_v| on the boundary, so
 * that parameter lengths approximate 3D lengths), and triangles are split at their centroid
 * until the surface lies within the chordal tolerance of every triangle (the surface points at
 * the (u, v) centroid and at the (u, v) midpoints of its inner sides, measured to the triangle
 * and to those sides: their distance, not their drift along the mesh where the
 * parameterisation runs unevenly) and the surface normals near its corners (sampled a little
 * inside it, so that a corner on a C0 knot line sees the span the triangle covers) and at its
 * centroid lie within the angular tolerance of its normal. A triangle side joining two samples
 * of one edge that are not neighbours along it, or two vertices that an edge of other faces
 * joins, is split at its midpoint, whatever the tolerances: another face could have the same
 * segment, which would then border four triangles (two faces hugging a curved edge from its
 * concave side; three faces around a short edge of two). Boundary samples are never moved or
 * added to, so refinement cannot break watertightness.
 *
 * Special places. A seam edge (used twice by one face) has its samples on both sides of the
 * (u, v) domain, mapped to the same 3D vertices. A vertex a face's loops visit twice at one
 * place (a pinch: a hole touching the outer boundary or another hole) is one point of the
 * triangulation: its (u, v) from two pcurves may differ by round-off, and copies closer than
 * the body's tolerance are unified. A pole or apex (a collapsed edge, or a jump of
 * a loop along a line of the surface that collapses to one point) is one 3D vertex: the
 * triangles that would join two of its (u, v) copies are dropped. A loop may close along such
 * a line, and a coedge that starts on it where the previous one ended keeps its pcurve's place
 * (the two seam coedges of a sphere face leave the pole at u = 2 pi and return at u = 0), as
 * does a boundary sample at the pole (its inversion may slide along the line). The pole line
 * gets copies of the pole, one per angle_tol of the turn it spans, so the triangles near the
 * pole corner there; and after refinement a triangle whose pole corner lies, along the line,
 * beyond both its other corners (in space it turns back round the pole and folds over its
 * neighbours: thin triangles along a cone's seam near the apex) is flipped out of the pole's
 * fan. Triangles are oriented
 * counter-clockwise in (u, v) when the face's same_sense is 1 (normal S_u x S_v), clockwise
 * otherwise, so a correctly oriented closed shell gives an outward mesh.
 *
 * Contacts. Where a body touches itself without crossing (a void touching the outer wall at a
 * point or along a curve), each surface keeps to its side, but a chord of one, within the
 * chordal tolerance of its surface, can reach past the other surface and cross its mesh.
 * After the faces are meshed, the pairs of triangles of two faces that cross
 * (cb_mesh_check_crossings at the body's tolerance) are found. A triangle of such a pair
 * whose chord lies past the other face's surface where its own surface does not (tested at
 * its centroid, the midpoints of its sides and the feet on it of the other triangle's
 * corners), or, where the two surfaces lie within the body's tolerance of each other,
 * leaves its surface by more than that, gets a zone: its face and that face's edges are
 * meshed again there to a quarter of the chordal tolerance, no finer than the body's
 * tolerance (the zone is round the triangle, or round the one it crosses when that is
 * far smaller). Up to 8 rounds, each a quarter finer, while triangles cross and the mesh
 * stays within 16 times its first size. Crossings that remain, and those of a body that
 * really crosses itself, which no refinement removes, are left for the mesh checks to
 * report. Measured on the randomized corpus (bench/README.md): voids touching a sphere
 * at a point all mesh without crossing; of those touching a cylinder along a circle, a
 * few still cross where the circle's ends meet both faces.
 *
 * Crossing chords. A curved edge sampled to the chordal tolerance can pass nearer to another
 * edge or vertex of its face than its chords' sag; its chords then cross that edge's in
 * (u, v), and no triangulation holds both. The face reports where, and cb_tess_body samples
 * that face's edges more finely there (a zone as long as the longer chord, the chordal
 * tolerance quartered each round, up to 4 rounds while the sampling changes) and meshes the
 * faces again. Loops that really touch or cross, which no sampling separates, fail naming
 * the face and the point.
 *
 * Shared sides. Two faces meeting at a thin wedge (surfaces crossing at a small angle) both
 * see a bend of their common edges from its convex side, and the triangles of both may cut
 * across it by the same segment between two shared samples: an edge of four triangles in the
 * body's mesh. cb_tess_body finds such segments once the faces are meshed and meshes the
 * faces using them again with those segments split (up to 3 rounds).
 *
 * Refinement stops short of the tolerances in two places, where no insertion could help: a
 * flat triangle on a boundary side (its error is the boundary samples'), and, for the normal
 * test only, triangles narrower (smallest height) than twice the chordal tolerance (a C0
 * crease of a B-spline would be chased forever, and a sliver along a curved line of the
 * surface has that line's plane for its normal, whatever the surface's).
 *
 * Limits. A loop that wraps around a periodic surface without a seam edge (a cylinder band
 * bounded by two circles only) and a face without loops are refused with CB_ERR_UNSUPPORTED
 * naming the face: brep/prim.h cuts such faces along seams, and the STEP reader gives a whole
 * sphere or torus written without edges, and band faces, their seams (cb_topo_close_faces).
 * Coedges without a pcurve are placed by inverting their samples on the surface, each
 * from the previous one, which is right for surfaces without periods; but edge sampling then
 * cannot see the faces' surfaces, so compute pcurves first (cb_topo_compute_pcurves: the
 * hummingbird needs it; STEP import does it).
 *
 * Needles, and how they were cured. Refinement at the centroid cannot shrink the triangles at a
 * corner or against a boundary segment; where a test fails there whatever is inserted, each
 * pass adds a point a third of the way closer, and the triangles left form a fan of needles
 * (area / longest side^2 down to 1e-12) that CGAL may find crossing (linkrods.step at 0.3x
 * and 0.1x the default chord, the hummingbird at 0.5x and 0.3x; trj5_k1-al-214.stp had fans
 * at every tolerance, short of crossing). Three such tests were found and are corrected
 * above: the chordal error was the distance to
 * the side's or triangle's linearly mapped point, so uneven speed along a long boundary segment
 * failed every inner side beside it; corner normals were taken at the corner, where a C0 knot
 * line meeting the boundary gives the span beyond it (90 degrees off on trj5); and the normal
 * test exempted short triangles only, not the slivers it had made. Since then the shipped
 * models mesh closed, manifold and free of self-intersections from 3x down to 0.05x the
 * default chord, no triangle below 2e-4 of that shape ratio (those join boundary samples of
 * narrow faces, which refinement may not move). The metric is still one scaling per face: a
 * test that could again not be met near a boundary vertex would again make a fan, bounded by
 * the pass limit. */
#ifndef CB_TESS_H
#define CB_TESS_H

#include "brep/context.h"
#include "brep/mesh.h"
#include "brep/topo.h"

/* Default chordal tolerance: this fraction of the diagonal of the body's edge box. */
#define CB_TESS_REL_CHORD 1e-3
/* Default angular tolerance, radians (20 degrees). */
#define CB_TESS_ANGLE 0.3490658503988659

typedef struct {
    double chord_tol; /* largest distance between surface and mesh, model units; <= 0: the
                         relative default CB_TESS_REL_CHORD */
    double angle_tol; /* largest angle between surface and triangle normals, and between edge
                         tangents at consecutive samples, radians in (0, pi/2]; <= 0:
                         CB_TESS_ANGLE */
    double max_edge;  /* longest triangle side, model units; 0: no limit */
} cb_tess_opts;

/* chord_tol = 0, angle_tol = 0 (the defaults), max_edge = 0. */
void cb_tess_opts_init(cb_tess_opts *o);

/* The options with the defaults filled in for body b (chord_tol from its edge box).
 * CB_ERR_INVALID, naming the field, for a NaN or infinite value, angle_tol > pi/2, a negative
 * max_edge, or a body whose edge box is empty or infinite when the default is needed. */
cb_status cb_tess_opts_resolve(cb_tess_opts *out, const cb_tess_opts *o, const cb_topo_body *b,
                               cb_error *err);

/* The samples of every edge of a body, shared by the faces that use the edge. Points 0 ..
 * n_vertices - 1 are the body's vertices (same index), the interior samples of the edges
 * follow. Edge e's samples, in increasing curve parameter, are ids[start[e] .. start[e + 1])
 * at parameters t[...] (its first and last are the vertices at the curve's ends; a collapsed
 * edge, a pole or an apex, has its two end samples only, both its vertex). */
typedef struct {
    int n_points;
    double *xyz; /* 3 per point */
    int n_edges;
    int *start; /* n_edges + 1 */
    int *ids;
    double *t;
} cb_tess_edges;

void cb_tess_edges_init(cb_tess_edges *es);
void cb_tess_edges_clear(cb_tess_edges *es);

/* Samples every edge of b by the resolved options o: a piece of curve is halved until its
 * chord lies within chord_tol of the curve (at its midpoint and quarter points), the tangents
 * at its ends differ by at most angle_tol, it is no longer than max_edge, and, on each face
 * using the edge through a pcurve, the surface image of the straight (u, v) segment between
 * its ends stays within chord_tol of the chord and the surface normals at its ends differ by
 * at most angle_tol (pieces longer than 2 chord_tol only); closed edges start from three
 * pieces, edges joining the same two vertices as another edge from two (so that their meshes
 * do not share a segment). Needs cb_topo_body_index. CB_ERR_INVALID from the surfaces, CB_ERR_CANCELLED,
 * CB_ERR_NOMEM. */
cb_status cb_tess_edges_sample(cb_tess_edges *es, const cb_topo_body *b, const cb_tess_opts *o,
                               cb_context *ctx, cb_error *err);

/* The triangles of one face. Vertex index i < es->n_points is the shared edge sample i; index
 * es->n_points + k is the face's own point k (xyz[3k ..]). */
typedef struct {
    int n_points;
    double *xyz;
    int n_tris;
    int *tri;
    int cap_points, cap_tris;
    /* After a failure because two chords of the face's boundary cross in (u, v) (a curved
     * edge sampled more coarsely than its distance to another edge or vertex of the face):
     * the point on the surface where they cross and the longer chord's length; cross_r = 0
     * after any other outcome. cb_tess_body samples the edges more finely there. */
    double cross_at[3], cross_r;
} cb_tess_face_mesh;

void cb_tess_face_mesh_init(cb_tess_face_mesh *fm);
void cb_tess_face_mesh_clear(cb_tess_face_mesh *fm);

/* Triangulates face `face` of b (see the method above) with the edge samples es made with the
 * same resolved options o; fm is replaced. Errors name the face: CB_ERR_UNSUPPORTED (see the
 * limits above), CB_ERR_NUMERIC when the loops do not close in (u, v) on the surface within
 * the body's tolerance or the triangulation fails, CB_ERR_CANCELLED, CB_ERR_NOMEM. */
cb_status cb_tess_face(cb_tess_face_mesh *fm, const cb_topo_body *b, int face,
                       const cb_tess_edges *es, const cb_tess_opts *o, cb_context *ctx,
                       cb_error *err);

/* Tessellates every face of b into out (replaced): edge samples, then the faces in parallel
 * (cb_parallel_for, ctx's thread count), assembled in face order, then the contacts refined
 * (see Contacts above), so the result is the same, bit for bit, for any number of threads. Vertices: the edge samples used by some triangle, in
 * sample order, then each face's own points, face by face. o NULL: the defaults. Progress
 * (stage "tessellate") after each face; cancellation is checked between faces and refinement
 * passes (CB_ERR_CANCELLED, out empty). Needs cb_topo_body_index. Errors as cb_tess_face
 * and cb_tess_opts_resolve; out is empty on failure. */
cb_status cb_tess_body(cb_mesh_t out, const cb_topo_body *b, const cb_tess_opts *o,
                       cb_context *ctx, cb_error *err);

#endif
